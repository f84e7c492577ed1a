/* Issue 3's quality numbers as the deep-point count grows, and the demo
 * chair stage by stage, as JSON lines (OpenCL backend, default parameters but
 * the sample count). tests/test_pipeline_shapes.c asserts the targets at one
 * small size; this shows how each number moves with size, since the surface
 * stage's spreading into missing regions needs more iterations as the shape
 * gets more r across (measured: one-view sphere coverage 0.99 at 1500
 * samples, 0.91 at 3000, 0.72 at 6000, the last two at the 200-iteration cap).
 *
 *   bench_quality_sizes [--samples M,M,...] [--seed S] [--noise F] [--device D] [--no-chair]
 *
 * Lines: {"bench":"quality_sizes","case":...,"samples":...,<measures>,
 * "targets":{name: pass}} per shape case and size; {"bench":"quality_chair",
 * "set":"input|wlop|surface|surface_supported|surface_unsupported",...} for
 * each chair setup. Lengths: shape cases in the shape's unit (R, T or rho), chair
 * in bbox diagonals of the ground truth.
 */
#include "dpoints_tools.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_SAMPLES "1500,3000,6000"
#define MAX_SIZES 8
/* Raw points per deep point for complete samples (the test's 12000 : 1500). */
#define RAW_PER_SAMPLE 8
/* One-view scans: res x res rays with res = SCAN_RES_1500 sqrt(m / 1500),
 * so the raw points per deep point stay near the test's (about 4). */
#define SCAN_RES_1500 160.0
#define DEFAULT_NOISE 0.003
#define DEFAULT_SEED 7
/* As in the test: the cylinder is 10 R long, spread cells are R/2 along
 * curves and T x T on the slab. */
#define CYLINDER_LENGTH_R 10.0
#define CURVE_CELL 0.5
#define SLAB_CELL 1.0
/* The demo chair (host/cli/cmd_demo.c): two views, noise 0.003; rays and
 * deep points as the demo first had them and as it has them now. A surface
 * point with η > SUPPORTED_ETA counts as supported by input (η = 1 + Σθ over
 * the input within σp r; 1 = none). */
#define CHAIR_VIEWS 2
#define SUPPORTED_ETA 2.0f
static const struct {
	int res;
	size_t samples;
} chair_setups[] = {{160, 3000}, {256, 4000}};

typedef struct options {
	size_t samples[MAX_SIZES];
	int nsizes;
	uint64_t seed;
	double noise;
	const char *device;
	int chair;
} options;

typedef enum case_kind { SPHERE, CYLINDER, SLAB, TORUS, VIEW_SPHERE, VIEW_TORUS, NCASES } case_kind;

static const char *case_name[NCASES] = {"sphere", "cylinder", "slab", "torus", "one_view_sphere",
					"one_view_torus"};
static const char *case_shape[NCASES] = {"sphere", "cylinder", "slab", "torus", "sphere", "torus"};

static double unit_of(const dp_shape *s)
{
	return s->kind == DP_SHAPE_SLAB ? s->thickness : s->kind == DP_SHAPE_TORUS ? s->tube : s->radius;
}

static void print_target(int *first, const char *name, int pass)
{
	printf("%s\"%s\":%s", *first ? "" : ",", name, pass ? "true" : "false");
	*first = 0;
}

static dp_status make_input(case_kind k, const dp_cloud *mesh, size_t m, const options *o, dp_cloud *in,
			    dp_error *err)
{
	if (k != VIEW_SPHERE && k != VIEW_TORUS)
		return dp_mesh_sample(mesh, RAW_PER_SAMPLE * m, o->noise, o->seed, in, err);
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = 1;
	sp.res = (int)lround(SCAN_RES_1500 * sqrt((double)m / 1500.0));
	sp.noise = o->noise;
	sp.normals = 0;
	sp.seed = o->seed;
	return dp_scan(mesh, &sp, in, NULL, err);
}

/* Coverage of the output, and of the input at the output's radius. */
static dp_status coverages(const dp_cloud *mesh, const dp_cloud *in, const dp_cloud *out, double *cov_out,
			   double *cov_in, dp_error *err)
{
	dp_eval_result eo, ei;
	dp_eval_params ep;
	dp_eval_params_default(&ep);
	dp_status st = dp_eval(mesh, out, NULL, &eo, err);
	if (st == DP_OK)
		st = dp_eval(mesh, in, NULL, &ei, err);
	if (st != DP_OK)
		return st;
	ep.coverage_factor *= eo.spacing_mean / ei.spacing_mean;
	st = dp_eval(mesh, in, &ep, &ei, err);
	*cov_out = eo.coverage;
	*cov_in = ei.coverage;
	return st;
}

static int run_case(dp_context *ctx, case_kind k, size_t m, const options *o)
{
	dp_error err = {0};
	dp_shape s;
	dp_cloud mesh = {0}, in = {0};
	dp_result res = {0};
	int rc = -1;
	if (dp_shape_default(case_shape[k], &s, &err) != DP_OK)
		goto out;
	if (s.kind == DP_SHAPE_CYLINDER)
		s.length = CYLINDER_LENGTH_R * s.radius;
	if (dp_shape_mesh(&s, &mesh, &err) != DP_OK || make_input(k, &mesh, m, o, &in, &err) != DP_OK)
		goto out;
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = m;
	if (dp_consolidate(ctx, &in, &p, &res, &err) != DP_OK)
		goto out;
	double u = unit_of(&s), cell = (s.kind == DP_SHAPE_SLAB ? SLAB_CELL : CURVE_CELL) * u;
	dp_shape_fit sk, su;
	if (dp_shape_fit_points(&s, &res.skeleton, cell, &sk, &err) != DP_OK ||
	    dp_shape_fit_points(&s, &res.surface, cell, &su, &err) != DP_OK)
		goto out;
	printf("{\"bench\":\"quality_sizes\",\"case\":\"%s\",\"samples\":%zu,\"filled_from\":%zu,\"raw\":%zu,"
	       "\"noise\":%g,\"seed\":%llu,\"r\":%.6g,\"unit_in_r\":%.3f,"
	       "\"iterations\":{\"wlop\":%d,\"sink\":%d,\"skeleton\":%d,\"surface\":%d},"
	       "\"surface_converged\":%s,\"seconds\":%.3f,\"skeleton_mean\":%.4f,\"surface_mean\":%.4f",
	       case_name[k], res.surface.n, res.filled_from, in.n, o->noise, (unsigned long long)o->seed, res.r,
	       u / res.r, res.wlop_stats.iterations, res.sink_stats.iterations, res.skeleton_stats.iterations,
	       res.surface_stats.iterations, res.surface_stats.converged ? "true" : "false", res.seconds_total,
	       sk.skeleton_mean / u, su.surface_mean / u);
	int first = 1;
	switch (k) {
	case SPHERE:
		printf(",\"targets\":{");
		print_target(&first, "skeleton_mean<0.15", sk.skeleton_mean / u < 0.15);
		print_target(&first, "surface_mean<0.01", su.surface_mean / u < 0.01);
		break;
	case CYLINDER:
		printf(",\"axis_spread\":%.4f,\"targets\":{", sk.spread);
		print_target(&first, "skeleton_mean<0.25", sk.skeleton_mean / u < 0.25);
		print_target(&first, "axis_spread>=0.7", sk.spread >= 0.7);
		break;
	case SLAB:
		printf(",\"plane_spread\":%.4f,\"targets\":{", sk.spread);
		print_target(&first, "skeleton_mean<0.25", sk.skeleton_mean / u < 0.25);
		print_target(&first, "plane_spread>=0.6", sk.spread >= 0.6);
		break;
	case TORUS:
		printf(",\"circle_gap\":%.4f,\"targets\":{", sk.largest_gap);
		print_target(&first, "skeleton_mean<0.25", sk.skeleton_mean / u < 0.25);
		print_target(&first, "circle_gap<0.1", sk.largest_gap < 0.1);
		break;
	case VIEW_SPHERE:
	case VIEW_TORUS: {
		double cov_out, cov_in;
		if (coverages(&mesh, &in, &res.surface, &cov_out, &cov_in, &err) != DP_OK) {
			printf("}\n");
			goto out;
		}
		printf(",\"coverage\":%.4f,\"input_coverage\":%.4f,\"targets\":{", cov_out, cov_in);
		print_target(&first, "coverage>=0.9", cov_out >= 0.9);
		print_target(&first, "surface_mean<0.05", su.surface_mean / u < 0.05);
		break;
	}
	case NCASES:
		break;
	}
	printf("}}\n");
	rc = 0;
out:
	if (rc)
		fprintf(stderr, "bench_quality_sizes: %s, %zu samples: %s\n", case_name[k], m, err.message);
	dp_result_free(&res);
	dp_cloud_free(&in);
	dp_cloud_free(&mesh);
	return rc;
}

static void chair_line(size_t samples, const char *set, const dp_eval_result *e)
{
	printf("{\"bench\":\"quality_chair\",\"samples\":%zu,\"set\":\"%s\",\"points\":%zu,\"accuracy_mean\":%.5f,"
	       "\"accuracy_p95\":%.5f,\"completeness_mean\":%.5f,\"coverage\":%.4f,\"spacing_cv\":%.4f,"
	       "\"scatter_median\":%.4f",
	       samples, set, e->points, e->accuracy_mean, e->accuracy_p95, e->completeness_mean, e->coverage, e->spacing_cv,
	       e->scatter_median);
	if (e->has_normals)
		printf(",\"normal_angle_deg\":%.3f,\"normal_flipped\":%.4f,\"normal_flipped_clear\":%.4f",
		       e->normal_angle_deg, e->normal_flipped, e->normal_flipped_clear);
	printf("}\n");
}

/* The surface points with (or without) input support, as their own cloud. */
static dp_status split_by_support(const dp_result *res, int supported, dp_cloud *out, dp_error *err)
{
	size_t n = 0;
	for (size_t i = 0; i < res->surface.n; i++)
		n += (res->eta[i] > SUPPORTED_ETA) == supported;
	dp_status st = dp_cloud_alloc(out, n, 1, err);
	if (st != DP_OK)
		return st;
	const dp_cloud *s = &res->surface;
	for (size_t i = 0, j = 0; i < s->n; i++) {
		if ((res->eta[i] > SUPPORTED_ETA) != supported)
			continue;
		out->x[j] = s->x[i], out->y[j] = s->y[i], out->z[j] = s->z[i];
		out->nx[j] = s->nx[i], out->ny[j] = s->ny[i], out->nz[j] = s->nz[i];
		j++;
	}
	return DP_OK;
}

static int run_chair(dp_context *ctx, int res_rays, size_t samples)
{
	dp_error err = {0};
	dp_shape s;
	dp_cloud mesh = {0}, scan = {0}, part[2] = {{0}, {0}};
	dp_result res = {0};
	int rc = -1;
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = CHAIR_VIEWS;
	sp.res = res_rays;
	sp.noise = DEFAULT_NOISE;
	sp.normals = 0;
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = samples;
	if (dp_shape_default("chair", &s, &err) != DP_OK || dp_shape_mesh(&s, &mesh, &err) != DP_OK ||
	    dp_scan(&mesh, &sp, &scan, NULL, &err) != DP_OK || dp_consolidate(ctx, &scan, &p, &res, &err) != DP_OK)
		goto out;
	printf("{\"bench\":\"quality_chair\",\"rays\":%d,\"raw\":%zu,\"samples\":%zu,\"r\":%.6g,\"iterations\":{\"wlop\":%d,"
	       "\"sink\":%d,\"skeleton\":%d,\"surface\":%d},\"sink_settled\":{\"front\":%zu,\"medial\":%zu,"
	       "\"width\":%zu,\"slow\":%zu,\"flat\":%zu,\"unsettled\":%zu},\"seconds\":%.3f}\n",
	       res_rays, scan.n, res.surface.n, res.r, res.wlop_stats.iterations, res.sink_stats.iterations,
	       res.skeleton_stats.iterations, res.surface_stats.iterations, res.sink_stats.settled_front,
	       res.sink_stats.settled_medial, res.sink_stats.settled_width, res.sink_stats.settled_slow,
	       res.sink_stats.settled_flat, res.sink_stats.unsettled,
	       res.seconds_total);
	const char *names[] = {"input", "wlop", "surface", "surface_unsupported", "surface_supported"};
	if (split_by_support(&res, 0, &part[0], &err) != DP_OK || split_by_support(&res, 1, &part[1], &err) != DP_OK)
		goto out;
	const dp_cloud *sets[] = {&scan, &res.wlop, &res.surface, &part[0], &part[1]};
	for (int i = 0; i < 5; i++) {
		dp_eval_result e;
		if (sets[i]->n < 2)
			continue;
		if (dp_eval(&mesh, sets[i], NULL, &e, &err) != DP_OK)
			goto out;
		chair_line(samples, names[i], &e);
	}
	rc = 0;
out:
	if (rc)
		fprintf(stderr, "bench_quality_sizes: chair: %s\n", err.message);
	dp_result_free(&res);
	dp_cloud_free(&part[0]);
	dp_cloud_free(&part[1]);
	dp_cloud_free(&scan);
	dp_cloud_free(&mesh);
	return rc;
}

static int parse_sizes(const char *text, options *o)
{
	o->nsizes = 0;
	while (*text) {
		char *end;
		unsigned long long m = strtoull(text, &end, 10);
		if (m < 2 || o->nsizes == MAX_SIZES || (*end && *end != ','))
			return -1;
		o->samples[o->nsizes++] = (size_t)m;
		text = *end ? end + 1 : end;
	}
	return o->nsizes ? 0 : -1;
}

static int parse(int argc, char **argv, options *o)
{
	o->seed = DEFAULT_SEED;
	o->noise = DEFAULT_NOISE;
	o->device = NULL;
	o->chair = 1;
	if (parse_sizes(DEFAULT_SAMPLES, o))
		return -1;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		char *end = "";
		if (!strcmp(a, "--no-chair")) {
			o->chair = 0;
			continue;
		}
		if (!v)
			return -1;
		i++;
		if (!strcmp(a, "--samples")) {
			if (parse_sizes(v, o))
				return -1;
		} else if (!strcmp(a, "--seed")) {
			o->seed = strtoull(v, &end, 10);
		} else if (!strcmp(a, "--noise")) {
			o->noise = strtod(v, &end);
			if (!(o->noise >= 0.0))
				return -1;
		} else if (!strcmp(a, "--device")) {
			o->device = v;
		} else {
			return -1;
		}
		if (*end)
			return -1;
	}
	return 0;
}

int main(int argc, char **argv)
{
	options o;
	if (parse(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_quality_sizes [--samples M,M,...] [--seed S] [--noise F] [--device D] "
				"[--no-chair]\n");
		return 2;
	}
	dp_context *ctx = NULL;
	dp_error err = {0};
	if (dp_context_create(&ctx, DP_BACKEND_CL, o.device, &err) != DP_OK) {
		fprintf(stderr, "bench_quality_sizes: %s\n", err.message);
		return 1;
	}
	int rc = 0;
	for (int i = 0; i < o.nsizes; i++)
		for (int k = 0; k < NCASES; k++) {
			rc |= run_case(ctx, (case_kind)k, o.samples[i], &o);
			fflush(stdout);
		}
	for (size_t i = 0; o.chair && i < sizeof chair_setups / sizeof chair_setups[0]; i++)
		rc |= run_chair(ctx, chair_setups[i].res, chair_setups[i].samples);
	dp_context_free(ctx);
	return rc ? 1 : 0;
}
