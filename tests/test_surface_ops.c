/* Every surface consolidation kernel equals its scalar reference
 * (kernels/surface.cl vs host/ref/surface_ref.c) on random inputs with the
 * awkward cases of tk_random_points, queries that coincide with grid points
 * (self pairs and exact duplicates) and normals of every direction. */
#include "testkit.h"

#include "backend/ops.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Radius of the neighbour sums and r, as in the stage (σp = 5 would leave most
 * random pairs with θ ~ 0; 3 keeps every weight in play). */
#define RADIUS 0.9f
#define SPACING (RADIUS / 3.0f)
/* Queries that are exact copies of grid points. */
#define N_COPIES 40

typedef struct fixture {
	float *x, *y, *z; /* grid points (input, surface or skeleton) */
	size_t n;
	float *qx, *qy, *qz; /* queries, the last N_COPIES copies of grid points */
	size_t m;
	float *nx, *ny, *nz; /* unit normals of the queries */
	float *len;          /* dpoint lengths of the grid points (caller order) */
	float *glen;         /* the same in grid order */
	float *qlen;         /* dpoint lengths of the queries */
	float *gnx, *gny, *gnz; /* unit normals of the grid points, grid order */
	float *zero, *depth; /* no side vector; the queries' depth behind p (qlen in units) */
	dp_grid grid;
} fixture;

static float *alloc_floats(size_t n)
{
	float *p = malloc((n ? n : 1) * sizeof *p);
	assert_non_null(p);
	return p;
}

static void random_unit(dp_rng *rng, float *x, float *y, float *z)
{
	double v[3], s;
	do {
		s = 0.0;
		for (int a = 0; a < 3; a++) {
			v[a] = dp_rng_normal(rng);
			s += v[a] * v[a];
		}
	} while (s < 1e-6);
	s = sqrt(s);
	*x = (float)(v[0] / s);
	*y = (float)(v[1] / s);
	*z = (float)(v[2] / s);
}

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	f->n = tk_random_points(&rng, 4000, 8.0f, RADIUS, &f->x, &f->y, &f->z);
	float *qx, *qy, *qz;
	size_t m0 = tk_random_points(&rng, 600, 8.0f, RADIUS, &qx, &qy, &qz);
	f->m = m0 + N_COPIES;
	f->qx = alloc_floats(f->m);
	f->qy = alloc_floats(f->m);
	f->qz = alloc_floats(f->m);
	memcpy(f->qx, qx, m0 * sizeof *qx);
	memcpy(f->qy, qy, m0 * sizeof *qy);
	memcpy(f->qz, qz, m0 * sizeof *qz);
	free(qx);
	free(qy);
	free(qz);
	for (size_t c = 0; c < N_COPIES; c++) {
		size_t src = (size_t)(dp_rng_uniform(&rng) * (double)f->n);
		f->qx[m0 + c] = f->x[src];
		f->qy[m0 + c] = f->y[src];
		f->qz[m0 + c] = f->z[src];
	}
	f->nx = alloc_floats(f->m);
	f->ny = alloc_floats(f->m);
	f->nz = alloc_floats(f->m);
	f->qlen = alloc_floats(f->m);
	for (size_t i = 0; i < f->m; i++) {
		double v[3], s = 0.0;
		do {
			s = 0.0;
			for (int a = 0; a < 3; a++) {
				v[a] = dp_rng_normal(&rng);
				s += v[a] * v[a];
			}
		} while (s < 1e-6);
		s = sqrt(s);
		/* A few normals along an axis: tangential offsets then vanish exactly
		 * for neighbours straight above or below (the tfloor guard). */
		if (i % 50 == 0) {
			v[0] = v[1] = 0.0;
			v[2] = s;
		}
		f->nx[i] = (float)(v[0] / s);
		f->ny[i] = (float)(v[1] / s);
		f->nz[i] = (float)(v[2] / s);
		f->qlen[i] = (float)(3.0 * dp_rng_uniform(&rng));
	}
	f->len = alloc_floats(f->n);
	f->glen = alloc_floats(f->n);
	for (size_t k = 0; k < f->n; k++)
		f->len[k] = (float)(3.0 * dp_rng_uniform(&rng));
	f->gnx = alloc_floats(f->n);
	f->gny = alloc_floats(f->n);
	f->gnz = alloc_floats(f->n);
	for (size_t k = 0; k < f->n; k++)
		random_unit(&rng, &f->gnx[k], &f->gny[k], &f->gnz[k]);
	f->zero = alloc_floats(f->m);
	f->depth = alloc_floats(f->m);
	for (size_t i = 0; i < f->m; i++) {
		f->zero[i] = 0.0f;
		f->depth[i] = f->qlen[i] * SPACING;
	}
	dp_error err = {0};
	if (dp_grid_build(&f->grid, f->n, f->x, f->y, f->z, RADIUS, &err) != DP_OK)
		return -1;
	dp_grid_gather(&f->grid, f->len, f->glen);
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	float *arrays[] = {f->x,   f->y,    f->z,   f->qx,  f->qy,  f->qz,   f->nx,   f->ny,
			   f->nz,  f->len, f->glen, f->qlen, f->gnx, f->gny, f->gnz, f->zero, f->depth};
	for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; a++)
		free(arrays[a]);
	dp_grid_free(&f->grid);
	free(f);
	return 0;
}

/* The data term with the side test (s = the query normal, depth = its
 * dpoint length; `sided`) or without it (s = 0). */
static void run_data(const fixture *f, int sided, float *out[2][5])
{
	for (int b = 0; b < 2; b++)
		for (int o = 0; o < 5; o++)
			out[b][o] = alloc_floats(f->m);
	for (int b = 0; b < 2; b++) {
		dp_surface_data_args a = {
			.input = &f->grid, .nq = f->m, .px = f->qx, .py = f->qy, .pz = f->qz,
			.sx = sided ? f->nx : f->zero, .sy = sided ? f->ny : f->zero, .sz = sided ? f->nz : f->zero,
			.depth = sided ? f->depth : f->qlen, .radius = RADIUS,
			.r = SPACING, .min_d2 = (DP_PAIR_EPS * RADIUS) * (DP_PAIR_EPS * RADIUS),
			.eta = out[b][0], .sum_alpha = out[b][1], .ox = out[b][2], .oy = out[b][3], .oz = out[b][4],
		};
		dp_error err = {0};
		if (dp_op_surface_data(b ? tk_cl_context() : tk_ref_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
	}
}

static void test_data(void **state)
{
	fixture *f = *state;
	float *out[2][5], *all[2][5];
	run_data(f, 1, out);
	run_data(f, 0, all);
	tk_assert_close(out[1][0], out[0][0], f->m, 1e-4f, 1e-6f, "surface_data eta");
	tk_assert_close(out[1][1], out[0][1], f->m, 1e-4f, 1e-6f, "surface_data sum_alpha");
	/* Offsets are averages of vectors up to RADIUS long that may cancel. */
	tk_assert_close(out[1][2], out[0][2], f->m, 1e-4f, 1e-4f * RADIUS, "surface_data ox");
	tk_assert_close(out[1][3], out[0][3], f->m, 1e-4f, 1e-4f * RADIUS, "surface_data oy");
	tk_assert_close(out[1][4], out[0][4], f->m, 1e-4f, 1e-4f * RADIUS, "surface_data oz");
	/* The copies of grid points must have skipped their duplicate, not
	 * divided by zero. */
	for (size_t i = f->m - N_COPIES; i < f->m; i++)
		assert_true(isfinite(out[0][2][i]) && out[0][0][i] >= 2.0f);
	/* The side test only ever drops pairs, and it drops some. */
	size_t fewer = 0;
	for (size_t i = 0; i < f->m; i++) {
		assert_true(out[0][0][i] <= all[0][0][i] + 1e-5f);
		fewer += out[0][0][i] < all[0][0][i] - 1e-3f;
	}
	assert_true(fewer > f->m / 4);
	for (int b = 0; b < 2; b++)
		for (int o = 0; o < 5; o++) {
			free(out[b][o]);
			free(all[b][o]);
		}
}

static void test_neighbour(void **state)
{
	fixture *f = *state;
	float *out[2][9];
	for (int b = 0; b < 2; b++)
		for (int o = 0; o < 9; o++)
			out[b][o] = alloc_floats(f->m);
	for (int b = 0; b < 2; b++) {
		/* side_cos 0: a neighbour counts only with a normal within 90° */
		dp_surface_neighbour_args a = {
			.surface = &f->grid, .glen = f->glen, .gnx = f->gnx, .gny = f->gny, .gnz = f->gnz, .nq = f->m,
			.px = f->qx, .py = f->qy, .pz = f->qz, .nx = f->nx, .ny = f->ny, .nz = f->nz, .len = f->qlen,
			.radius = RADIUS, .r = SPACING, .min_d2 = (DP_PAIR_EPS * RADIUS) * (DP_PAIR_EPS * RADIUS),
			.tfloor = 0.01f, .side_cos = 0.0f,
			.L = out[b][0], .var = out[b][1], .rx = out[b][2], .ry = out[b][3], .rz = out[b][4],
			.nn = out[b][5], .mx = out[b][6], .my = out[b][7], .mz = out[b][8],
		};
		dp_error err = {0};
		if (dp_op_surface_neighbour(b ? tk_cl_context() : tk_ref_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
	}
	tk_assert_close(out[1][0], out[0][0], f->m, 1e-4f, 1e-5f, "surface_neighbour L");
	tk_assert_close(out[1][1], out[0][1], f->m, 1e-4f, 1e-4f, "surface_neighbour var");
	tk_assert_close(out[1][2], out[0][2], f->m, 1e-4f, 1e-4f * RADIUS, "surface_neighbour rx");
	tk_assert_close(out[1][3], out[0][3], f->m, 1e-4f, 1e-4f * RADIUS, "surface_neighbour ry");
	tk_assert_close(out[1][4], out[0][4], f->m, 1e-4f, 1e-4f * RADIUS, "surface_neighbour rz");
	tk_assert_close(out[1][5], out[0][5], f->m, 1e-4f, 1e-6f, "surface_neighbour nn");
	tk_assert_close(out[1][6], out[0][6], f->m, 1e-4f, 1e-4f * RADIUS, "surface_neighbour mx");
	tk_assert_close(out[1][7], out[0][7], f->m, 1e-4f, 1e-4f * RADIUS, "surface_neighbour my");
	tk_assert_close(out[1][8], out[0][8], f->m, 1e-4f, 1e-4f * RADIUS, "surface_neighbour mz");
	/* The repulsion is tangential: orthogonal to the query's normal. */
	for (size_t i = 0; i < f->m; i++) {
		float dn = out[0][2][i] * f->nx[i] + out[0][3][i] * f->ny[i] + out[0][4][i] * f->nz[i];
		assert_true(fabsf(dn) <= 1e-4f * RADIUS);
	}
	for (int b = 0; b < 2; b++)
		for (int o = 0; o < 9; o++)
			free(out[b][o]);
}

static void test_covariance(void **state)
{
	fixture *f = *state;
	float *cov[2];
	for (int b = 0; b < 2; b++) {
		cov[b] = alloc_floats(6 * f->m);
		dp_surface_covariance_args a = {
			.surface = &f->grid, .gnx = f->gnx, .gny = f->gny, .gnz = f->gnz, .nq = f->m, .px = f->qx,
			.py = f->qy, .pz = f->qz, .nx = f->nx, .ny = f->ny, .nz = f->nz, .radius = RADIUS,
			.r = SPACING, .side_cos = 0.0f, .cov = cov[b],
		};
		dp_error err = {0};
		if (dp_op_surface_covariance(b ? tk_cl_context() : tk_ref_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
	}
	/* Entries are in r², up to (RADIUS/SPACING)² = 9. */
	tk_assert_close(cov[1], cov[0], 6 * f->m, 1e-4f, 1e-4f, "surface_covariance");
	free(cov[0]);
	free(cov[1]);
}

/* The skeleton points the neighbours' inner ends hang on: random positions
 * around each grid point, so that the weighted mean differs from the
 * neighbours' own centroid. */
static void test_ends(void **state)
{
	fixture *f = *state;
	dp_rng rng;
	dp_rng_seed(&rng, 23);
	float *gs[3], *out[2][4];
	for (int c = 0; c < 3; c++)
		gs[c] = alloc_floats(f->n);
	for (size_t k = 0; k < f->n; k++) {
		const float *g[3] = {f->grid.x, f->grid.y, f->grid.z};
		for (int c = 0; c < 3; c++)
			gs[c][k] = g[c][k] + (float)(2.0 * dp_rng_uniform(&rng) - 1.0) * RADIUS;
	}
	for (int b = 0; b < 2; b++) {
		for (int o = 0; o < 4; o++)
			out[b][o] = alloc_floats(f->m);
		dp_surface_ends_args a = {
			.surface = &f->grid, .gnx = f->gnx, .gny = f->gny, .gnz = f->gnz, .nq = f->m, .px = f->qx,
			.py = f->qy, .pz = f->qz, .nx = f->nx, .ny = f->ny, .nz = f->nz, .gsx = gs[0], .gsy = gs[1],
			.gsz = gs[2], .radius = RADIUS, .sigma = 2.0f * SPACING, .side_cos = 0.0f, .wsum = out[b][0],
			.ox = out[b][1], .oy = out[b][2], .oz = out[b][3],
		};
		dp_error err = {0};
		if (dp_op_surface_ends(b ? tk_cl_context() : tk_ref_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
	}
	tk_assert_close(out[1][0], out[0][0], f->m, 1e-4f, 1e-5f, "surface_ends wsum");
	tk_assert_close(out[1][1], out[0][1], f->m, 1e-4f, 1e-4f * RADIUS, "surface_ends ox");
	tk_assert_close(out[1][2], out[0][2], f->m, 1e-4f, 1e-4f * RADIUS, "surface_ends oy");
	tk_assert_close(out[1][3], out[0][3], f->m, 1e-4f, 1e-4f * RADIUS, "surface_ends oz");
	size_t weighed = 0;
	for (size_t i = 0; i < f->m; i++)
		weighed += out[0][0][i] > 0.0f;
	assert_true(weighed > f->m / 2);
	for (int c = 0; c < 3; c++)
		free(gs[c]);
	for (int b = 0; b < 2; b++)
		for (int o = 0; o < 4; o++)
			free(out[b][o]);
}

static void test_reattach(void **state)
{
	fixture *f = *state;
	/* p_i = the query moved along its normal, so that lines through it cross
	 * the grid's points around q_i from both sides. */
	float *px = alloc_floats(f->m), *py = alloc_floats(f->m), *pz = alloc_floats(f->m);
	for (size_t i = 0; i < f->m; i++) {
		float t = (float)(i % 7) * 0.3f - 0.6f;
		px[i] = f->qx[i] + t * f->nx[i];
		py[i] = f->qy[i] + t * f->ny[i];
		pz[i] = f->qz[i] + t * f->nz[i];
	}
	int32_t *best[2];
	float *dist2[2];
	for (int b = 0; b < 2; b++) {
		best[b] = malloc(f->m * sizeof *best[b]);
		assert_non_null(best[b]);
		dist2[b] = alloc_floats(f->m);
		dp_surface_reattach_args a = {
			.skeleton = &f->grid, .nq = f->m, .qx = f->qx, .qy = f->qy, .qz = f->qz, .px = px, .py = py,
			.pz = pz, .nx = f->nx, .ny = f->ny, .nz = f->nz, .radius = RADIUS, .r = SPACING,
			.best = best[b], .dist2 = dist2[b],
		};
		dp_error err = {0};
		if (dp_op_surface_reattach(b ? tk_cl_context() : tk_ref_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
	}
	size_t found = 0, differ = 0;
	for (size_t i = 0; i < f->m; i++) {
		assert_true(best[0][i] >= -1 && best[0][i] < (int32_t)f->n);
		assert_int_equal(best[0][i] < 0, best[1][i] < 0);
		found += best[0][i] >= 0;
		/* A different choice is only allowed between (float-)equal lines. */
		if (best[0][i] != best[1][i])
			differ++;
	}
	tk_assert_close(dist2[1], dist2[0], f->m, 1e-3f, 1e-5f, "surface_reattach dist2");
	assert_true(found > f->m / 2);
	assert_true(differ <= f->m / 100);
	free(px);
	free(py);
	free(pz);
	for (int b = 0; b < 2; b++) {
		free(best[b]);
		free(dist2[b]);
	}
}

/* An empty grid: every query gets the neutral outputs on both backends. */
static void test_empty_grid(void **state)
{
	fixture *f = *state;
	dp_grid empty = {0};
	dp_error err = {0};
	assert_int_equal(dp_grid_build(&empty, 0, NULL, NULL, NULL, RADIUS, &err), DP_OK);
	for (int b = 0; b < 2; b++) {
		dp_context *ctx = b ? tk_cl_context() : tk_ref_context();
		float *eta = alloc_floats(f->m), *sa = alloc_floats(f->m), *o[3];
		for (int c = 0; c < 3; c++)
			o[c] = alloc_floats(f->m);
		dp_surface_data_args a = {
			.input = &empty, .nq = f->m, .px = f->qx, .py = f->qy, .pz = f->qz, .sx = f->nx, .sy = f->ny,
			.sz = f->nz, .depth = f->depth, .radius = RADIUS,
			.r = SPACING, .min_d2 = 0.0f, .eta = eta, .sum_alpha = sa, .ox = o[0], .oy = o[1], .oz = o[2],
		};
		if (dp_op_surface_data(ctx, &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		for (size_t i = 0; i < f->m; i++)
			assert_true(eta[i] == 1.0f && sa[i] == 0.0f && o[0][i] == 0.0f);
		dp_surface_ends_args e = {
			.surface = &empty, .gnx = f->gnx, .gny = f->gny, .gnz = f->gnz, .nq = f->m, .px = f->qx,
			.py = f->qy, .pz = f->qz, .nx = f->nx, .ny = f->ny, .nz = f->nz, .gsx = f->gnx, .gsy = f->gny,
			.gsz = f->gnz, .radius = RADIUS, .sigma = SPACING, .side_cos = -2.0f, .wsum = eta, .ox = o[0],
			.oy = o[1], .oz = o[2],
		};
		if (dp_op_surface_ends(ctx, &e, &err) != DP_OK)
			fail_msg("%s", err.message);
		for (size_t i = 0; i < f->m; i++)
			assert_true(eta[i] == 0.0f && o[0][i] == 0.0f && o[1][i] == 0.0f && o[2][i] == 0.0f);
		free(eta);
		free(sa);
		for (int c = 0; c < 3; c++)
			free(o[c]);
	}
	dp_grid_free(&empty);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_data),
		cmocka_unit_test(test_neighbour),
		cmocka_unit_test(test_covariance),
		cmocka_unit_test(test_ends),
		cmocka_unit_test(test_reattach),
		cmocka_unit_test(test_empty_grid),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
