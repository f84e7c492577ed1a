/* The whole pipeline (dp_consolidate, OpenCL backend, default parameters but
 * the sample count) on raw noisy inputs made from the analytic shapes,
 * measured against them: issue 3's "Done means", thresholds as the issue
 * states them. Complete shapes are area-uniform samples of the mesh with
 * Gaussian noise; the one-sided cases are a single view of the virtual
 * scanner, with noise. The 1500 deep points are kept from the coarse level's
 * 4000 (dp_refine_params: a count below it is an even subset of it);
 * bench/bench_quality_sizes.c prints the same numbers at 1500, 3000 and
 * 4000, every target held (README has them). */
#include "testkit.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Noise sigma per coordinate, in bbox diagonals: 0.01 R on the sphere,
 * 0.037 rho on the torus (the raw points lie about 0.8 sigma off the
 * surface on average). */
#define NOISE 0.003
#define RAW_POINTS 12000
#define SAMPLES 1500
/* One view of res x res rays: about 6400 hits on the sphere, 4700 on the torus. */
#define SCAN_RES 160
#define SEED 7
/* The issue asks for a cylinder of length >= 8 R; at 8 R the ideal curve
 * (the medial axis stops R short of each flat cap) spans only 75%. */
#define CYLINDER_LENGTH_R 10.0
/* Resolution of the spread measures, in the shape's unit (R, T, rho): a
 * skeleton point covers half a unit of the cylinder's axis; slab cells are
 * T x T. */
#define CURVE_CELL 0.5
#define SLAB_CELL 1.0
/* "the input covers about half": the one-view scan's coverage at the
 * output's radius must lie in this band, or the case tests something else. */
#define HALF_LOW 0.35
#define HALF_HIGH 0.65

typedef enum input_kind { COMPLETE, ONE_VIEW } input_kind;

typedef struct run {
	dp_shape shape;
	dp_cloud mesh, input;
	dp_result res;
	double unit; /* R, T or rho */
} run;

static void run_pipeline_with(const char *name, input_kind kind, const dp_params *params, run *r)
{
	dp_error err = {0};
	memset(r, 0, sizeof *r);
	assert_int_equal(dp_shape_default(name, &r->shape, &err), DP_OK);
	if (r->shape.kind == DP_SHAPE_CYLINDER)
		r->shape.length = CYLINDER_LENGTH_R * r->shape.radius;
	r->unit = r->shape.kind == DP_SHAPE_SLAB ? r->shape.thickness
		  : r->shape.kind == DP_SHAPE_TORUS ? r->shape.tube
						     : r->shape.radius;
	assert_int_equal(dp_shape_mesh(&r->shape, &r->mesh, &err), DP_OK);
	if (kind == COMPLETE) {
		assert_int_equal(dp_mesh_sample(&r->mesh, RAW_POINTS, NOISE, SEED, &r->input, &err), DP_OK);
	} else {
		dp_scan_params sp;
		dp_scan_params_default(&sp);
		sp.views = 1;
		sp.res = SCAN_RES;
		sp.noise = NOISE;
		sp.normals = 0;
		sp.seed = SEED;
		assert_int_equal(dp_scan(&r->mesh, &sp, &r->input, NULL, &err), DP_OK);
	}
	dp_params p = *params;
	p.wlop.samples = SAMPLES;
	dp_status st = dp_consolidate(tk_cl_context(), &r->input, &p, &r->res, &err);
	if (st != DP_OK)
		fail_msg("%s: %s", name, err.message);
	printf("%s: %zu raw -> %zu deep points, r = %.4f (%.2f r per unit); iterations wlop %d sink %d skeleton %d "
	       "surface %d; %.2f s\n",
	       name, r->input.n, r->res.wlop.n, r->res.r, r->unit / r->res.r, r->res.wlop_stats.iterations,
	       r->res.sink_stats.iterations, r->res.skeleton_stats.iterations, r->res.surface_stats.iterations,
	       r->res.seconds_total);
}

static void run_pipeline(const char *name, input_kind kind, run *r)
{
	dp_params p;
	dp_params_default(&p);
	run_pipeline_with(name, kind, &p, r);
}

static void run_free(run *r)
{
	dp_result_free(&r->res);
	dp_cloud_free(&r->input);
	dp_cloud_free(&r->mesh);
}

static dp_shape_fit fit(const run *r, const dp_cloud *points, double cell)
{
	dp_shape_fit f;
	dp_error err = {0};
	assert_int_equal(dp_shape_fit_points(&r->shape, points, cell * r->unit, &f, &err), DP_OK);
	return f;
}

/* The issue's thresholds are strict: measured < limit. */
static void expect_below(const char *what, double measured, double limit)
{
	printf("  %-40s %.4f (target < %g)\n", what, measured, limit);
	if (!(measured < limit))
		fail_msg("%s = %.4f, not below %g", what, measured, limit);
}

static void expect_at_least(const char *what, double measured, double limit)
{
	printf("  %-40s %.4f (target >= %g)\n", what, measured, limit);
	if (!(measured >= limit))
		fail_msg("%s = %.4f, below %g", what, measured, limit);
}

static void test_sphere(void **state)
{
	(void)state;
	run r;
	run_pipeline("sphere", COMPLETE, &r);
	expect_below("skeleton distance to the centre / R", fit(&r, &r.res.skeleton, CURVE_CELL).skeleton_mean / r.unit,
		     0.15);
	expect_below("surface distance to the sphere / R", fit(&r, &r.res.surface, CURVE_CELL).surface_mean / r.unit,
		     0.01);
	run_free(&r);
}

/* A complete scan has nothing to fill: the surface stage comes to rest
 * (dpoints.h, min_move_r) well before the mean move and the spacing's
 * variation stop falling by a few per cent per window, and as accurately. */
static void test_sphere_rest(void **state)
{
	(void)state;
	dp_params p;
	dp_params_default(&p);
	run rest, creep;
	run_pipeline_with("sphere", COMPLETE, &p, &rest);
	p.surface.min_move_r = 0.0;
	run_pipeline_with("sphere", COMPLETE, &p, &creep);
	double d_rest = fit(&rest, &rest.res.surface, CURVE_CELL).surface_mean / rest.unit;
	double d_creep = fit(&creep, &creep.res.surface, CURVE_CELL).surface_mean / creep.unit;
	printf("  surface iterations at rest %d (converged %d), without the rest test %d (converged %d); "
	       "distance to the sphere / R %.5f and %.5f\n",
	       rest.res.surface_stats.iterations, rest.res.surface_stats.converged, creep.res.surface_stats.iterations,
	       creep.res.surface_stats.converged, d_rest, d_creep);
	assert_int_equal(rest.res.surface_stats.converged, 1);
	/* only the rest test can stop within two windows */
	assert_true(rest.res.surface_stats.iterations < 2 * p.surface.window);
	assert_true(rest.res.surface_stats.iterations + p.surface.window < creep.res.surface_stats.iterations);
	expect_below("surface distance to the sphere / R at rest", d_rest, fmin(0.01, d_creep + 0.001));
	run_free(&rest);
	run_free(&creep);
}

static void test_cylinder(void **state)
{
	(void)state;
	run r;
	run_pipeline("cylinder", COMPLETE, &r);
	dp_shape_fit f = fit(&r, &r.res.skeleton, CURVE_CELL);
	expect_below("skeleton distance to the axis / R", f.skeleton_mean / r.unit, 0.25);
	expect_at_least("fraction of the length spanned", f.spread, 0.70);
	run_free(&r);
}

static void test_slab(void **state)
{
	(void)state;
	run r;
	run_pipeline("slab", COMPLETE, &r);
	dp_shape_fit f = fit(&r, &r.res.skeleton, SLAB_CELL);
	expect_below("skeleton distance to the mid-plane / T", f.skeleton_mean / r.unit, 0.25);
	expect_at_least("fraction of the mid-plane (T x T cells)", f.spread, 0.60);
	run_free(&r);
}

static void test_torus(void **state)
{
	(void)state;
	run r;
	run_pipeline("torus", COMPLETE, &r);
	dp_shape_fit f = fit(&r, &r.res.skeleton, CURVE_CELL);
	expect_below("skeleton distance to the core circle / rho", f.skeleton_mean / r.unit, 0.25);
	expect_below("largest gap / circle length", f.largest_gap, 0.10);
	run_free(&r);
}

/* One view: the output covers the whole surface at the right distance, the
 * input about half of it (measured at the output's coverage radius). */
static void one_view(const char *name)
{
	run r;
	run_pipeline(name, ONE_VIEW, &r);
	dp_error err = {0};
	dp_eval_result out, in;
	assert_int_equal(dp_eval(&r.mesh, &r.res.surface, NULL, &out, &err), DP_OK);
	assert_int_equal(dp_eval(&r.mesh, &r.input, NULL, &in, &err), DP_OK);
	dp_eval_params ep;
	dp_eval_params_default(&ep);
	ep.coverage_factor *= out.spacing_mean / in.spacing_mean;
	assert_int_equal(dp_eval(&r.mesh, &r.input, &ep, &in, &err), DP_OK);
	printf("  input coverage at the output's radius     %.4f (about half: [%g, %g])\n", in.coverage, HALF_LOW,
	       HALF_HIGH);
	assert_true(in.coverage >= HALF_LOW && in.coverage <= HALF_HIGH);
	expect_at_least("surface coverage", out.coverage, 0.90);
	expect_below("surface distance to the true surface / unit",
		     fit(&r, &r.res.surface, CURVE_CELL).surface_mean / r.unit, 0.05);
	run_free(&r);
}

static void test_sphere_one_view(void **state)
{
	(void)state;
	one_view("sphere");
}

static void test_torus_one_view(void **state)
{
	(void)state;
	one_view("torus");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_sphere),	cmocka_unit_test(test_sphere_rest), cmocka_unit_test(test_cylinder),
		cmocka_unit_test(test_slab),	cmocka_unit_test(test_torus),
		cmocka_unit_test(test_sphere_one_view), cmocka_unit_test(test_torus_one_view),
	};
	int rc = cmocka_run_group_tests(tests, NULL, NULL);
	tk_teardown_contexts(NULL);
	return rc;
}
