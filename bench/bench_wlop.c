/* WLOP benchmark (DESIGN 6): the whole stage and each operator, on the OpenCL
 * backend and the scalar reference over the same inputs, as JSON lines.
 * Inputs: noisy torus samples made here at the paper's Table 1 sizes, and the
 * statue scan of the paper's Fig. 12 when the shared data folder has it.
 *
 *   bench_wlop [--sizes N:M,...] [--iters K] [--ref-max N] [--device D]
 *              [--data DIR] [--no-ops] [--no-statue]
 */
#include "dpoints.h"
#include "backend/ops.h"
#include "core/common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Table 1 of the paper: |C| -> |S| (22K -> 2K, 85K -> 7K, 484K -> 47K). */
#define DEFAULT_SIZES "22000:2000,85000:7000,484000:47000"
/* The paper's WLOP takes 30-40 iterations; every run does exactly K (tol = 0)
 * so both backends do the same work. */
#define DEFAULT_ITERS 35
#define STATUE_FILE "paper/statue-fig12b-raw.xyz"
#define STATUE_SAMPLES 7252
#define MAX_SIZES 16
/* Torus with core radius 1 and tube radius 0.35; noise sigma 1% of the core
 * radius, about a third of the sample spacing at 47K samples. */
#define TORUS_R 1.0
#define TORUS_RHO 0.35
#define TORUS_NOISE 0.01
#define TORUS_SEED 7

typedef struct options {
	size_t sizes[MAX_SIZES], samples[MAX_SIZES];
	int nsizes;
	int iters;
	size_t ref_max; /* 0 = no limit */
	const char *device;
	const char *data;
	int ops, statue;
} options;

static int parse_sizes(const char *text, options *o)
{
	o->nsizes = 0;
	while (*text) {
		char *end;
		unsigned long long n = strtoull(text, &end, 10);
		if (*end != ':' || o->nsizes == MAX_SIZES)
			return -1;
		unsigned long long m = strtoull(end + 1, &end, 10);
		if (n == 0 || m == 0 || m > n || (*end && *end != ','))
			return -1;
		o->sizes[o->nsizes] = (size_t)n;
		o->samples[o->nsizes++] = (size_t)m;
		text = *end ? end + 1 : end;
	}
	return o->nsizes ? 0 : -1;
}

static int parse_options(int argc, char **argv, options *o)
{
	memset(o, 0, sizeof *o);
	o->iters = DEFAULT_ITERS;
	o->ops = o->statue = 1;
	o->data = getenv("DP_DATA_DIR") ? getenv("DP_DATA_DIR") : "../shared/data";
	parse_sizes(DEFAULT_SIZES, o);
	for (int a = 1; a < argc; a++) {
		const char *arg = argv[a], *val = a + 1 < argc ? argv[a + 1] : NULL;
		if (!strcmp(arg, "--no-ops")) {
			o->ops = 0;
		} else if (!strcmp(arg, "--no-statue")) {
			o->statue = 0;
		} else if (!val) {
			return -1;
		} else if (!strcmp(arg, "--sizes")) {
			if (parse_sizes(val, o))
				return -1;
			a++;
		} else if (!strcmp(arg, "--iters")) {
			o->iters = atoi(val);
			if (o->iters < 1)
				return -1;
			a++;
		} else if (!strcmp(arg, "--ref-max")) {
			o->ref_max = (size_t)strtoull(val, NULL, 10);
			a++;
		} else if (!strcmp(arg, "--device")) {
			o->device = val;
			a++;
		} else if (!strcmp(arg, "--data")) {
			o->data = val;
			a++;
		} else {
			return -1;
		}
	}
	return 0;
}

/* n points uniform by area on the torus (rejection on the tube angle), plus
 * Gaussian noise. */
static dp_status make_torus(size_t n, dp_cloud *c, dp_error *err)
{
	dp_status st = dp_cloud_alloc(c, n, 0, err);
	if (st != DP_OK)
		return st;
	dp_rng rng;
	dp_rng_seed(&rng, TORUS_SEED);
	for (size_t i = 0; i < n;) {
		double u = 2.0 * M_PI * dp_rng_uniform(&rng), v = 2.0 * M_PI * dp_rng_uniform(&rng);
		double ring = TORUS_R + TORUS_RHO * cos(v);
		if (dp_rng_uniform(&rng) * (TORUS_R + TORUS_RHO) > ring)
			continue;
		c->x[i] = (float)(ring * cos(u) + TORUS_NOISE * dp_rng_normal(&rng));
		c->y[i] = (float)(ring * sin(u) + TORUS_NOISE * dp_rng_normal(&rng));
		c->z[i] = (float)(TORUS_RHO * sin(v) + TORUS_NOISE * dp_rng_normal(&rng));
		i++;
	}
	return DP_OK;
}

static void print_skip(const char *what, const char *input, size_t n, const char *backend, const char *why)
{
	printf("{\"what\":\"%s\",\"input\":\"%s\",\"size\":%zu,\"backend\":\"%s\",\"skipped\":\"%s\"}\n", what, input, n,
	       backend, why);
	fflush(stdout);
}

static int run_stage(dp_context *ctx, const char *backend, const char *input, const dp_cloud *c, size_t m,
		     int iters)
{
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = m;
	p.max_iters = iters;
	p.tol = 0.0;
	dp_wlop_stats s;
	dp_cloud out;
	dp_error err = {0};
	if (dp_wlop(ctx, c, &p, &out, &s, &err) != DP_OK) {
		fprintf(stderr, "bench_wlop: %s\n", err.message);
		return -1;
	}
	double compute = s.seconds_density + s.seconds_iterations;
	printf("{\"what\":\"wlop\",\"input\":\"%s\",\"size\":%zu,\"samples\":%zu,\"backend\":\"%s\",\"device\":\"%s\","
	       "\"seconds\":%.4f,\"iterations\":%d,\"pair_evals_per_s\":%.4g,\"h\":%.6g,\"pair_evaluations\":%.6g,"
	       "\"seconds_setup\":%.4f,\"seconds_density\":%.4f,\"seconds_grid\":%.4f,"
	       "\"seconds_sample_density\":%.4f,\"seconds_attraction\":%.4f,\"seconds_repulsion\":%.4f}\n",
	       input, c->n, m, backend, dp_context_device_name(ctx), s.seconds, s.iterations,
	       compute > 0 ? s.pair_evaluations / compute : 0.0, s.h, s.pair_evaluations, s.seconds_setup,
	       s.seconds_density, s.seconds_grid, s.seconds_sample_density, s.seconds_attraction, s.seconds_repulsion);
	fflush(stdout);
	dp_cloud_free(&out);
	return 0;
}

/* The operators of one iteration, timed alone on the initial samples: grids
 * and arguments as dp_wlop builds them (h from the default factor). */
typedef struct op_case {
	dp_grid input, sample;
	float *inv_v, *w;
	float *scratch;         /* |C| floats: density results */
	float *out;             /* 4 arrays of m: attraction and repulsion results */
	const float *ux, *uy, *uz; /* the samples in their random (unsorted) order */
	float h, theta_k, min_d2;
	int gaussian, sqrt_density;
} op_case;

static void op_case_free(op_case *oc)
{
	dp_grid_free(&oc->input);
	dp_grid_free(&oc->sample);
	free(oc->inv_v);
	free(oc->w);
	free(oc->scratch);
	free(oc->out);
}

static dp_status op_case_make(const dp_cloud *c, const dp_cloud *initial, double h, op_case *oc, dp_error *err)
{
	memset(oc, 0, sizeof *oc);
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	oc->h = (float)h;
	oc->theta_k = (float)p.theta_k;
	oc->min_d2 = (DP_PAIR_EPS * oc->h) * (DP_PAIR_EPS * oc->h);
	oc->gaussian = p.weight == DP_WLOP_GAUSSIAN;
	oc->sqrt_density = p.sqrt_density;
	size_t m = initial->n;
	oc->inv_v = dp_alloc_array(c->n, sizeof(float));
	oc->w = dp_alloc_array(m, sizeof(float));
	oc->scratch = dp_alloc_array(c->n, sizeof(float));
	oc->out = dp_alloc_array(4 * m, sizeof(float));
	oc->ux = initial->x;
	oc->uy = initial->y;
	oc->uz = initial->z;
	if (!oc->inv_v || !oc->w || !oc->scratch || !oc->out)
		return dp_fail(err, DP_ERR_NOMEM, "bench_wlop: out of memory");
	dp_status st = dp_grid_build(&oc->input, c->n, c->x, c->y, c->z, oc->h, err);
	if (st == DP_OK)
		st = dp_grid_build(&oc->sample, m, initial->x, initial->y, initial->z, oc->h, err);
	if (st != DP_OK)
		return st;
	/* The attribute values the stage would use in its first iteration. */
	dp_context *ref;
	if ((st = dp_context_create(&ref, DP_BACKEND_REF, NULL, err)) != DP_OK)
		return st;
	dp_density_args v = {.data = &oc->input, .nq = c->n, .qx = oc->input.x, .qy = oc->input.y,
			     .qz = oc->input.z, .h = oc->h, .theta_k = oc->theta_k, .min_d2 = oc->min_d2,
			     .out = oc->inv_v};
	dp_density_args w = {.data = &oc->sample, .nq = m, .qx = oc->sample.x, .qy = oc->sample.y,
			     .qz = oc->sample.z, .h = oc->h, .theta_k = oc->theta_k, .min_d2 = oc->min_d2,
			     .sqrt_density = oc->sqrt_density, .out = oc->w};
	if ((st = dp_op_density(ref, &v, err)) == DP_OK)
		st = dp_op_density(ref, &w, err);
	dp_context_free(ref);
	for (size_t k = 0; k < c->n; k++)
		oc->inv_v[k] = 1.0f / oc->inv_v[k];
	return st;
}

typedef enum op_kind {
	OP_INPUT_DENSITY,
	OP_SAMPLE_DENSITY,
	OP_ATTRACTION,
	OP_ATTRACTION_UNSORTED,
	OP_REPULSION,
	OP_COUNT
} op_kind;

static const char *op_names[OP_COUNT] = {"input_density", "sample_density", "attraction",
					  "attraction_unsorted_queries", "repulsion"};

static dp_status run_op(dp_context *ctx, const op_case *oc, op_kind op, dp_error *err)
{
	const dp_grid *s = &oc->sample, *in = &oc->input;
	size_t m = s->n;
	float *o = oc->out;
	if (op == OP_INPUT_DENSITY || op == OP_SAMPLE_DENSITY) {
		const dp_grid *g = op == OP_INPUT_DENSITY ? in : s;
		dp_density_args a = {.data = g, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = oc->h,
				     .theta_k = oc->theta_k, .min_d2 = oc->min_d2,
				     .sqrt_density = op == OP_SAMPLE_DENSITY && oc->sqrt_density, .out = oc->scratch};
		return dp_op_density(ctx, &a, err);
	}
	if (op == OP_ATTRACTION || op == OP_ATTRACTION_UNSORTED) {
		int sorted = op == OP_ATTRACTION;
		dp_attraction_args a = {.data = in, .inv_v = oc->inv_v, .nq = m, .qx = sorted ? s->x : oc->ux,
					.qy = sorted ? s->y : oc->uy, .qz = sorted ? s->z : oc->uz, .h = oc->h,
					.theta_k = oc->theta_k, .min_d2 = oc->min_d2, .gaussian = oc->gaussian,
					.out_x = o, .out_y = o + m, .out_z = o + 2 * m, .out_w = o + 3 * m};
		return dp_op_attraction(ctx, &a, err);
	}
	dp_repulsion_args a = {.data = s, .w = oc->w, .nq = m, .qx = s->x, .qy = s->y, .qz = s->z, .h = oc->h,
			       .theta_k = oc->theta_k, .min_d2 = oc->min_d2, .out_x = o, .out_y = o + m,
			       .out_z = o + 2 * m, .out_w = o + 3 * m};
	return dp_op_repulsion(ctx, &a, err);
}

/* Each operator is repeated for at least this long so that short ones are
 * not dominated by launch jitter. */
#define OP_MIN_SECONDS 0.5

static int run_ops(dp_context *ctx, const char *backend, const char *input, const op_case *oc, size_t n)
{
	dp_error err = {0};
	for (int op = 0; op < OP_COUNT; op++) {
		/* Warm-up: the first launch of a kernel creates it. */
		if (run_op(ctx, oc, (op_kind)op, &err) != DP_OK)
			goto fail;
		int reps = 0;
		double pairs0 = ctx->pair_evaluations, t0 = dp_seconds(), t;
		do {
			if (run_op(ctx, oc, (op_kind)op, &err) != DP_OK)
				goto fail;
			reps++;
			t = dp_seconds() - t0;
		} while (t < OP_MIN_SECONDS);
		printf("{\"what\":\"wlop_op\",\"op\":\"%s\",\"input\":\"%s\",\"size\":%zu,\"samples\":%zu,"
		       "\"backend\":\"%s\",\"device\":\"%s\",\"seconds\":%.5f,\"pair_evals_per_s\":%.4g}\n",
		       op_names[op], input, n, oc->sample.n, backend, dp_context_device_name(ctx), t / reps,
		       (ctx->pair_evaluations - pairs0) / t);
		fflush(stdout);
	}
	return 0;
fail:
	fprintf(stderr, "bench_wlop: %s\n", err.message);
	return -1;
}

/* Initial samples as dp_wlop chooses them (0 iterations), and its h. */
static dp_status initial_samples(dp_context *ctx, const dp_cloud *c, size_t m, dp_cloud *initial, double *h,
				 dp_error *err)
{
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = m;
	p.max_iters = 0;
	dp_wlop_stats s;
	dp_status st = dp_wlop(ctx, c, &p, initial, &s, err);
	*h = s.h;
	return st;
}

static int run_case(dp_context *cl, dp_context *ref, const options *o, const char *input, const dp_cloud *c,
		    size_t m)
{
	int use_ref = !o->ref_max || c->n <= o->ref_max;
	if (run_stage(cl, "cl", input, c, m, o->iters))
		return -1;
	if (!use_ref)
		print_skip("wlop", input, c->n, "ref", "above --ref-max");
	else if (run_stage(ref, "ref", input, c, m, o->iters))
		return -1;
	if (!o->ops)
		return 0;
	dp_error err = {0};
	dp_cloud initial;
	double h;
	op_case oc;
	int rc = -1;
	if (initial_samples(ref, c, m, &initial, &h, &err) != DP_OK) {
		fprintf(stderr, "bench_wlop: %s\n", err.message);
		return -1;
	}
	if (op_case_make(c, &initial, h, &oc, &err) != DP_OK) {
		fprintf(stderr, "bench_wlop: %s\n", err.message);
		goto done;
	}
	if (run_ops(cl, "cl", input, &oc, c->n))
		goto done;
	if (!use_ref)
		print_skip("wlop_op", input, c->n, "ref", "above --ref-max");
	else if (run_ops(ref, "ref", input, &oc, c->n))
		goto done;
	rc = 0;
done:
	op_case_free(&oc);
	dp_cloud_free(&initial);
	return rc;
}

int main(int argc, char **argv)
{
	options o;
	if (parse_options(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_wlop [--sizes N:M,...] [--iters K] [--ref-max N] [--device D] "
				"[--data DIR] [--no-ops] [--no-statue]\n");
		return 2;
	}
	dp_error err = {0};
	dp_context *cl = NULL, *ref = NULL;
	if (dp_context_create(&cl, DP_BACKEND_CL, o.device, &err) != DP_OK ||
	    dp_context_create(&ref, DP_BACKEND_REF, NULL, &err) != DP_OK) {
		fprintf(stderr, "bench_wlop: %s\n", err.message);
		dp_context_free(cl);
		return 1;
	}
	int rc = 0;
	for (int i = 0; i < o.nsizes && !rc; i++) {
		dp_cloud c;
		char name[64];
		snprintf(name, sizeof name, "torus-%zu", o.sizes[i]);
		if (make_torus(o.sizes[i], &c, &err) != DP_OK) {
			fprintf(stderr, "bench_wlop: %s\n", err.message);
			rc = 1;
			break;
		}
		rc = run_case(cl, ref, &o, name, &c, o.samples[i]) ? 1 : 0;
		dp_cloud_free(&c);
	}
	if (!rc && o.statue) {
		char path[4096];
		snprintf(path, sizeof path, "%s/%s", o.data, STATUE_FILE);
		dp_cloud c;
		if (dp_cloud_read(path, &c, DP_READ_POINTS, &err) != DP_OK) {
			fprintf(stderr, "bench_wlop: %s\n", err.message);
			print_skip("wlop", "statue-fig12b", 0, "cl", "data absent or unreadable");
		} else {
			rc = run_case(cl, ref, &o, "statue-fig12b", &c, STATUE_SAMPLES) ? 1 : 0;
			dp_cloud_free(&c);
		}
	}
	dp_context_free(cl);
	dp_context_free(ref);
	return rc;
}
