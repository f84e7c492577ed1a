/* The uniform grid's 27-cell neighbour sets equal FLANN's exact radius search. */
#include "testkit.h"

#include "grid/grid.h"
#include "knn/knn.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Compares, for every query, the set {k : |q - p_k| < radius} found by
 * scanning the grid rows with the one FLANN returns. */
static void check_against_flann(size_t n, const float *x, const float *y, const float *z, float radius,
				size_t nq, const float *qx, const float *qy, const float *qz)
{
	dp_error err = {0};
	dp_grid g = {0};
	assert_int_equal(dp_grid_build(&g, n, x, y, z, radius, &err), DP_OK);
	assert_true(g.cell >= radius);
	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, n, x, y, z, &err), DP_OK);
	int *fidx = malloc(n * sizeof *fidx);
	float *fd2 = malloc(n * sizeof *fd2);
	char *mark = calloc(n, 1);
	float r2 = radius * radius;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < nq; i++) {
		int nf = dp_knn_radius(&knn, qx[i], qy[i], qz[i], r2, fidx, fd2, (int)n);
		int strict = 0;
		for (int j = 0; j < nf; j++)
			if (fd2[j] < r2) {
				mark[fidx[j]] = 1;
				strict++;
			}
		int found = 0;
		dp_grid_rows(&g, qx[i], qy[i], qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = qx[i] - g.x[k], dy = qy[i] - g.y[k], dz = qz[i] - g.z[k];
				if (dx * dx + dy * dy + dz * dz < r2) {
					uint32_t orig = g.perm[k];
					if (!mark[orig])
						fail_msg("query %zu: grid finds %u which FLANN does not", i, orig);
					mark[orig] = 2;
					found++;
				}
			}
		if (found != strict)
			fail_msg("query %zu: grid finds %d neighbours, FLANN %d", i, found, strict);
		for (int j = 0; j < nf; j++)
			mark[fidx[j]] = 0;
	}
	free(fidx);
	free(fd2);
	free(mark);
	dp_knn_free(&knn);
	dp_grid_free(&g);
}

static void test_random(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 7);
	float *x, *y, *z;
	size_t n = tk_random_points(&rng, 3000, 10.0f, 0.7f, &x, &y, &z);
	check_against_flann(n, x, y, z, 0.7f, n, x, y, z);
	/* queries outside the grid's box and far away */
	float qx[] = {-0.3f, 10.4f, -50.0f, 5.0f, 1e6f}, qy[] = {5.0f, 10.6f, 5.0f, -0.69f, 0.0f},
	      qz[] = {5.0f, 10.2f, 5.0f, 3.0f, 0.0f};
	check_against_flann(n, x, y, z, 0.7f, 5, qx, qy, qz);
	free(x);
	free(y);
	free(z);
}

static void test_clustered_and_duplicates(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	size_t n = 2000;
	float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z);
	for (size_t i = 0; i < n; i++) {
		int c = (int)(i % 4);
		x[i] = (float)(c * 3 + dp_rng_normal(&rng) * 0.1);
		y[i] = (float)(dp_rng_normal(&rng) * 0.1);
		z[i] = (float)(c + dp_rng_normal(&rng) * 0.1);
		if (i % 10 == 0 && i) {
			x[i] = x[i - 1];
			y[i] = y[i - 1];
			z[i] = z[i - 1];
		}
	}
	check_against_flann(n, x, y, z, 0.15f, n, x, y, z);
	free(x);
	free(y);
	free(z);
}

static void test_planar_and_single(void **state)
{
	(void)state;
	size_t n = 900;
	float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = calloc(n, sizeof *z);
	for (size_t i = 0; i < n; i++) {
		x[i] = (float)(i % 30) * 0.1f;
		y[i] = (float)(i / 30) * 0.1f;
	}
	/* radius exactly a lattice step: points on cell borders, strict test */
	check_against_flann(n, x, y, z, 0.1f, n, x, y, z);
	check_against_flann(n, x, y, z, 0.25f, n, x, y, z);
	float sx = 1.0f, sy = 2.0f, sz = 3.0f;
	check_against_flann(1, &sx, &sy, &sz, 0.5f, 1, &sx, &sy, &sz);
	free(x);
	free(y);
	free(z);
}

static void test_rebuild_reuses_and_caps(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_grid g = {0};
	float x[2] = {0.0f, 1e5f}, y[2] = {0.0f, 1e5f}, z[2] = {0.0f, 1e5f};
	assert_int_equal(dp_grid_build(&g, 2, x, y, z, 0.01f, &err), DP_OK);
	assert_true(g.ncells <= DP_GRID_MAX_CELLS);
	assert_int_equal(g.cell_count[dp_grid_cell_id(&g, dp_grid_coord(&g, 0, 0.0f), dp_grid_coord(&g, 1, 0.0f),
						      dp_grid_coord(&g, 2, 0.0f))],
			 1);
	assert_int_equal(dp_grid_build(&g, 0, x, y, z, 1.0f, &err), DP_OK);
	assert_int_equal(g.n, 0);
	assert_int_equal(dp_grid_build(&g, 2, x, y, z, -1.0f, &err), DP_ERR_ARG);
	dp_grid_free(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_random),
		cmocka_unit_test(test_clustered_and_duplicates),
		cmocka_unit_test(test_planar_and_single),
		cmocka_unit_test(test_rebuild_reuses_and_caps),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
