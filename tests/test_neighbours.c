/* The true-neighbour counts benchmarks print (backend/neighbours.c) are the
 * brute-force counts, per operator, and nothing is counted unless asked; the
 * dispatcher counts every launch once, by its row's RADIUS (and METRIC). */
#include "testkit.h"

#include "backend/neighbours.h"
#include "backend/ops.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NPOINTS 3000
#define NQUERY 400
#define EXTENT 6.0f
#define RADIUS 0.7f
/* the ellipsoid's semi-axes along x, y, z, in units of RADIUS */
static const float semi[3] = {1.0f, 0.5f, 2.0f};

typedef struct fixture {
	float *x, *y, *z, *qx, *qy, *qz;
	size_t n, m;
} fixture;

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 21);
	f->n = tk_random_points(&rng, NPOINTS, EXTENT, RADIUS, &f->x, &f->y, &f->z);
	f->m = tk_random_points(&rng, NQUERY, EXTENT, RADIUS, &f->qx, &f->qy, &f->qz);
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	float *arrays[] = {f->x, f->y, f->z, f->qx, f->qy, f->qz};
	for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
		free(arrays[i]);
	free(f);
	return 0;
}

/* Pairs with Σ_a (d_a / (s_a RADIUS))² below 1 (strictly when `strict`),
 * counted over every point in double; `border` gets those within 1e-5 of 1. */
static double brute_force(const fixture *f, const float s[3], int strict, double *border)
{
	double total = 0.0;
	*border = 0.0;
	for (size_t i = 0; i < f->m; i++)
		for (size_t k = 0; k < f->n; k++) {
			double d[3] = {f->qx[i] - f->x[k], f->qy[i] - f->y[k], f->qz[i] - f->z[k]}, u2 = 0.0;
			for (int a = 0; a < 3; a++)
				u2 += (d[a] / (s[a] * RADIUS)) * (d[a] / (s[a] * RADIUS));
			total += strict ? u2 < 1.0 : u2 <= 1.0;
			*border += fabs(u2 - 1.0) <= 1e-5;
		}
	return total;
}

static void test_counts_within_radius(void **state)
{
	fixture *f = *state;
	dp_grid g = {0};
	dp_error err = {0};
	assert_int_equal(dp_grid_build(&g, f->n, f->x, f->y, f->z, RADIUS, &err), DP_OK);
	dp_context *ctx = tk_ref_context();
	dp_count_neighbours(ctx, "off", &g, f->m, f->qx, f->qy, f->qz, RADIUS);
	dp_neighbour_counts counts;
	memset(&counts, 0, sizeof counts);
	ctx->neighbours = &counts;
	dp_count_neighbours(ctx, "op_a", &g, f->m, f->qx, f->qy, f->qz, RADIUS);
	dp_count_neighbours(ctx, "op_b", &g, f->m, f->qx, f->qy, f->qz, RADIUS);
	dp_count_neighbours(ctx, "op_a", &g, f->m, f->qx, f->qy, f->qz, RADIUS);
	ctx->neighbours = NULL;
	const float ball[3] = {1.0f, 1.0f, 1.0f};
	double border, want = brute_force(f, ball, 1, &border);
	assert_true(want > 10.0 * (double)f->m);
	assert_int_equal(counts.nops, 2); /* nothing recorded while off */
	assert_string_equal(counts.ops[0].name, "op_a");
	assert_true(counts.ops[0].launches == 2.0 && counts.ops[1].launches == 1.0);
	if (fabs(counts.ops[1].pairs - want) > border)
		fail_msg("counted %.0f pairs within the radius, brute force %.0f", counts.ops[1].pairs, want);
	assert_true(counts.ops[0].pairs == 2.0 * counts.ops[1].pairs);
	assert_true(counts.pairs == 3.0 * counts.ops[1].pairs);
	assert_true(fabs(counts.ops[0].radius_sum / counts.ops[0].launches - RADIUS) < 1e-6);
	assert_true(counts.ops[0].nq_sum == 2.0 * (double)f->m && counts.ops[0].ndata == f->n);
	dp_grid_free(&g);
}

/* The axis-aligned ellipsoid of every query: metric rows e_a / semi_a and
 * the reach just past its semi-axes times RADIUS. */
static void ellipsoid(size_t m, float *metric, float *reach)
{
	for (size_t i = 0; i < m; i++)
		for (int a = 0; a < 3; a++) {
			metric[9 * i + 4 * a] = 1.0f / semi[a];
			reach[3 * i + a] = semi[a] * RADIUS * 1.001f;
		}
}

/* An axis-aligned ellipsoid: metric rows e_a / semi_a, cutoff RADIUS. */
static void test_counts_inside_ellipsoid(void **state)
{
	fixture *f = *state;
	float *metric = calloc(9 * f->m, sizeof(float)), *reach = calloc(3 * f->m, sizeof(float));
	ellipsoid(f->m, metric, reach);
	dp_grid g = {0};
	dp_error err = {0};
	assert_int_equal(dp_grid_build_margin(&g, f->n, f->x, f->y, f->z, RADIUS, 3, &err), DP_OK);
	dp_context *ctx = tk_ref_context();
	dp_neighbour_counts counts;
	memset(&counts, 0, sizeof counts);
	ctx->neighbours = &counts;
	dp_count_neighbours_metric(ctx, "ellipsoid", &g, f->m, f->qx, f->qy, f->qz, metric, reach, RADIUS);
	ctx->neighbours = NULL;
	double border, want = brute_force(f, semi, 0, &border);
	assert_true(want > 10.0 * (double)f->m);
	if (fabs(counts.pairs - want) > border)
		fail_msg("counted %.0f pairs inside the ellipsoid, brute force %.0f", counts.pairs, want);
	double ball = cbrt((double)semi[0] * semi[1] * semi[2]) * RADIUS * 1.001;
	assert_true(fabs(counts.ops[0].radius_sum - ball) < 1e-4);
	dp_grid_free(&g);
	free(metric);
	free(reach);
}

/* Three rows through dp_op_*: a ball of radius h (WLOP's density), the
 * ellipsoid of test_counts_inside_ellipsoid (skeleton_median's METRIC and
 * cutoff) and the peak's ball; each launch recorded once under its kernel. */
static void test_dispatcher_counts_by_row(void **state)
{
	fixture *f = *state;
	size_t m = f->m;
	float *metric = calloc(9 * m, sizeof(float)), *reach = calloc(3 * m, sizeof(float));
	float *out = calloc(3 * m, sizeof(float)), *sum = calloc(m, sizeof(float));
	assert_true(metric && reach && out && sum);
	ellipsoid(m, metric, reach);
	dp_grid g = {0};
	dp_error err = {0};
	assert_int_equal(dp_grid_build_margin(&g, f->n, f->x, f->y, f->z, RADIUS, 3, &err), DP_OK);
	dp_density_args density = {.nq = m, .qx = f->qx, .qy = f->qy, .qz = f->qz, .data = &g, .h = RADIUS,
				    .theta_k = 1.0f, .min_d2 = 0.0f, .sqrt_density = 0, .out = out};
	dp_skeleton_median_args median = {.nq = m, .qx = f->qx, .qy = f->qy, .qz = f->qz, .metric = metric,
					  .reach = reach, .data = &g, .cutoff = RADIUS, .min_d2 = 0.0f,
					  .median = out};
	dp_peak_args peak = {.nq = m, .qx = f->qx, .qy = f->qy, .qz = f->qz, .data = &g, .radius = RADIUS,
			     .reach = 1, .count = out, .sum = sum};
	dp_context *ctx = tk_ref_context();
	dp_neighbour_counts counts;
	memset(&counts, 0, sizeof counts);
	ctx->neighbours = &counts;
	assert_int_equal(dp_op_density(ctx, &density, &err), DP_OK);
	assert_int_equal(dp_op_skeleton_median(ctx, &median, &err), DP_OK);
	assert_int_equal(dp_op_peak(ctx, &peak, &err), DP_OK);
	ctx->neighbours = NULL;
	assert_int_equal(dp_op_density(ctx, &density, &err), DP_OK);
	const float ball[3] = {1.0f, 1.0f, 1.0f};
	double ball_border, ball_want = brute_force(f, ball, 1, &ball_border);
	double ell_border, ell_want = brute_force(f, semi, 0, &ell_border);
	assert_int_equal(counts.nops, 3);
	const char *names[3] = {"wlop_density", "skeleton_median", "peak_pairs"};
	const double want[3] = {ball_want, ell_want, ball_want}, border[3] = {ball_border, ell_border, ball_border};
	for (int k = 0; k < 3; k++) {
		assert_string_equal(counts.ops[k].name, names[k]);
		assert_true(counts.ops[k].launches == 1.0);
		if (fabs(counts.ops[k].pairs - want[k]) > border[k])
			fail_msg("%s: counted %.0f pairs, brute force %.0f", names[k], counts.ops[k].pairs, want[k]);
	}
	assert_true(fabs(counts.ops[0].radius_sum - RADIUS) < 1e-6);
	dp_grid_free(&g);
	free(metric);
	free(reach);
	free(out);
	free(sum);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_counts_within_radius),
		cmocka_unit_test(test_counts_inside_ellipsoid),
		cmocka_unit_test(test_dispatcher_counts_by_row),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
