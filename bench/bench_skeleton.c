/* Meso-skeleton benchmark (DESIGN 4.2, 6): dp_skeleton on the OpenCL backend
 * and the scalar reference over the same anchors, as JSON lines. Inputs are
 * the behaviour tests' shapes at the paper's Table 1 sizes (|S| up to 67K): a
 * thin slab (a sheet skeleton) and a torus (a curve skeleton), with anchors
 * built as sinking would leave them (surface samples moved inwards by their
 * medial depth, with noise), and r their mean surface spacing (Eq. 1).
 *
 *   bench_skeleton [--sizes N,...] [--shapes slab,torus] [--iters K]
 *                  [--ref-max N] [--device D]
 *
 * --iters K runs exactly K iterations (no convergence test), so both backends
 * and different builds do the same work; without it the stage stops as usual.
 * The reference runs only for sizes <= --ref-max (0 = always); above, a
 * "skipped" line is printed. Besides the speed, every line reports the mean
 * distance of the result to the ideal skeleton (in r), so a faster build can
 * be checked to compute the same thing.
 */
#include "dpoints.h"
#include "core/common.h"
#include "knn/knn.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_SIZES "5000,20000,67000"
#define DEFAULT_SHAPES "slab,torus"
/* The reference runs 3-6x slower than the kernels on 2 cores; above this size
 * one run takes minutes. */
#define DEFAULT_REF_MAX 20000
#define MAX_SIZES 16
#define SEED 22
#define PI 3.14159265358979323846
/* Anchor noise as in tests/test_skeleton.c: relative depth error, isotropic
 * jitter in r, normal jitter. */
#define DEPTH_NOISE 0.05
#define JITTER_R 0.5
#define NORMAL_NOISE 0.05
/* The shapes of tests/test_skeleton.c: slab T x W x W, torus core Rc, tube rho. */
#define SLAB_T 1.0
#define SLAB_W 10.0
#define TORUS_RC 1.0
#define TORUS_RHO 0.3

typedef struct options {
	size_t sizes[MAX_SIZES];
	int nsizes;
	int slab, torus;
	int iters;      /* 0 = until converged */
	size_t ref_max; /* 0 = no limit */
	const char *device;
} options;

static int parse_sizes(const char *text, options *o)
{
	o->nsizes = 0;
	while (*text) {
		char *end;
		unsigned long long n = strtoull(text, &end, 10);
		if (n == 0 || o->nsizes == MAX_SIZES || (*end && *end != ','))
			return -1;
		o->sizes[o->nsizes++] = (size_t)n;
		text = *end ? end + 1 : end;
	}
	return o->nsizes ? 0 : -1;
}

static int parse_shapes(const char *text, options *o)
{
	o->slab = strstr(text, "slab") != NULL;
	o->torus = strstr(text, "torus") != NULL;
	return o->slab || o->torus ? 0 : -1;
}

static int parse_options(int argc, char **argv, options *o)
{
	memset(o, 0, sizeof *o);
	o->ref_max = DEFAULT_REF_MAX;
	parse_sizes(DEFAULT_SIZES, o);
	parse_shapes(DEFAULT_SHAPES, o);
	for (int a = 1; a < argc; a++) {
		const char *arg = argv[a], *val = a + 1 < argc ? argv[a + 1] : NULL;
		if (!val)
			return -1;
		if (!strcmp(arg, "--sizes")) {
			if (parse_sizes(val, o))
				return -1;
		} else if (!strcmp(arg, "--shapes")) {
			if (parse_shapes(val, o))
				return -1;
		} else if (!strcmp(arg, "--iters")) {
			o->iters = atoi(val);
			if (o->iters < 1)
				return -1;
		} else if (!strcmp(arg, "--ref-max")) {
			o->ref_max = (size_t)strtoull(val, NULL, 10);
		} else if (!strcmp(arg, "--device")) {
			o->device = val;
		} else {
			return -1;
		}
		a++;
	}
	return 0;
}

/* One surface sample: position, outward unit normal, medial depth. */
typedef void (*sample_fn)(dp_rng *rng, double p[3], double n[3], double *depth);
/* Distance of a point to the shape's ideal meso-skeleton. */
typedef double (*skeleton_distance_fn)(const double p[3]);

/* For a convex box the inward ball stops at the nearest of half the distance
 * to the opposite face and the distance to a perpendicular face's plane. */
static void sample_slab(dp_rng *rng, double p[3], double n[3], double *depth)
{
	double T = SLAB_T, W = SLAB_W, face = W * W, side = W * T;
	double u = dp_rng_uniform(rng) * (2 * face + 4 * side);
	double a = (dp_rng_uniform(rng) - 0.5) * W, b = dp_rng_uniform(rng) - 0.5;
	if (u < 2 * face) {
		double s = u < face ? 1.0 : -1.0;
		p[0] = a, p[1] = b * W, p[2] = s * 0.5 * T;
		n[0] = 0, n[1] = 0, n[2] = s;
		*depth = fmin(0.5 * T, fmin(0.5 * W - fabs(p[0]), 0.5 * W - fabs(p[1])));
	} else {
		int k = (int)((u - 2 * face) / side); /* which of the 4 sides */
		double s = (k & 1) ? 1.0 : -1.0, z = b * T;
		int axis = k < 2 ? 0 : 1;
		p[axis] = s * 0.5 * W, p[1 - axis] = a, p[2] = z;
		n[axis] = s, n[1 - axis] = 0, n[2] = 0;
		*depth = fmin(0.5 * T - fabs(z), 0.5 * W - fabs(a));
	}
}

static double slab_distance(const double p[3])
{
	double ox = fmax(0.0, fabs(p[0]) - 0.5 * SLAB_W), oy = fmax(0.0, fabs(p[1]) - 0.5 * SLAB_W);
	return sqrt(ox * ox + oy * oy + p[2] * p[2]);
}

/* Every inward ball of a torus stops on the core circle; area-uniform by
 * rejection on the tube angle. */
static void sample_torus(dp_rng *rng, double p[3], double n[3], double *depth)
{
	double t, f;
	do {
		t = 2 * PI * dp_rng_uniform(rng);
		f = 2 * PI * dp_rng_uniform(rng);
	} while (dp_rng_uniform(rng) * (TORUS_RC + TORUS_RHO) > TORUS_RC + TORUS_RHO * cos(f));
	n[0] = cos(f) * cos(t), n[1] = cos(f) * sin(t), n[2] = sin(f);
	p[0] = TORUS_RC * cos(t) + TORUS_RHO * n[0];
	p[1] = TORUS_RC * sin(t) + TORUS_RHO * n[1];
	p[2] = TORUS_RHO * n[2];
	*depth = TORUS_RHO;
}

static double torus_distance(const double p[3])
{
	return hypot(hypot(p[0], p[1]) - TORUS_RC, p[2]);
}

/* n anchors of the shape and r, the mean spacing of its surface samples. */
static dp_status make_anchors(sample_fn fn, size_t n, dp_cloud *anchors, double *r, dp_error *err)
{
	dp_cloud surf;
	double *depth = dp_alloc_array(n, sizeof *depth);
	if (!depth)
		return dp_fail(err, DP_ERR_NOMEM, "bench_skeleton: out of memory");
	dp_status st = dp_cloud_alloc(&surf, n, 0, err);
	if (st != DP_OK) {
		free(depth);
		return st;
	}
	if ((st = dp_cloud_alloc(anchors, n, 1, err)) != DP_OK) {
		dp_cloud_free(&surf);
		free(depth);
		return st;
	}
	dp_rng rng;
	dp_rng_seed(&rng, SEED);
	for (size_t i = 0; i < n; i++) {
		double p[3], nn[3];
		fn(&rng, p, nn, &depth[i]);
		surf.x[i] = (float)p[0], surf.y[i] = (float)p[1], surf.z[i] = (float)p[2];
		anchors->nx[i] = (float)nn[0], anchors->ny[i] = (float)nn[1], anchors->nz[i] = (float)nn[2];
	}
	if ((st = dp_mean_spacing(n, surf.x, surf.y, surf.z, r, err)) == DP_OK)
		for (size_t i = 0; i < n; i++) {
			double nn[3] = {anchors->nx[i], anchors->ny[i], anchors->nz[i]};
			double d = depth[i] * (1.0 + DEPTH_NOISE * dp_rng_normal(&rng));
			anchors->x[i] = (float)(surf.x[i] - d * nn[0] + JITTER_R * *r * dp_rng_normal(&rng));
			anchors->y[i] = (float)(surf.y[i] - d * nn[1] + JITTER_R * *r * dp_rng_normal(&rng));
			anchors->z[i] = (float)(surf.z[i] - d * nn[2] + JITTER_R * *r * dp_rng_normal(&rng));
			for (int c = 0; c < 3; c++)
				nn[c] += NORMAL_NOISE * dp_rng_normal(&rng);
			double len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
			anchors->nx[i] = (float)(nn[0] / len);
			anchors->ny[i] = (float)(nn[1] / len);
			anchors->nz[i] = (float)(nn[2] / len);
		}
	dp_cloud_free(&surf);
	free(depth);
	if (st != DP_OK)
		dp_cloud_free(anchors);
	return st;
}

static double mean_distance(const dp_cloud *q, skeleton_distance_fn dist)
{
	double total = 0.0;
	for (size_t i = 0; i < q->n; i++) {
		double p[3] = {q->x[i], q->y[i], q->z[i]};
		total += dist(p);
	}
	return total / (double)q->n;
}

static int run_stage(dp_context *ctx, const char *backend, const char *shape, const dp_cloud *h, double r,
		     skeleton_distance_fn dist, int iters)
{
	dp_skeleton_params p;
	dp_skeleton_params_default(&p);
	if (iters) {
		/* A window longer than the run and no move threshold: exactly iters. */
		p.max_iters = iters;
		p.window = iters + 1;
		p.min_move_r = 0.0;
	}
	dp_skeleton_stats s;
	dp_cloud q;
	dp_error err = {0};
	if (dp_skeleton(ctx, h, r, &p, &q, &s, &err) != DP_OK) {
		fprintf(stderr, "bench_skeleton: %s\n", err.message);
		return -1;
	}
	printf("{\"what\":\"skeleton\",\"shape\":\"%s\",\"size\":%zu,\"backend\":\"%s\",\"device\":\"%s\","
	       "\"seconds\":%.4f,\"iterations\":%d,\"pair_evals_per_s\":%.4g,\"pair_evaluations\":%.6g,"
	       "\"converged\":%d,\"last_mean_move_r\":%.4f,\"anchor_distance_r\":%.4f,\"skeleton_distance_r\":%.4f}\n",
	       shape, h->n, backend, dp_context_device_name(ctx), s.seconds, s.iterations,
	       s.seconds > 0 ? s.pair_evaluations / s.seconds : 0.0, s.pair_evaluations, s.converged,
	       s.last_mean_move, mean_distance(h, dist) / r, mean_distance(&q, dist) / r);
	fflush(stdout);
	dp_cloud_free(&q);
	return 0;
}

static int run_case(dp_context *cl, dp_context *ref, const options *o, const char *shape, sample_fn fn,
		    skeleton_distance_fn dist, size_t n)
{
	dp_error err = {0};
	dp_cloud h;
	double r;
	if (make_anchors(fn, n, &h, &r, &err) != DP_OK) {
		fprintf(stderr, "bench_skeleton: %s\n", err.message);
		return -1;
	}
	int rc = run_stage(cl, "cl", shape, &h, r, dist, o->iters);
	if (!rc && o->ref_max && n > o->ref_max) {
		printf("{\"what\":\"skeleton\",\"shape\":\"%s\",\"size\":%zu,\"backend\":\"ref\","
		       "\"skipped\":\"above --ref-max %zu\"}\n",
		       shape, n, o->ref_max);
		fflush(stdout);
	} else if (!rc) {
		rc = run_stage(ref, "ref", shape, &h, r, dist, o->iters);
	}
	dp_cloud_free(&h);
	return rc;
}

int main(int argc, char **argv)
{
	options o;
	if (parse_options(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_skeleton [--sizes N,...] [--shapes slab,torus] [--iters K] "
				"[--ref-max N] [--device D]\n");
		return 2;
	}
	dp_error err = {0};
	dp_context *cl = NULL, *ref = NULL;
	if (dp_context_create(&cl, DP_BACKEND_CL, o.device, &err) != DP_OK ||
	    dp_context_create(&ref, DP_BACKEND_REF, NULL, &err) != DP_OK) {
		fprintf(stderr, "bench_skeleton: %s\n", err.message);
		dp_context_free(cl);
		return 1;
	}
	int rc = 0;
	for (int i = 0; i < o.nsizes && !rc; i++) {
		if (o.slab)
			rc = run_case(cl, ref, &o, "slab", sample_slab, slab_distance, o.sizes[i]);
		if (!rc && o.torus)
			rc = run_case(cl, ref, &o, "torus", sample_torus, torus_distance, o.sizes[i]);
	}
	dp_context_free(cl);
	dp_context_free(ref);
	return rc ? 1 : 0;
}
