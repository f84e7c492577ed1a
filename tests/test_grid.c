/* The uniform grid's neighbour sets equal FLANN's exact radius search: the
 * 27-cell scan (dp_grid_rows) with radius <= cell, and the scan of reach R
 * cells per side (dp_grid_row) on grids with an R-cell margin, for spheres of
 * up to R cells and axis-aligned ellipsoids with a different reach per axis,
 * queries inside and outside the points' box. */
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

/* For every query, the set {k : Σ_a (d_a / axes[a])² < 1} found by the scan
 * of reach dp_grid_reach_cells(axes[a]) per axis on a grid of cell `cell` and
 * `margin`, against FLANN's radius search with the longest axis filtered by
 * the same test. */
static void check_reach_against_flann(size_t n, const float *x, const float *y, const float *z, float cell,
				      int margin, const float axes[3], size_t nq, const float *qx, const float *qy,
				      const float *qz)
{
	dp_error err = {0};
	dp_grid g = {0};
	assert_int_equal(dp_grid_build_margin(&g, n, x, y, z, cell, margin, &err), DP_OK);
	assert_int_equal(g.margin, margin);
	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, n, x, y, z, &err), DP_OK);
	int *fidx = malloc(n * sizeof *fidx);
	float *fd2 = malloc(n * sizeof *fd2);
	char *mark = calloc(n, 1);
	float longest = fmaxf(axes[0], fmaxf(axes[1], axes[2]));
	int reach[3];
	for (int a = 0; a < 3; a++) {
		reach[a] = dp_grid_reach_cells(&g, axes[a]);
		assert_true(reach[a] <= margin);
	}
	for (size_t i = 0; i < nq; i++) {
		float q[3] = {qx[i], qy[i], qz[i]};
		int nf = dp_knn_radius(&knn, q[0], q[1], q[2], longest * longest, fidx, fd2, (int)n);
		int expected = 0;
		for (int j = 0; j < nf; j++) {
			float p[3] = {x[fidx[j]], y[fidx[j]], z[fidx[j]]}, e = 0.0f;
			for (int a = 0; a < 3; a++)
				e += (q[a] - p[a]) * (q[a] - p[a]) / (axes[a] * axes[a]);
			if (e < 1.0f) {
				mark[fidx[j]] = 1;
				expected++;
			}
		}
		int found = 0;
		int cx = dp_grid_coord(&g, 0, q[0]), cy = dp_grid_coord(&g, 1, q[1]), cz = dp_grid_coord(&g, 2, q[2]);
		for (int dz = -reach[2]; dz <= reach[2]; dz++)
			for (int dy = -reach[1]; dy <= reach[1]; dy++) {
				uint32_t beg, end;
				dp_grid_row(&g, cx, cy + dy, cz + dz, reach[0], &beg, &end);
				for (uint32_t k = beg; k < end; k++) {
					float p[3] = {g.x[k], g.y[k], g.z[k]}, e = 0.0f;
					for (int a = 0; a < 3; a++)
						e += (q[a] - p[a]) * (q[a] - p[a]) / (axes[a] * axes[a]);
					if (e >= 1.0f)
						continue;
					uint32_t orig = g.perm[k];
					if (mark[orig] != 1)
						fail_msg("query %zu: reach scan finds %u %s", i, orig,
							 mark[orig] ? "twice" : "which FLANN does not");
					mark[orig] = 2;
					found++;
				}
			}
		if (found != expected)
			fail_msg("query %zu at (%g, %g, %g): reach scan finds %d neighbours, FLANN %d", i, q[0], q[1],
				 q[2], found, expected);
		for (int j = 0; j < nf; j++)
			mark[fidx[j]] = 0;
	}
	free(fidx);
	free(fd2);
	free(mark);
	dp_knn_free(&knn);
	dp_grid_free(&g);
}

/* Spheres of exactly R cells (points on the last scanned border), of a
 * fraction of a cell, and ellipsoids reaching 1, 3 and 4 cells along the axes. */
static void check_reach_shapes(size_t n, const float *x, const float *y, const float *z, float cell, size_t nq,
			       const float *qx, const float *qy, const float *qz)
{
	const float shapes[][3] = {{3 * cell, 3 * cell, 3 * cell},
				   {0.4f * cell, 0.4f * cell, 0.4f * cell},
				   {3.5f * cell, 0.6f * cell, 2.2f * cell},
				   {0.9f * cell, 3.9f * cell, 2.9f * cell}};
	for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++)
		check_reach_against_flann(n, x, y, z, cell, 4, shapes[s], nq, qx, qy, qz);
}

static void test_reach_random_and_outside(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 8);
	float *x, *y, *z;
	size_t n = tk_random_points(&rng, 3000, 10.0f, 0.5f, &x, &y, &z);
	check_reach_shapes(n, x, y, z, 0.5f, n, x, y, z);
	/* outside the box along one, two and three axes, within and beyond reach */
	float qx[] = {-0.3f, -1.2f, 10.4f, 31.5f, 5.0f, -1.0f, 1e6f, -2.5f},
	      qy[] = {5.0f, 5.0f, 10.6f, 30.2f, -1.69f, 31.0f, 0.0f, 4.0f},
	      qz[] = {5.0f, -0.4f, 10.2f, 29.0f, 3.0f, 32.0f, 0.0f, 12.0f};
	check_reach_shapes(n, x, y, z, 0.5f, sizeof qx / sizeof qx[0], qx, qy, qz);
	free(x);
	free(y);
	free(z);
}

static void test_reach_clustered_and_lattice(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 12);
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
	check_reach_shapes(n, x, y, z, 0.04f, n, x, y, z);
	/* a planar lattice of step = cell: points on every cell border */
	for (size_t i = 0; i < 900; i++) {
		x[i] = (float)(i % 30) * 0.1f;
		y[i] = (float)(i / 30) * 0.1f;
		z[i] = 0.0f;
	}
	check_reach_shapes(900, x, y, z, 0.1f, 900, x, y, z);
	free(x);
	free(y);
	free(z);
}

/* Margins outside [1, DP_GRID_MAX_MARGIN] are refused; reaches convert to
 * whole cells within the margin, whatever the length. */
static void test_margin_and_reach_cells(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_grid g = {0};
	float x[3] = {0.0f, 1.0f, 2.5f}, y[3] = {0.0f, 0.5f, 1.0f}, z[3] = {0.0f, 0.0f, 3.0f};
	assert_int_equal(dp_grid_build_margin(&g, 3, x, y, z, 1.0f, 0, &err), DP_ERR_ARG);
	assert_int_equal(dp_grid_build_margin(&g, 3, x, y, z, 1.0f, DP_GRID_MAX_MARGIN + 1, &err), DP_ERR_ARG);
	assert_int_equal(dp_grid_build_margin(&g, 3, x, y, z, 1.0f, 5, &err), DP_OK);
	/* the margin cells are empty: every point lies in [margin, dim-1-margin] */
	uint32_t inside = 0;
	for (int cz = g.margin; cz < g.dim[2] - g.margin; cz++)
		for (int cy = g.margin; cy < g.dim[1] - g.margin; cy++)
			for (int cx = g.margin; cx < g.dim[0] - g.margin; cx++)
				inside += g.cell_count[dp_grid_cell_id(&g, cx, cy, cz)];
	assert_int_equal(inside, 3);
	assert_int_equal(g.dim[0], 3 + 2 * 5);
	assert_int_equal(dp_grid_reach_cells(&g, 0.0f), 0);
	assert_int_equal(dp_grid_reach_cells(&g, -2.0f), 0);
	assert_int_equal(dp_grid_reach_cells(&g, 2.0f), 2);
	assert_int_equal(dp_grid_reach_cells(&g, 2.01f), 3);
	assert_int_equal(dp_grid_reach_cells(&g, 1e30f), 5);
	assert_int_equal(dp_grid_reach_cells(&g, NAN), 5);
	/* a cell capped by DP_GRID_MAX_CELLS keeps the margin */
	float fx[2] = {0.0f, 1e5f};
	assert_int_equal(dp_grid_build_margin(&g, 2, fx, fx, fx, 0.01f, 7, &err), DP_OK);
	assert_true(g.ncells <= DP_GRID_MAX_CELLS);
	assert_int_equal(g.margin, 7);
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
	/* finite coordinates whose float difference overflows: the cell grows to
	 * fit (it used to grow for ever) and both points are bucketed */
	float fx[2] = {-3e38f, 3e38f}, fy[2] = {0.0f, 0.0f}, fz[2] = {0.0f, 0.0f};
	assert_int_equal(dp_grid_build(&g, 2, fx, fy, fz, 1.0f, &err), DP_OK);
	assert_true(isfinite(g.cell) && g.ncells <= DP_GRID_MAX_CELLS);
	uint32_t total = 0;
	for (uint32_t c = 0; c < g.ncells; c++)
		total += g.cell_count[c];
	assert_int_equal(total, 2);
	dp_grid_free(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_random),
		cmocka_unit_test(test_clustered_and_duplicates),
		cmocka_unit_test(test_planar_and_single),
		cmocka_unit_test(test_rebuild_reuses_and_caps),
		cmocka_unit_test(test_reach_random_and_outside),
		cmocka_unit_test(test_reach_clustered_and_lattice),
		cmocka_unit_test(test_margin_and_reach_cells),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
