/* The peak kernel (peak_pairs, kernels/peak.cl) equals its scalar reference
 * (host/ref/peak_ref.c) on grids of 1, 2 and 3 cells per radius, and the
 * reference's count is the true number of points within the radius. */
#include "testkit.h"

#include "backend/ops.h"

#include <math.h>
#include <stdlib.h>

#define NDATA 5000
#define NQUERY 700
#define EXTENT 8.0f
#define RADIUS 0.9f
#define MAX_REACH 3
#define RTOL 1e-4f
/* Pairs whose d² lies this close to radius² (relatively) may fall on either
 * side on the device, whose arithmetic may contract or reorder; they are
 * excused from the exact count, and nothing else is. */
#define BORDER_REL 1e-5

typedef struct fixture {
	float *x, *y, *z;
	size_t n;
	float *qx, *qy, *qz;
	size_t m;
	float *count_ref, *count_cl, *sum_ref, *sum_cl;
} fixture;

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 8);
	/* border points on the cells of the finest grid, the hardest case */
	f->n = tk_random_points(&rng, NDATA, EXTENT, RADIUS / MAX_REACH, &f->x, &f->y, &f->z);
	f->m = tk_random_points(&rng, NQUERY, EXTENT, RADIUS / MAX_REACH, &f->qx, &f->qy, &f->qz);
	f->count_ref = malloc(f->m * sizeof(float));
	f->count_cl = malloc(f->m * sizeof(float));
	f->sum_ref = malloc(f->m * sizeof(float));
	f->sum_cl = malloc(f->m * sizeof(float));
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	float *arrays[] = {f->x, f->y, f->z, f->qx, f->qy, f->qz, f->count_ref, f->count_cl, f->sum_ref, f->sum_cl};
	for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
		free(arrays[i]);
	free(f);
	return 0;
}

/* Brute force over every point: the number of points within the radius of
 * query i and how many of them lie within BORDER_REL of it. */
static void true_count(const fixture *f, size_t i, size_t *within, size_t *border)
{
	double r2 = (double)RADIUS * RADIUS;
	*within = *border = 0;
	for (size_t k = 0; k < f->n; k++) {
		float dx = f->qx[i] - f->x[k], dy = f->qy[i] - f->y[k], dz = f->qz[i] - f->z[k];
		double d2 = (double)(dx * dx + dy * dy + dz * dz);
		*within += d2 < r2;
		*border += fabs(d2 - r2) <= BORDER_REL * r2;
	}
}

/* exact: the grid must have the cells asked for (else the cap on cells per
 * point may have grown them, and the scan covers the radius in fewer). */
static void check_reach(fixture *f, int reach, int exact)
{
	dp_grid g = {0};
	dp_error err = {0};
	int cells = 0;
	assert_int_equal(dp_peak_grid(&g, f->n, f->x, f->y, f->z, RADIUS, reach, &cells, &err), DP_OK);
	assert_true(cells >= 1 && cells <= reach);
	if (exact)
		assert_int_equal(cells, reach);
	dp_peak_args a = {.data = &g, .nq = f->m, .qx = f->qx, .qy = f->qy, .qz = f->qz, .radius = RADIUS,
			  .reach = cells, .count = f->count_ref, .sum = f->sum_ref};
	assert_int_equal(dp_op_peak(tk_ref_context(), &a, &err), DP_OK);
	a.count = f->count_cl;
	a.sum = f->sum_cl;
	if (dp_op_peak(tk_cl_context(), &a, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t total = 0;
	for (size_t i = 0; i < f->m; i++) {
		size_t within, border;
		true_count(f, i, &within, &border);
		total += within;
		double slack = (double)border;
		if (fabs((double)f->count_ref[i] - (double)within) > slack)
			fail_msg("reach %d, query %zu: reference counts %.0f, %zu lie within the radius", reach, i,
				 (double)f->count_ref[i], within);
		if (fabs((double)f->count_cl[i] - (double)f->count_ref[i]) > slack)
			fail_msg("reach %d, query %zu: kernel counts %.0f, reference %.0f", reach, i,
				 (double)f->count_cl[i], (double)f->count_ref[i]);
	}
	/* the fixture must exercise the sums: most queries have neighbours */
	assert_true(total > 10 * f->m);
	/* a border pair adds at most exp(-1) to the sum */
	for (size_t i = 0; i < f->m; i++) {
		size_t within, border;
		true_count(f, i, &within, &border);
		double tol = RTOL * fabs((double)f->sum_ref[i]) + 1e-6 + (double)border;
		if (!(fabs((double)f->sum_cl[i] - (double)f->sum_ref[i]) <= tol))
			fail_msg("reach %d, query %zu: sum %.9g vs reference %.9g", reach, i, (double)f->sum_cl[i],
				 (double)f->sum_ref[i]);
	}
	dp_grid_free(&g);
}

static void test_reach_1(void **state) { check_reach(*state, 1, 1); }
static void test_reach_2(void **state) { check_reach(*state, 2, 1); }
/* the far point of the fixture makes 3 cells per radius exceed the cap */
static void test_reach_3(void **state) { check_reach(*state, 3, 0); }

/* A reach beyond the grid's margin would read outside it: refused. */
static void test_reach_beyond_margin(void **state)
{
	fixture *f = *state;
	dp_grid g = {0};
	dp_error err = {0};
	int cells = 0;
	assert_int_equal(dp_peak_grid(&g, f->n, f->x, f->y, f->z, RADIUS, 1, &cells, &err), DP_OK);
	dp_peak_args a = {.data = &g, .nq = f->m, .qx = f->qx, .qy = f->qy, .qz = f->qz, .radius = RADIUS,
			  .reach = 2, .count = f->count_cl, .sum = f->sum_cl};
	assert_int_equal(dp_op_peak(tk_cl_context(), &a, &err), DP_ERR_ARG);
	assert_int_equal(dp_op_peak(tk_ref_context(), &a, &err), DP_ERR_ARG);
	dp_grid_free(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_reach_1),
		cmocka_unit_test(test_reach_2),
		cmocka_unit_test(test_reach_3),
		cmocka_unit_test(test_reach_beyond_margin),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
