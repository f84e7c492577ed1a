/* Per-stage benchmark of the whole pipeline (DESIGN 6, issue 3 part 5): WLOP,
 * normals, sinking, meso-skeleton and surface consolidation, each run on the
 * OpenCL backend and on the scalar reference over the SAME input in one run,
 * printed as JSON lines. Inputs are noisy virtual scans of built-in shapes at
 * the paper's Table 1 sizes (|C| -> |S|, |S| from 2K to 67K) and the statue
 * scan of the paper's Fig. 12 (bottom) when the shared data folder has it.
 *
 *   bench_stages [--sizes C:S[:shape],...|none] [--stages wlop,normals,sink,skeleton,surface,total]
 *                [--ref-max N] [--ref-uncapped] [--quick] [--table1] [--no-statue] [--no-warm-up]
 *                [--no-neighbours] [--no-peak] [--device D] [--data DIR] [--threads N]
 *
 * --table1 runs every row of the paper's Table 1 (22K -> 2K up to 484K ->
 * 47K): the two scans the shared data folder holds (the statue, Fig. 12 B,
 * and the loops, Fig. 10 T), the other rows as scans of built-in shapes;
 * every line of a row carries the paper's time (T_w on WLOP's, T_d on the
 * deep stages' and T_w + T_d on the total). A data row whose file is absent
 * is skipped with a message and a "skipped" line.
 *
 * Every stage's reference run starts from the OpenCL run's input of that stage
 * (WLOP from C; sinking from the OpenCL WLOP samples with their normals; the
 * skeleton from the OpenCL anchors; the surface from the OpenCL skeleton), so
 * the two lines of a stage time the same work on the same data, and
 * "mean_diff_r" (mean distance between the two outputs, in r) shows they
 * computed the same thing. The OpenCL run uses the default parameters and
 * convergence tests; the reference then runs exactly the OpenCL run's
 * iteration count, with its convergence test off ("iters_capped_to_cl": true,
 * "iteration_cap"): rounding differences can make the two stop tests fire
 * iterations apart, and equal work makes the seconds comparable. With
 * --ref-uncapped the reference runs to its own convergence instead. Sinking
 * stops early anyway once every point has settled. Normals and r (paper Eq. 1) run on the host with either
 * backend (FLANN kNN): their lines time the same code twice.
 * "seconds" is the wall time of the public call, measured here around it.
 * The reference is skipped (a line with "skipped") above --ref-max samples.
 * OpenCL lines also give the bytes moved host -> device and device -> host
 * (whole stage and per iteration) and the bytes not uploaded because the
 * device buffer already held them, and each is followed by one
 * {"what":"operator"} line per kernel the stage launched: launches, seconds,
 * candidate pairs and their rate, bytes each way.
 *
 * True neighbours: every operator's pairs within its radius (the skeleton's
 * weighted sums: inside its ellipsoid) are counted on the host before each
 * launch (backend/neighbours.h), and stage and operator lines give them and
 * their rate beside the candidates': a finer grid lowers the candidates and
 * their rate for the same work, the neighbours stay. The count's own time is
 * taken out of the stage's "seconds" ("neighbour_count_seconds" says how much)
 * and never enters an operator's, which dp_cl_launch measures;
 * --no-neighbours turns it off. After each OpenCL operator line the peak
 * kernel (kernels/peak.cl, bench_peak) runs on that operator's point counts
 * and mean radius, over the stage's clouds of those sizes, on a grid of cells
 * as large as the radius as the operators scan: "peak_pair_evals_per_s" and
 * "peak_neighbour_pairs_per_s" are the ceiling, "of_peak_neighbour" the
 * operator's share of it (--no-peak skips it).
 */
#include "peak_timing.h"

#include "dpoints_tools.h"
#include "backend/context.h"
#include "backend/neighbours.h"
#include "core/common.h"
#include "knn/knn.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Table 1 rows covering |S| = 2K ... 67K, with the smallest and largest |S|
 * (Fig. 1 and Fig. 13 B). Each gets a different built-in shape: the paper's
 * inputs differ in shape too, and the knot (tubes) and the chair (flat parts,
 * thin legs) exercise curve and sheet skeletons. */
#define DEFAULT_SIZES "84772:2143:chair,22148:5234:knot,24292:13812:torus,40509:40509:chair,67131:67131:knot"
/* --quick: one small input, no statue: a smoke run of seconds. */
#define QUICK_SIZES "22148:2143:knot"
/* No limit: on the 2-core PoCL machine the reference took only 1-3x the
 * kernels' time per input (the whole default run, both backends, about 8
 * minutes), and the largest inputs are where the two differ most. On a fast
 * device, --ref-max keeps the reference to the small inputs. */
#define DEFAULT_REF_MAX 0
/* --table1: the rows no scan in the shared data folder covers, as scans of
 * built-in shapes (tubes, sheets and thin legs, loops), up to the largest,
 * the knot of the timings. */
#define TABLE1_SIZES                                                                                  \
	"84772:2143:chair,58710:6870:torus,22148:5234:knot,78630:6727:chair,24292:13812:torus,"       \
	"40509:40509:chair,67131:67131:knot,175312:19721:torus,300283:57791:chair,292910:32142:rods," \
	"483583:47083:knot"
#define MAX_SIZES 16
/* Scanner: a ring of views around the vertical axis, as in the paper's real
 * scans, so the underside is missed (missing data for sinking and surface
 * completion to work on); Gaussian noise of 0.2% of the bounding-box
 * diagonal per coordinate. */
#define SCAN_VIEWS 4
#define SCAN_NOISE 0.002
#define SCAN_SEED 11
/* The ray grid is sized from a probe scan: enough rays for this many times
 * |C| hits, then |C| of them are kept at random. */
#define PROBE_RES 64
#define RES_MARGIN 1.15
#define RES_GROWTH 1.2
#define RES_TRIES 4
#define SUBSET_SEED 5
/* PoCL compiles each kernel for the device at its first launch (seconds per
 * kernel unless its cache already holds it); a small unprinted OpenCL run of
 * the whole chain first keeps that out of the first input's times. */
#define WARM_UP_SIZE 3000
#define WARM_UP_SAMPLES 500
#define WARM_UP_SHAPE "knot"

/* The real scans of Table 1 rows in the shared data folder; the statue runs
 * by default, all with --table1. */
typedef struct data_input {
	const char *file, *name;
	size_t samples;
} data_input;

static const data_input data_inputs[] = {
	{"paper/statue-fig12b-raw.xyz", "statue-fig12b", 7252},
	{"paper/loops-fig10t-raw.ply", "loops-fig10t", 3996},
};

typedef enum stage_id { ST_WLOP, ST_NORMALS, ST_SINK, ST_SKELETON, ST_SURFACE, ST_COUNT } stage_id;
static const char *stage_names[ST_COUNT] = {"wlop", "normals", "sink", "skeleton", "surface"};

/* The paper's Table 1: |C|, |S|, T_w (WLOP) and T_d (deep points) in seconds
 * on a 6-core i7-5930K, to print beside our times for the same sizes. */
typedef struct paper_row {
	size_t c, s;
	double tw, td;
} paper_row;

static const paper_row paper_table[] = {
	{84772, 2143, 3.1, 26.3},     {58710, 6870, 4.8, 41.2},      {22148, 5234, 2.7, 30.5},
	{43545, 3996, 4.1, 83.9},     {78630, 6727, 8.4, 87.3},      {24292, 13812, 3.2, 112.9},
	{32614, 7252, 5.5, 61.5},     {40509, 40509, 10.5, 259.6},   {67131, 67131, 18.9, 408.8},
	{175312, 19721, 17.8, 197.3}, {300283, 57791, 47.3, 449.9}, {292910, 32142, 30.3, 355.3},
	{483583, 47083, 134.9, 723.7},
};

static const paper_row *paper_lookup(size_t c, size_t s)
{
	for (size_t i = 0; i < sizeof paper_table / sizeof paper_table[0]; i++)
		if (paper_table[i].c == c && paper_table[i].s == s)
			return &paper_table[i];
	return NULL;
}

typedef struct options {
	size_t sizes[MAX_SIZES], samples[MAX_SIZES];
	char shapes[MAX_SIZES][16];
	int nsizes;
	int stages[ST_COUNT];
	int total;
	size_t ref_max; /* 0 = no limit */
	int ref_uncapped;
	int statue;
	int table1;
	int warm_up;
	int neighbours, peak;
	const char *device;
	const char *data;
	int threads; /* host threads of both contexts; 0 = the CPUs */
} options;

/* "none": the statue only. */
static int parse_sizes(const char *text, options *o)
{
	o->nsizes = 0;
	if (!strcmp(text, "none"))
		return 0;
	while (*text) {
		char *end;
		unsigned long long n = strtoull(text, &end, 10);
		if (*end != ':' || o->nsizes == MAX_SIZES)
			return -1;
		unsigned long long m = strtoull(end + 1, &end, 10);
		if (n == 0 || m == 0 || m > n)
			return -1;
		const char *shape = "knot";
		size_t len = strlen(shape);
		if (*end == ':') {
			shape = end + 1;
			len = strcspn(shape, ",");
			end = (char *)shape + len;
		}
		if (len == 0 || len >= sizeof o->shapes[0] || (*end && *end != ','))
			return -1;
		memcpy(o->shapes[o->nsizes], shape, len);
		o->shapes[o->nsizes][len] = '\0';
		o->sizes[o->nsizes] = (size_t)n;
		o->samples[o->nsizes++] = (size_t)m;
		text = *end ? end + 1 : end;
	}
	return o->nsizes ? 0 : -1;
}

static int parse_stages(const char *text, options *o)
{
	memset(o->stages, 0, sizeof o->stages);
	o->total = 0;
	while (*text) {
		size_t len = strcspn(text, ",");
		int found = 0;
		for (int s = 0; s < ST_COUNT; s++)
			if (strlen(stage_names[s]) == len && !strncmp(text, stage_names[s], len))
				o->stages[s] = found = 1;
		if (len == strlen("total") && !strncmp(text, "total", len))
			o->total = found = 1;
		if (!found)
			return -1;
		text += len + (text[len] == ',');
	}
	for (int s = 0; s < ST_COUNT; s++)
		if (o->stages[s])
			return 0;
	return o->total ? 0 : -1;
}

static int parse_options(int argc, char **argv, options *o)
{
	memset(o, 0, sizeof *o);
	o->ref_max = DEFAULT_REF_MAX;
	o->statue = 1;
	o->warm_up = 1;
	o->neighbours = 1;
	o->peak = 1;
	o->data = getenv("DP_DATA_DIR") ? getenv("DP_DATA_DIR") : "../shared/data";
	parse_sizes(DEFAULT_SIZES, o);
	parse_stages("wlop,normals,sink,skeleton,surface,total", o);
	for (int a = 1; a < argc; a++) {
		const char *arg = argv[a], *val = a + 1 < argc ? argv[a + 1] : NULL;
		if (!strcmp(arg, "--quick")) {
			parse_sizes(QUICK_SIZES, o);
			o->statue = 0;
			continue;
		}
		if (!strcmp(arg, "--no-statue")) {
			o->statue = 0;
			continue;
		}
		if (!strcmp(arg, "--table1")) {
			parse_sizes(TABLE1_SIZES, o);
			o->table1 = 1;
			continue;
		}
		if (!strcmp(arg, "--no-neighbours")) {
			o->neighbours = 0;
			continue;
		}
		if (!strcmp(arg, "--no-peak")) {
			o->peak = 0;
			continue;
		}
		if (!strcmp(arg, "--ref-uncapped")) {
			o->ref_uncapped = 1;
			continue;
		}
		if (!strcmp(arg, "--no-warm-up")) {
			o->warm_up = 0;
			continue;
		}
		if (!val)
			return -1;
		if (!strcmp(arg, "--sizes")) {
			if (parse_sizes(val, o))
				return -1;
		} else if (!strcmp(arg, "--stages")) {
			if (parse_stages(val, o))
				return -1;
		} else if (!strcmp(arg, "--ref-max")) {
			char *end;
			o->ref_max = (size_t)strtoull(val, &end, 10);
			if (*end)
				return -1;
		} else if (!strcmp(arg, "--device")) {
			o->device = val;
		} else if (!strcmp(arg, "--threads")) {
			char *end;
			long t = strtol(val, &end, 10);
			if (end == val || *end || t < 0 || t > 1000)
				return -1;
			o->threads = (int)t;
		} else if (!strcmp(arg, "--data")) {
			o->data = val;
		} else {
			return -1;
		}
		a++;
	}
	return 0;
}

/* ------------------------------------------------------------------ inputs */

/* Keeps n of the scan's points, chosen at random in their scan order
 * (selection sampling: each kept with probability needed / remaining). */
static dp_status keep_subset(const dp_cloud *scan, size_t n, dp_cloud *out, dp_error *err)
{
	dp_status st = dp_cloud_alloc(out, n, 0, err);
	if (st != DP_OK)
		return st;
	dp_rng rng;
	dp_rng_seed(&rng, SUBSET_SEED);
	size_t kept = 0;
	for (size_t i = 0; i < scan->n && kept < n; i++) {
		if (dp_rng_uniform(&rng) * (double)(scan->n - i) >= (double)(n - kept))
			continue;
		out->x[kept] = scan->x[i];
		out->y[kept] = scan->y[i];
		out->z[kept] = scan->z[i];
		kept++;
	}
	return DP_OK;
}

/* A noisy ring scan of the named shape with exactly n points. */
static dp_status make_scan(const char *shape_name, size_t n, dp_cloud *out, dp_error *err)
{
	dp_shape shape;
	dp_cloud mesh = {0}, scan = {0};
	dp_status st = dp_shape_default(shape_name, &shape, err);
	if (st == DP_OK)
		st = dp_shape_mesh(&shape, &mesh, err);
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = SCAN_VIEWS;
	sp.noise = SCAN_NOISE;
	sp.seed = SCAN_SEED;
	sp.normals = 0;
	sp.res = PROBE_RES;
	if (st == DP_OK)
		st = dp_scan(&mesh, &sp, &scan, NULL, err);
	if (st != DP_OK)
		goto done;
	double hits_per_ray = (double)scan.n / ((double)sp.views * PROBE_RES * PROBE_RES);
	double res = sqrt(RES_MARGIN * (double)n / (sp.views * hits_per_ray));
	for (int t = 0; t < RES_TRIES && scan.n < n; t++, res *= RES_GROWTH) {
		dp_cloud_free(&scan);
		sp.res = (int)ceil(res);
		if ((st = dp_scan(&mesh, &sp, &scan, NULL, err)) != DP_OK)
			goto done;
	}
	if (scan.n < n)
		st = dp_fail(err, DP_ERR_ARG, "bench_stages: a %d x %d scan of %s gives %zu < %zu points", sp.res,
			     sp.res, shape_name, scan.n, n);
	else
		st = keep_subset(&scan, n, out, err);
done:
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
	return st;
}

/* ----------------------------------------------------------------- results */

typedef struct input_case {
	const char *name;
	size_t size, samples;
	const paper_row *paper;
	int warm_up; /* OpenCL chain only, nothing printed */
} input_case;

/* One stage run on one backend. */
typedef struct run_result {
	double seconds, pairs;
	int iterations; /* -1: not iterative (normals) */
	int converged;  /* sinking: every point settled; -1: no test ran (normals, capped runs) */
	double seconds_spacing;
	int sink;       /* the three counts below are set */
	size_t settled_front, settled_slow, unsettled;
	int moved; /* the byte counts below are set (OpenCL runs) */
	double h2d, d2h, h2d_skipped;
	int counted; /* the neighbour fields below are set */
	double neighbours, count_seconds;
} run_result;

/* The OpenCL context's transfer and per-kernel counters at one moment. */
typedef struct cl_counters {
	double h2d, d2h, skipped;
	size_t nkernels;
	dp_cl_kernel_stats k[DP_CL_MAX_KERNELS];
	char names[DP_CL_MAX_KERNELS][64];
} cl_counters;

static void cl_counters_take(const dp_context *ctx, cl_counters *c)
{
	c->h2d = ctx->cl.h2d_bytes;
	c->d2h = ctx->cl.d2h_bytes;
	c->skipped = ctx->cl.h2d_skipped_bytes;
	c->nkernels = ctx->cl.nkernels;
	for (size_t i = 0; i < c->nkernels; i++) {
		c->k[i] = ctx->cl.kernels[i].stats;
		memcpy(c->names[i], ctx->cl.kernels[i].name, sizeof c->names[i]);
	}
}

static void print_head(const input_case *in, const char *stage, const char *backend)
{
	printf("{\"what\":\"stage\",\"stage\":\"%s\",\"input\":\"%s\",\"size\":%zu,\"samples\":%zu,\"backend\":\"%s\"",
	       stage, in->name, in->size, in->samples, backend);
}

static void print_skip(const input_case *in, const char *stage, const char *backend, const char *why)
{
	print_head(in, stage, backend);
	printf(",\"skipped\":\"%s\"}\n", why);
	fflush(stdout);
}

/* The common fields; the caller adds its own and closes the line. */
static void print_run(const input_case *in, const char *stage, dp_context *ctx, const run_result *r)
{
	const char *backend = dp_context_backend(ctx) == DP_BACKEND_CL ? "cl" : "ref";
	double load[1] = {-1.0};
	if (getloadavg(load, 1) < 1)
		load[0] = -1.0;
	print_head(in, stage, backend);
	printf(",\"device\":\"%s\",\"host_threads\":%d,\"seconds\":%.4f", dp_context_device_name(ctx),
	       dp_context_threads(ctx), r->seconds);
	if (r->iterations >= 0)
		printf(",\"iterations\":%d,\"pair_evaluations\":%.6g,\"pair_evals_per_s\":%.4g", r->iterations,
		       r->pairs, r->seconds > 0 ? r->pairs / r->seconds : 0.0);
	else
		printf(",\"iterations\":null,\"pair_evaluations\":null,\"pair_evals_per_s\":null");
	if (r->converged >= 0)
		printf(",\"converged\":%s", r->converged ? "true" : "false");
	if (r->sink)
		printf(",\"settled_front\":%zu,\"settled_slow\":%zu,\"unsettled\":%zu", r->settled_front,
		       r->settled_slow, r->unsettled);
	if (r->moved) {
		double it = r->iterations > 0 ? r->iterations : 1;
		printf(",\"h2d_bytes\":%.0f,\"d2h_bytes\":%.0f,\"h2d_bytes_per_iter\":%.0f,\"d2h_bytes_per_iter\":%.0f,"
		       "\"h2d_skipped_bytes\":%.0f",
		       r->h2d, r->d2h, r->h2d / it, r->d2h / it, r->h2d_skipped);
	}
	if (r->counted)
		printf(",\"neighbour_pairs\":%.6g,\"neighbour_pairs_per_s\":%.4g,\"neighbour_count_seconds\":%.4f",
		       r->neighbours, r->seconds > 0 ? r->neighbours / r->seconds : 0.0, r->count_seconds);
	printf(",\"loadavg_1m\":%.2f", load[0]);
}

/* What the peak runs on beside a stage's operators: the OpenCL context and
 * the stage's clouds (output first, then inputs, then C); `data_of` names,
 * for the operators whose grid is not over the first cloud of its size, the
 * cloud it is over. */
typedef struct peak_setting {
	dp_context *ctx;
	const dp_cloud *clouds[4];
	int nclouds;
	const dp_cloud *skeleton_anchors, *surface_skeleton;
	int run;
} peak_setting;

/* The first n points of the first cloud with n or more (sinking's operators
 * query the points not yet settled, a subset). */
static int cloud_of_size(const peak_setting *pk, size_t n, const dp_cloud *prefer, dp_cloud *view)
{
	const dp_cloud *c = prefer && prefer->n >= n ? prefer : NULL;
	for (int i = 0; i < pk->nclouds && !c; i++)
		if (pk->clouds[i]->n == n)
			c = pk->clouds[i];
	for (int i = 0; i < pk->nclouds && !c; i++)
		if (pk->clouds[i]->n >= n)
			c = pk->clouds[i];
	if (!c || n == 0)
		return 0;
	*view = *c;
	view->n = n;
	return 1;
}

/* The operator's true neighbours between two counts; its last launch's
 * sizes and its mean radius over those launches. */
static dp_neighbour_op neighbour_diff(const dp_neighbour_counts *before, const dp_neighbour_counts *after,
				      const char *name)
{
	dp_neighbour_op d = {0};
	for (size_t i = 0; i < after->nops; i++)
		if (!strcmp(after->ops[i].name, name))
			d = after->ops[i];
	for (size_t i = 0; i < before->nops; i++)
		if (!strcmp(before->ops[i].name, name)) {
			d.launches -= before->ops[i].launches;
			d.pairs -= before->ops[i].pairs;
			d.radius_sum -= before->ops[i].radius_sum;
			d.nq_sum -= before->ops[i].nq_sum;
		}
	return d;
}

/* The peak kernel on the operator's sizes and mean radius, printed as fields
 * of its line; nothing when no cloud of the stage has those sizes. */
static void print_peak(const peak_setting *pk, const dp_neighbour_op *op, double seconds, dp_error *err)
{
	int reattach = !strcmp(op->name, "surface_reattach");
	const dp_cloud *prefer = !strcmp(op->name, "skeleton_median") ? pk->skeleton_anchors
				 : reattach                           ? pk->surface_skeleton
								      : NULL;
	dp_cloud q_view, data_view;
	const dp_cloud *q = &q_view, *data = &data_view;
	size_t nq = op->launches > 0.0 ? (size_t)llround(op->nq_sum / op->launches) : 0;
	/* re-attachment queries the skeleton points over the skeleton's grid */
	if (!cloud_of_size(pk, nq, reattach ? prefer : NULL, &q_view) ||
	    !cloud_of_size(pk, op->ndata, prefer, &data_view)) {
		printf(",\"peak\":null");
		return;
	}
	float radius = (float)(op->radius_sum / op->launches);
	float *count = dp_alloc_array(q->n, sizeof(float)), *sum = dp_alloc_array(q->n, sizeof(float));
	peak_result p;
	if (!count || !sum || peak_measure(pk->ctx, data, q, radius, 1, count, sum, &p, err) != DP_OK) {
		fprintf(stderr, "bench_stages: peak beside %s: %s\n", op->name, count && sum ? err->message : "no memory");
		printf(",\"peak\":null");
	} else {
		double nb_rate = seconds > 0 ? op->pairs / seconds : 0.0;
		printf(",\"peak_radius\":%.6g,\"peak_queries\":%zu,\"peak_points\":%zu,\"peak_seconds_per_launch\":%.6f,\"peak_pair_evals_per_s\":%.4g,"
		       "\"peak_neighbour_pairs_per_s\":%.4g,\"of_peak_neighbour\":%.3f",
		       (double)radius, q->n, data->n, p.seconds, p.candidates / p.seconds, p.neighbours / p.seconds,
		       nb_rate / (p.neighbours / p.seconds));
	}
	free(count);
	free(sum);
}

/* One line per kernel launched between the two counters, with its true
 * neighbours (when counted) and the peak beside it (when pk->run). */
static void print_operators(const input_case *in, const char *stage, const cl_counters *before,
			    const cl_counters *after, const dp_neighbour_counts *nb_before,
			    const dp_neighbour_counts *nb_after, const peak_setting *pk)
{
	dp_error err = {0};
	for (size_t i = 0; i < after->nkernels; i++) {
		dp_cl_kernel_stats d = after->k[i];
		if (i < before->nkernels) {
			d.launches -= before->k[i].launches;
			d.seconds -= before->k[i].seconds;
			d.h2d_bytes -= before->k[i].h2d_bytes;
			d.d2h_bytes -= before->k[i].d2h_bytes;
			d.h2d_skipped_bytes -= before->k[i].h2d_skipped_bytes;
			d.pairs -= before->k[i].pairs;
		}
		if (d.launches <= 0.0)
			continue;
		printf("{\"what\":\"operator\",\"stage\":\"%s\",\"input\":\"%s\",\"kernel\":\"%s\",\"launches\":%.0f,"
		       "\"seconds\":%.4f,\"pair_evaluations\":%.6g,\"pair_evals_per_s\":%.4g,\"h2d_bytes\":%.0f,"
		       "\"d2h_bytes\":%.0f,\"h2d_bytes_per_launch\":%.0f,\"h2d_skipped_bytes\":%.0f",
		       stage, in->name, after->names[i], d.launches,
		       d.seconds, d.pairs, d.seconds > 0 ? d.pairs / d.seconds : 0.0, d.h2d_bytes, d.d2h_bytes,
		       d.h2d_bytes / d.launches, d.h2d_skipped_bytes);
		if (nb_before && nb_after) {
			dp_neighbour_op op = neighbour_diff(nb_before, nb_after, after->names[i]);
			if (op.launches > 0.0) {
				printf(",\"neighbour_pairs\":%.6g,\"neighbour_pairs_per_s\":%.4g,\"radius\":%.6g",
				       op.pairs, d.seconds > 0 ? op.pairs / d.seconds : 0.0, op.radius_sum / op.launches);
				if (pk->run)
					print_peak(pk, &op, d.seconds, &err);
			}
		}
		printf("}\n");
		fflush(stdout);
	}
}

/* Mean distance between corresponding points of two clouds of one order, in r. */
static double mean_diff(const dp_cloud *a, const dp_cloud *b, double r)
{
	if (a->n != b->n || a->n == 0)
		return NAN;
	double total = 0.0;
	for (size_t i = 0; i < a->n; i++) {
		double dx = a->x[i] - b->x[i], dy = a->y[i] - b->y[i], dz = a->z[i] - b->z[i];
		total += sqrt(dx * dx + dy * dy + dz * dz);
	}
	return total / (double)a->n / r;
}

/* Ends a reference line: how its iterations were chosen and how far its
 * output lies from the OpenCL one. */
static void print_ref_tail(int capped, int cap, double diff_r)
{
	if (capped)
		printf(",\"iters_capped_to_cl\":true,\"iteration_cap\":%d", cap);
	else
		printf(",\"iters_capped_to_cl\":false");
	if (isfinite(diff_r))
		printf(",\"mean_diff_r\":%.4g", diff_r);
	printf("}\n");
	fflush(stdout);
}

/* ------------------------------------------------------------------ stages */

/* cap > 0: exactly cap iterations, convergence test off (the reference
 * matched to the OpenCL run); cap == 0: the defaults. */

static dp_status run_wlop(dp_context *ctx, const dp_cloud *c, size_t m, int cap, dp_cloud *s, run_result *r,
			  dp_error *err)
{
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = m;
	if (cap) {
		p.max_iters = cap;
		p.tol = 0.0;
	}
	dp_wlop_stats st;
	double t0 = dp_seconds();
	dp_status rc = dp_wlop(ctx, c, &p, s, &st, err);
	r->seconds = dp_seconds() - t0;
	r->pairs = st.pair_evaluations;
	r->iterations = st.iterations;
	r->converged = cap ? -1 : st.converged;
	return rc;
}

/* Normals of a copy of S's positions, then r (paper Eq. 1), as the pipeline
 * does between WLOP and sinking. */
static dp_status run_normals(const dp_cloud *s, dp_cloud *out, double *spacing, run_result *r, dp_error *err)
{
	dp_status rc = dp_cloud_alloc(out, s->n, 0, err);
	if (rc != DP_OK)
		return rc;
	memcpy(out->x, s->x, s->n * sizeof(float));
	memcpy(out->y, s->y, s->n * sizeof(float));
	memcpy(out->z, s->z, s->n * sizeof(float));
	double t0 = dp_seconds();
	rc = dp_estimate_normals(out, NULL, err);
	double t1 = dp_seconds();
	if (rc == DP_OK)
		rc = dp_mean_spacing(out->n, out->x, out->y, out->z, spacing, err);
	double t2 = dp_seconds();
	r->seconds = t2 - t0;
	r->seconds_spacing = t2 - t1;
	r->pairs = 0.0;
	r->iterations = r->converged = -1;
	if (rc == DP_OK && !(*spacing > 0.0))
		rc = dp_fail(err, DP_ERR_EMPTY, "bench_stages: the %zu samples coincide: no spacing r", s->n);
	return rc;
}

static dp_status run_sink(dp_context *ctx, const dp_cloud *s, double r_unit, int cap, dp_cloud *h, run_result *r,
			  dp_error *err)
{
	dp_sink_params p;
	dp_sink_params_default(&p);
	if (cap)
		p.max_iters = cap;
	dp_sink_stats st;
	double t0 = dp_seconds();
	dp_status rc = dp_sink(ctx, s, r_unit, &p, h, NULL, &st, err);
	r->seconds = dp_seconds() - t0;
	r->pairs = st.pair_evaluations;
	r->iterations = st.iterations;
	r->converged = st.unsettled == 0;
	r->sink = 1;
	r->settled_front = st.settled_front;
	r->settled_slow = st.settled_slow;
	r->unsettled = st.unsettled;
	return rc;
}

static dp_status run_skeleton(dp_context *ctx, const dp_cloud *h, double r_unit, int cap, dp_cloud *q,
			      run_result *r, dp_error *err)
{
	dp_skeleton_params p;
	dp_skeleton_params_default(&p);
	if (cap) {
		/* A window longer than the run and no move threshold: exactly cap. */
		p.max_iters = cap;
		p.window = cap + 1;
		p.min_move_r = 0.0;
	}
	dp_skeleton_stats st;
	double t0 = dp_seconds();
	dp_status rc = dp_skeleton(ctx, h, r_unit, &p, q, &st, err);
	r->seconds = dp_seconds() - t0;
	r->pairs = st.pair_evaluations;
	r->iterations = st.iterations;
	r->converged = cap ? -1 : st.converged;
	return rc;
}

/* dp_surface updates the skeleton in place (re-attachment), so each backend
 * gets its own copy of Q; *eta is caller-allocated, |S| floats. */
static dp_status run_surface(dp_context *ctx, const dp_cloud *c, const dp_cloud *s, const dp_cloud *q,
			     double r_unit, int cap, dp_cloud *p_out, float *eta, run_result *r, dp_error *err)
{
	dp_surface_params p;
	dp_surface_params_default(&p);
	if (cap) {
		/* A window longer than the run: neither stop test fires, exactly cap. */
		p.max_iters = cap;
		p.window = cap + 1;
	}
	dp_cloud qc;
	dp_status rc = dp_cloud_copy(&qc, q, err);
	if (rc != DP_OK)
		return rc;
	dp_surface_stats st;
	double t0 = dp_seconds();
	rc = dp_surface(ctx, c, s, &qc, NULL, r_unit, &p, p_out, eta, &st, err);
	r->seconds = dp_seconds() - t0;
	r->pairs = st.pair_evaluations;
	r->iterations = st.iterations;
	r->converged = cap ? -1 : st.converged;
	dp_cloud_free(&qc);
	return rc;
}

/* ---------------------------------------------------------------- one input */

typedef struct bench {
	const options *o;
	dp_context *cl, *ref;
	dp_neighbour_counts *cl_nb, *ref_nb; /* the contexts' counts, NULL when off */
} bench;

/* The OpenCL run's data: the input, each stage's output (out[ST_WLOP] = S,
 * out[ST_NORMALS] = S with normals, out[ST_SINK] = H, out[ST_SKELETON] = Q,
 * out[ST_SURFACE] = P) and r. Both backends read their stage input here. */
typedef struct chain {
	const dp_cloud *c;
	size_t samples;
	dp_cloud out[ST_COUNT];
	double r;
	float *eta;
} chain;

/* The peak's clouds beside stage s: its input(s) and output. */
static void stage_clouds(const chain *ch, stage_id s, peak_setting *pk)
{
	pk->nclouds = 0;
	pk->clouds[pk->nclouds++] = &ch->out[s];
	if (s == ST_SINK)
		pk->clouds[pk->nclouds++] = &ch->out[ST_NORMALS];
	if (s == ST_SKELETON)
		pk->clouds[pk->nclouds++] = &ch->out[ST_SINK];
	if (s == ST_SURFACE) {
		pk->clouds[pk->nclouds++] = &ch->out[ST_NORMALS];
		pk->clouds[pk->nclouds++] = &ch->out[ST_SKELETON];
	}
	pk->clouds[pk->nclouds++] = ch->c;
	pk->skeleton_anchors = &ch->out[ST_SINK];
	pk->surface_skeleton = &ch->out[ST_SKELETON];
}

/* Takes the neighbour count's time out of a stage's wall time. */
static void take_count(run_result *r, const dp_neighbour_counts *before, const dp_neighbour_counts *after)
{
	if (!before || !after)
		return;
	r->counted = 1;
	r->neighbours = after->pairs - before->pairs;
	r->count_seconds = after->seconds - before->seconds;
	r->seconds -= r->count_seconds;
}

/* Stage s on ctx, from the OpenCL chain's input of that stage, into *out. */
static dp_status run_stage(dp_context *ctx, stage_id s, int cap, const chain *ch, dp_cloud *out, double *r_out,
			   run_result *res, dp_error *err)
{
	switch (s) {
	case ST_WLOP:
		return run_wlop(ctx, ch->c, ch->samples, cap, out, res, err);
	case ST_NORMALS:
		return run_normals(&ch->out[ST_WLOP], out, r_out, res, err);
	case ST_SINK:
		return run_sink(ctx, &ch->out[ST_NORMALS], ch->r, cap, out, res, err);
	case ST_SKELETON:
		return run_skeleton(ctx, &ch->out[ST_SINK], ch->r, cap, out, res, err);
	case ST_SURFACE:
		return run_surface(ctx, ch->c, &ch->out[ST_NORMALS], &ch->out[ST_SKELETON], ch->r, cap, out, ch->eta,
				   res, err);
	default:
		return dp_fail(err, DP_ERR_INTERNAL, "bench_stages: no stage %d", (int)s);
	}
}

static void print_totals(const bench *b, const input_case *in, const run_result *cl_runs,
			 const run_result *ref_runs, int ref_complete, const char *ref_why)
{
	for (int k = 0; k < 2; k++) {
		const run_result *runs = k ? ref_runs : cl_runs;
		if (k && !ref_complete) {
			print_skip(in, "total", "ref", ref_why);
			continue;
		}
		run_result t = {.converged = -1};
		for (int s = 0; s < ST_COUNT; s++) {
			t.seconds += runs[s].seconds;
			t.pairs += runs[s].pairs;
			t.iterations += runs[s].iterations > 0 ? runs[s].iterations : 0;
			t.counted |= runs[s].counted;
			t.neighbours += runs[s].neighbours;
			t.count_seconds += runs[s].count_seconds;
		}
		print_run(in, "total", k ? b->ref : b->cl, &t);
		if (in->paper)
			printf(",\"paper_seconds\":%.1f,\"paper_wlop_seconds\":%.1f,\"paper_deep_seconds\":%.1f",
			       in->paper->tw + in->paper->td, in->paper->tw, in->paper->td);
		printf(",\"deep_seconds\":%.4f", t.seconds - runs[ST_WLOP].seconds);
		if (k)
			printf(",\"iters_capped_to_cl\":%s", b->o->ref_uncapped ? "false" : "true");
		printf("}\n");
		fflush(stdout);
	}
}

/* The OpenCL chain and the reference beside it, stage by stage. A stage not
 * asked for still runs on OpenCL when a later one needs its output, but
 * prints nothing. */
static int run_input(const bench *b, const input_case *in, const dp_cloud *c)
{
	const options *o = b->o;
	int last = in->warm_up ? ST_SURFACE : -1;
	for (int s = 0; s < ST_COUNT; s++)
		if (o->stages[s] || o->total)
			last = s;
	int use_ref = !in->warm_up && (!o->ref_max || in->samples <= o->ref_max);
	char why[96];
	snprintf(why, sizeof why, "samples %zu above --ref-max %zu", in->samples, o->ref_max);
	dp_error err = {0};
	chain ch = {.c = c, .samples = in->samples};
	dp_cloud ref_out = {0};
	run_result cl_runs[ST_COUNT], ref_runs[ST_COUNT];
	memset(cl_runs, 0, sizeof cl_runs);
	memset(ref_runs, 0, sizeof ref_runs);
	int ref_stages = 0, rc = -1;
	if (!(ch.eta = dp_alloc_array(in->samples, sizeof(float)))) {
		dp_fail(&err, DP_ERR_NOMEM, "bench_stages: out of memory");
		goto done;
	}
	for (int s = 0; s <= last; s++) {
		int want = o->stages[s] && !in->warm_up;
		if (!in->warm_up)
			fprintf(stderr, "bench_stages: %s %s\n", in->name, stage_names[s]);
		cl_counters before, after;
		dp_neighbour_counts nb_before, nb_after;
		cl_counters_take(b->cl, &before);
		if (b->cl_nb)
			nb_before = *b->cl_nb;
		if (run_stage(b->cl, (stage_id)s, 0, &ch, &ch.out[s], &ch.r, &cl_runs[s], &err) != DP_OK)
			goto done;
		cl_counters_take(b->cl, &after);
		if (b->cl_nb) {
			nb_after = *b->cl_nb;
			if (s != ST_NORMALS)
				take_count(&cl_runs[s], &nb_before, &nb_after);
		}
		cl_runs[s].moved = s != ST_NORMALS;
		cl_runs[s].h2d = after.h2d - before.h2d;
		cl_runs[s].d2h = after.d2h - before.d2h;
		cl_runs[s].h2d_skipped = after.skipped - before.skipped;
		/* r for the diffs of WLOP too; the normals line times it. */
		if (s == ST_WLOP &&
		    dp_mean_spacing(ch.out[s].n, ch.out[s].x, ch.out[s].y, ch.out[s].z, &ch.r, &err) != DP_OK)
			goto done;
		if (!want)
			continue;
		print_run(in, stage_names[s], b->cl, &cl_runs[s]);
		if (s == ST_WLOP && in->paper)
			printf(",\"paper_seconds\":%.1f", in->paper->tw);
		if (s != ST_WLOP && in->paper)
			printf(",\"paper_deep_seconds\":%.1f", in->paper->td);
		if (s == ST_NORMALS)
			printf(",\"r\":%.6g,\"seconds_spacing\":%.4f,\"host_only\":true", ch.r,
			       cl_runs[s].seconds_spacing);
		printf("}\n");
		fflush(stdout);
		peak_setting pk = {.ctx = b->cl, .run = o->peak};
		stage_clouds(&ch, (stage_id)s, &pk);
		print_operators(in, stage_names[s], &before, &after, b->cl_nb ? &nb_before : NULL,
				b->cl_nb ? &nb_after : NULL, &pk);
		if (!use_ref) {
			print_skip(in, stage_names[s], "ref", why);
			continue;
		}

		int cap = o->ref_uncapped ? 0 : cl_runs[s].iterations;
		double r_ref;
		if (b->ref_nb)
			nb_before = *b->ref_nb;
		if (run_stage(b->ref, (stage_id)s, cap, &ch, &ref_out, &r_ref, &ref_runs[s], &err) != DP_OK)
			goto done;
		if (b->ref_nb && s != ST_NORMALS) {
			nb_after = *b->ref_nb;
			take_count(&ref_runs[s], &nb_before, &nb_after);
		}
		ref_stages |= 1 << s;
		print_run(in, stage_names[s], b->ref, &ref_runs[s]);
		if (s == ST_NORMALS) {
			printf(",\"r\":%.6g,\"seconds_spacing\":%.4f,\"host_only\":true}\n", r_ref,
			       ref_runs[s].seconds_spacing);
			fflush(stdout);
		} else {
			print_ref_tail(cap > 0, cap, mean_diff(&ch.out[s], &ref_out, ch.r));
		}
		dp_cloud_free(&ref_out);
	}
	if (o->total && !in->warm_up)
		print_totals(b, in, cl_runs, ref_runs, ref_stages == (1 << ST_COUNT) - 1,
			     use_ref ? "not every stage ran on the reference" : why);
	rc = 0;
done:
	if (rc)
		fprintf(stderr, "bench_stages: %s: %s\n", in->name, err.message);
	for (int s = 0; s < ST_COUNT; s++)
		dp_cloud_free(&ch.out[s]);
	dp_cloud_free(&ref_out);
	free(ch.eta);
	return rc;
}

int main(int argc, char **argv)
{
	options o;
	if (parse_options(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_stages [--sizes C:S[:shape],...|none] "
				"[--stages wlop,normals,sink,skeleton,surface,total]\n"
				"                    [--ref-max N] [--ref-uncapped] [--quick] [--table1] [--no-statue] "
				"[--no-warm-up]\n                    [--no-neighbours] [--no-peak] [--device D] "
				"[--data DIR] [--threads N]\n");
		return 2;
	}
	dp_error err = {0};
	bench b = {.o = &o};
	if (dp_context_create(&b.cl, DP_BACKEND_CL, o.device, &err) != DP_OK ||
	    dp_context_create(&b.ref, DP_BACKEND_REF, NULL, &err) != DP_OK) {
		fprintf(stderr, "bench_stages: %s\n", err.message);
		dp_context_free(b.cl);
		return 1;
	}
	/* the host loops are the same code on both backends: the same threads */
	dp_context_set_threads(b.cl, o.threads);
	dp_context_set_threads(b.ref, o.threads);
	dp_neighbour_counts cl_nb = {0}, ref_nb = {0};
	if (o.neighbours) {
		b.cl->neighbours = b.cl_nb = &cl_nb;
		b.ref->neighbours = b.ref_nb = &ref_nb;
	}
	int rc = 0;
	if (o.warm_up) {
		input_case in = {.name = "warm-up", .size = WARM_UP_SIZE, .samples = WARM_UP_SAMPLES, .warm_up = 1};
		dp_cloud c;
		if (make_scan(WARM_UP_SHAPE, WARM_UP_SIZE, &c, &err) != DP_OK) {
			fprintf(stderr, "bench_stages: %s\n", err.message);
			rc = 1;
		} else {
			rc = run_input(&b, &in, &c) ? 1 : 0;
			dp_cloud_free(&c);
		}
	}
	for (int i = 0; i < o.nsizes && !rc; i++) {
		char name[64];
		snprintf(name, sizeof name, "%s-%zu", o.shapes[i], o.sizes[i]);
		input_case in = {.name = name, .size = o.sizes[i], .samples = o.samples[i],
				 .paper = paper_lookup(o.sizes[i], o.samples[i])};
		dp_cloud c;
		fprintf(stderr, "bench_stages: scanning %s\n", name);
		if (make_scan(o.shapes[i], o.sizes[i], &c, &err) != DP_OK) {
			fprintf(stderr, "bench_stages: %s\n", err.message);
			rc = 1;
			break;
		}
		rc = run_input(&b, &in, &c) ? 1 : 0;
		dp_cloud_free(&c);
	}
	size_t ndata = o.table1 ? sizeof data_inputs / sizeof data_inputs[0] : (size_t)o.statue;
	for (size_t i = 0; i < ndata && !rc; i++) {
		const data_input *d = &data_inputs[i];
		char path[4096];
		snprintf(path, sizeof path, "%s/%s", o.data, d->file);
		dp_cloud c;
		if (dp_cloud_read(path, &c, DP_READ_POINTS, &err) != DP_OK) {
			fprintf(stderr, "bench_stages: skipping %s: %s\n", d->name, err.message);
			input_case in = {.name = d->name, .samples = d->samples};
			print_skip(&in, "total", "cl", "data absent or unreadable");
		} else {
			input_case in = {.name = d->name, .size = c.n, .samples = d->samples,
					 .paper = paper_lookup(c.n, d->samples)};
			rc = run_input(&b, &in, &c) ? 1 : 0;
			dp_cloud_free(&c);
		}
	}
	dp_context_free(b.cl);
	dp_context_free(b.ref);
	return rc;
}
