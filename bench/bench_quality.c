/* Issue 3's "Done means" numbers for the whole pipeline: raw noisy inputs made
 * from the analytic shapes (complete samples or one scanner view), through
 * dp_consolidate with default parameters (only the sample count set), measured
 * with the analytic distance functions. Prints one JSON line per target
 * (measured, threshold, pass) and, per case, one line per stage (WLOP samples,
 * anchors, skeleton, surface) with the same measures, to show which stage
 * loses the accuracy (the one-view sphere's coverage: WLOP covers only the
 * seen half, as it must, and the surface stage stops spreading at its
 * convergence test; see tests/test_pipeline.c for the numbers).
 * tests/test_pipeline.c asserts the targets that pass;
 * the measures here are the same (see the comments there for their
 * definitions). Usage: bench_quality [--seed S] [--samples M] [--noise F]
 * [--device D]; the defaults are the test's. */
#include "dpoints.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Raw-input noise, in bbox diagonals (issue 3 asks for noisy inputs; the
 * middle of the 0.2-0.5% range the tests use). */
#define NOISE 0.003
/* Raw points and deep points per case: the test's sizes. */
#define RAW_POINTS 12000
#define SAMPLES 2000
#define SEED 7
/* One-view scans: a res x res ray grid gives about 10K hits on these shapes. */
#define SCAN_RES 200
/* Spread measures: a skeleton point counts towards the span/area/circle when
 * it lies within this fraction of the tube radius / half-thickness of the
 * ideal skeleton. */
#define NEAR_FRACTION 0.5
/* Cylinder axis bins and slab cells: about one R or T each. */
#define AXIS_BINS 8
#define SLAB_CELLS 10

typedef struct options {
	uint64_t seed;
	size_t samples;
	double noise;
	const char *device;
} options;

typedef enum target_kind { SPHERE, CYLINDER, SLAB, TORUS, SCAN_SPHERE, SCAN_TORUS } target_kind;

static const char *case_name[] = {"sphere", "cylinder", "slab", "torus", "scan_sphere", "scan_torus"};

static double mean_distance(const dp_shape *s, const dp_cloud *c, int skeleton)
{
	double sum = 0;
	for (size_t i = 0; i < c->n; i++) {
		double p[3] = {c->x[i], c->y[i], c->z[i]};
		sum += skeleton ? dp_shape_skeleton_distance(s, p) : dp_shape_surface_distance(s, p);
	}
	return sum / (double)c->n;
}

/* Fraction of the axis (AXIS_BINS bins over |z| <= L/2) holding a point
 * within NEAR_FRACTION R of the axis. */
static double axis_span(const dp_shape *s, const dp_cloud *c)
{
	int hit[AXIS_BINS] = {0}, count = 0;
	for (size_t i = 0; i < c->n; i++) {
		double z = c->z[i], rr = hypot(c->x[i], c->y[i]);
		int b = (int)floor((z / s->length + 0.5) * AXIS_BINS);
		if (rr <= NEAR_FRACTION * s->radius && b >= 0 && b < AXIS_BINS)
			hit[b] = 1;
	}
	for (int b = 0; b < AXIS_BINS; b++)
		count += hit[b];
	return (double)count / AXIS_BINS;
}

/* Fraction of SLAB_CELLS^2 cells of the mid-plane holding a point within
 * NEAR_FRACTION T/2 of it. */
static double slab_area(const dp_shape *s, const dp_cloud *c)
{
	int hit[SLAB_CELLS][SLAB_CELLS] = {{0}}, count = 0;
	for (size_t i = 0; i < c->n; i++) {
		int u = (int)floor((c->x[i] / s->width + 0.5) * SLAB_CELLS);
		int v = (int)floor((c->y[i] / s->width + 0.5) * SLAB_CELLS);
		if (fabs(c->z[i]) <= NEAR_FRACTION * s->thickness / 2 && u >= 0 && u < SLAB_CELLS && v >= 0 &&
		    v < SLAB_CELLS)
			hit[u][v] = 1;
	}
	for (int u = 0; u < SLAB_CELLS; u++)
		for (int v = 0; v < SLAB_CELLS; v++)
			count += hit[u][v];
	return (double)count / (SLAB_CELLS * SLAB_CELLS);
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* Longest gap along the core circle between points within NEAR_FRACTION rho
 * of it, as a fraction of the circle (1 when none is near). */
static double torus_gap(const dp_shape *s, const dp_cloud *c)
{
	double *a = malloc(c->n * sizeof *a), gap = 1;
	size_t m = 0;
	if (!a)
		return NAN;
	for (size_t i = 0; i < c->n; i++) {
		double p[3] = {c->x[i], c->y[i], c->z[i]};
		if (dp_shape_skeleton_distance(s, p) <= NEAR_FRACTION * s->tube)
			a[m++] = atan2(p[1], p[0]);
	}
	if (m > 0) {
		qsort(a, m, sizeof *a, cmp_double);
		gap = a[0] + 2 * M_PI - a[m - 1];
		for (size_t i = 1; i < m; i++)
			gap = fmax(gap, a[i] - a[i - 1]);
		gap /= 2 * M_PI;
	}
	free(a);
	return gap;
}

static double coverage(const dp_cloud *mesh, const dp_cloud *c)
{
	dp_eval_result r;
	dp_error err = {0};
	if (dp_eval(mesh, c, NULL, &r, &err) != DP_OK) {
		fprintf(stderr, "bench_quality: %s\n", err.message);
		return NAN;
	}
	return r.coverage;
}

static void target(const char *name, double measured, double threshold, int at_least)
{
	int pass = at_least ? measured >= threshold : measured < threshold;
	printf("{\"bench\":\"quality\",\"target\":\"%s\",\"measured\":%.4f,\"threshold\":\"%s %g\",\"pass\":%s}\n",
	       name, measured, at_least ? ">=" : "<", threshold, pass ? "true" : "false");
}

/* The shape's unit (R, T or rho) in which distances are reported. */
static double unit_of(const dp_shape *s)
{
	switch (s->kind) {
	case DP_SHAPE_SLAB:
		return s->thickness;
	case DP_SHAPE_TORUS:
		return s->tube;
	default:
		return s->radius;
	}
}

static void stage_line(target_kind k, const char *stage, const dp_shape *s, const dp_cloud *mesh,
		       const dp_cloud *c)
{
	double u = unit_of(s);
	printf("{\"bench\":\"quality\",\"case\":\"%s\",\"stage\":\"%s\",\"n\":%zu,\"surface_mean\":%.4f,"
	       "\"skeleton_mean\":%.4f",
	       case_name[k], stage, c->n, mean_distance(s, c, 0) / u, mean_distance(s, c, 1) / u);
	if (s->kind == DP_SHAPE_CYLINDER)
		printf(",\"axis_span\":%.3f", axis_span(s, c));
	if (s->kind == DP_SHAPE_SLAB)
		printf(",\"slab_area\":%.3f", slab_area(s, c));
	if (s->kind == DP_SHAPE_TORUS)
		printf(",\"circle_gap\":%.3f", torus_gap(s, c));
	if (c->n >= 2 && (!strcmp(stage, "input") || !strcmp(stage, "wlop") || !strcmp(stage, "surface")))
		printf(",\"coverage\":%.3f", coverage(mesh, c));
	printf("}\n");
}

static int make_shape(target_kind k, dp_shape *s, dp_error *err)
{
	static const char *kind[] = {"sphere", "cylinder", "slab", "torus", "sphere", "torus"};
	if (dp_shape_default(kind[k], s, err) != DP_OK)
		return -1;
	return 0;
}

static int make_input(const options *o, target_kind k, const dp_cloud *mesh, dp_cloud *in, dp_error *err)
{
	if (k == SCAN_SPHERE || k == SCAN_TORUS) {
		dp_scan_params sp;
		dp_scan_params_default(&sp);
		sp.views = 1;
		sp.res = SCAN_RES;
		sp.noise = o->noise;
		sp.normals = 0;
		sp.seed = o->seed;
		return dp_scan(mesh, &sp, in, NULL, err) == DP_OK ? 0 : -1;
	}
	return dp_mesh_sample(mesh, RAW_POINTS, o->noise, o->seed, in, err) == DP_OK ? 0 : -1;
}

static int run_case(const options *o, dp_context *ctx, target_kind k)
{
	dp_shape s;
	dp_cloud mesh = {0}, in = {0};
	dp_result res = {0};
	dp_params params;
	dp_error err = {0};
	int rc = -1;
	if (make_shape(k, &s, &err) || dp_shape_mesh(&s, &mesh, &err) != DP_OK || make_input(o, k, &mesh, &in, &err))
		goto out;
	dp_params_default(&params);
	params.wlop.samples = o->samples;
	if (dp_consolidate(ctx, &in, &params, &res, &err) != DP_OK)
		goto out;
	double u = unit_of(&s);
	printf("{\"bench\":\"quality\",\"case\":\"%s\",\"seed\":%llu,\"noise\":%g,\"raw\":%zu,\"samples\":%zu,"
	       "\"r\":%.5f,\"r_per_unit\":%.4f,\"sink_iterations\":%d,\"skeleton_iterations\":%d,"
	       "\"surface_iterations\":%d,\"surface_converged\":%d,\"seconds\":%.2f}\n",
	       case_name[k], (unsigned long long)o->seed, o->noise, in.n, res.wlop.n, res.r, res.r / u,
	       res.sink_stats.iterations, res.skeleton_stats.iterations, res.surface_stats.iterations,
	       res.surface_stats.converged, res.seconds_total);
	stage_line(k, "input", &s, &mesh, &in);
	stage_line(k, "wlop", &s, &mesh, &res.wlop);
	stage_line(k, "anchors", &s, &mesh, &res.anchors);
	stage_line(k, "skeleton", &s, &mesh, &res.skeleton);
	stage_line(k, "surface", &s, &mesh, &res.surface);
	switch (k) {
	case SPHERE:
		target("sphere.skeleton_mean_R", mean_distance(&s, &res.skeleton, 1) / u, 0.15, 0);
		target("sphere.surface_mean_R", mean_distance(&s, &res.surface, 0) / u, 0.01, 0);
		break;
	case CYLINDER:
		target("cylinder.skeleton_mean_R", mean_distance(&s, &res.skeleton, 1) / u, 0.25, 0);
		target("cylinder.axis_span", axis_span(&s, &res.skeleton), 0.70, 1);
		break;
	case SLAB:
		target("slab.skeleton_mean_T", mean_distance(&s, &res.skeleton, 1) / u, 0.25, 0);
		target("slab.area", slab_area(&s, &res.skeleton), 0.60, 1);
		break;
	case TORUS:
		target("torus.skeleton_mean_rho", mean_distance(&s, &res.skeleton, 1) / u, 0.25, 0);
		target("torus.circle_gap", torus_gap(&s, &res.skeleton), 0.10, 0);
		break;
	case SCAN_SPHERE:
	case SCAN_TORUS:
		target(k == SCAN_SPHERE ? "scan_sphere.coverage" : "scan_torus.coverage", coverage(&mesh, &res.surface),
		       0.90, 1);
		target(k == SCAN_SPHERE ? "scan_sphere.surface_mean_R" : "scan_torus.surface_mean_rho",
		       mean_distance(&s, &res.surface, 0) / u, 0.05, 0);
		break;
	}
	rc = 0;
out:
	if (rc)
		fprintf(stderr, "bench_quality: %s: %s\n", case_name[k], err.message);
	dp_result_free(&res);
	dp_cloud_free(&in);
	dp_cloud_free(&mesh);
	return rc;
}

static int parse(int argc, char **argv, options *o)
{
	o->seed = SEED;
	o->samples = SAMPLES;
	o->noise = NOISE;
	o->device = NULL;
	for (int i = 1; i + 1 < argc; i += 2) {
		char *end;
		if (!strcmp(argv[i], "--seed"))
			o->seed = strtoull(argv[i + 1], &end, 10);
		else if (!strcmp(argv[i], "--samples"))
			o->samples = strtoull(argv[i + 1], &end, 10);
		else if (!strcmp(argv[i], "--noise"))
			o->noise = strtod(argv[i + 1], &end);
		else if (!strcmp(argv[i], "--device"))
			end = "", o->device = argv[i + 1];
		else
			return -1;
		if (*end)
			return -1;
	}
	return argc % 2 ? 0 : -1;
}

int main(int argc, char **argv)
{
	dp_context *ctx = NULL;
	dp_error err = {0};
	options o;
	int rc = 0;
	if (parse(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_quality [--seed S] [--samples M] [--noise F] [--device D]\n");
		return 2;
	}
	if (dp_context_create(&ctx, DP_BACKEND_CL, o.device, &err) != DP_OK) {
		fprintf(stderr, "bench_quality: %s\n", err.message);
		return 1;
	}
	for (int k = SPHERE; k <= SCAN_TORUS; k++)
		rc |= run_case(&o, ctx, (target_kind)k);
	dp_context_free(ctx);
	return rc ? 1 : 0;
}
