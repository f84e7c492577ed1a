/* Every WLOP kernel equals its scalar reference: wlop_density, wlop_attraction and wlop_repulsion
 * (kernels/wlop.cl) against host/ref/wlop_ref.c. */
#include "testkit.h"

#include "backend/ops.h"

#include <math.h>
#include <stdlib.h>

/* Queries that sit exactly on a data point, as initial samples do: the
 * min_d2 skip must treat them the same on both backends. */
#define COINCIDENT_QUERIES 50
#define RTOL 1e-4f

typedef struct fixture {
	float *x, *y, *z; /* data (input points) */
	size_t n;
	float *sx, *sy, *sz; /* queries (samples) */
	size_t m;
	dp_grid grid;        /* over the data */
	dp_grid sample_grid; /* over the queries */
	float *attr;         /* a positive per-point attribute (1/v or w) in sorted order */
	float h;
} fixture;

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 3);
	f->h = 0.9f;
	f->n = tk_random_points(&rng, 5000, 8.0f, f->h, &f->x, &f->y, &f->z);
	f->m = tk_random_points(&rng, 700, 8.0f, f->h, &f->sx, &f->sy, &f->sz);
	for (size_t i = 0; i < COINCIDENT_QUERIES; i++) {
		size_t j = (size_t)(dp_rng_uniform(&rng) * (double)f->n);
		f->sx[i] = f->x[j];
		f->sy[i] = f->y[j];
		f->sz[i] = f->z[j];
	}
	dp_error err = {0};
	if (dp_grid_build(&f->grid, f->n, f->x, f->y, f->z, f->h, &err) != DP_OK ||
	    dp_grid_build(&f->sample_grid, f->m, f->sx, f->sy, f->sz, f->h, &err) != DP_OK)
		return -1;
	size_t most = f->n > f->m ? f->n : f->m;
	f->attr = malloc(most * sizeof *f->attr);
	for (size_t i = 0; i < most; i++)
		f->attr[i] = (float)(0.05 + dp_rng_uniform(&rng));
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	free(f->x);
	free(f->y);
	free(f->z);
	free(f->sx);
	free(f->sy);
	free(f->sz);
	free(f->attr);
	dp_grid_free(&f->grid);
	dp_grid_free(&f->sample_grid);
	free(f);
	return 0;
}

static float min_d2(float h)
{
	return (DP_PAIR_EPS * h) * (DP_PAIR_EPS * h);
}

/* Weighted offset sums Σ wt·d cancel to near zero for a query in the middle of
 * its neighbours, so their tolerance is relative to the bound h·Σ wt. */
static void assert_offsets_close(const float *cl[4], const float *ref[4], size_t n, float h, const char *what)
{
	tk_assert_close(cl[3], ref[3], n, RTOL, 1e-6f, what);
	for (int c = 0; c < 3; c++)
		for (size_t i = 0; i < n; i++) {
			double tol = RTOL * (fabs((double)ref[c][i]) + (double)h * ref[3][i]) + 1e-7;
			if (!(fabs((double)cl[c][i] - (double)ref[c][i]) <= tol))
				fail_msg("%s: component %d of query %zu: %.9g vs %.9g (bound h*sum %.9g)", what, c, i,
					 (double)cl[c][i], (double)ref[c][i], (double)h * ref[3][i]);
		}
}

static void test_density(void **state)
{
	fixture *f = *state;
	float *ref = malloc(f->m * sizeof *ref), *cl = malloc(f->m * sizeof *cl);
	for (int variant = 0; variant < 2; variant++) {
		dp_density_args a = {
			.data = &f->grid, .nq = f->m, .qx = f->sx, .qy = f->sy, .qz = f->sz, .h = f->h,
			.theta_k = variant ? 4.0f : 16.0f, .min_d2 = min_d2(f->h), .sqrt_density = variant,
			.out = ref,
		};
		dp_error err = {0};
		assert_int_equal(dp_op_density(tk_ref_context(), &a, &err), DP_OK);
		a.out = cl;
		if (dp_op_density(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		tk_assert_close(cl, ref, f->m, RTOL, 1e-5f, "wlop_density");
	}
	free(ref);
	free(cl);
}

static void test_attraction(void **state)
{
	fixture *f = *state;
	float *buf = malloc(8 * f->m * sizeof *buf);
	float *ref[4], *cl[4];
	for (int c = 0; c < 4; c++) {
		ref[c] = buf + (size_t)c * f->m;
		cl[c] = buf + (size_t)(4 + c) * f->m;
	}
	for (int variant = 0; variant < 2; variant++) {
		dp_attraction_args a = {
			.data = &f->grid, .inv_v = f->attr, .nq = f->m, .qx = f->sx, .qy = f->sy, .qz = f->sz,
			/* the stage keeps coincident pairs for the finite Gaussian weight */
			.h = f->h, .theta_k = variant ? 4.0f : 16.0f, .min_d2 = variant ? 0.0f : min_d2(f->h),
			.gaussian = variant,
			.out_x = ref[0], .out_y = ref[1], .out_z = ref[2], .out_w = ref[3],
		};
		dp_error err = {0};
		assert_int_equal(dp_op_attraction(tk_ref_context(), &a, &err), DP_OK);
		a.out_x = cl[0];
		a.out_y = cl[1];
		a.out_z = cl[2];
		a.out_w = cl[3];
		if (dp_op_attraction(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		assert_offsets_close((const float **)cl, (const float **)ref, f->m, f->h,
				     variant ? "wlop_attraction (gaussian)" : "wlop_attraction (L1)");
		/* Coincident queries must have skipped their own point, not
		 * summed an infinite weight. */
		for (size_t i = 0; i < COINCIDENT_QUERIES; i++)
			assert_true(isfinite(cl[3][i]) && isfinite(ref[3][i]));
	}
	free(buf);
}

static void test_repulsion(void **state)
{
	fixture *f = *state;
	const dp_grid *g = &f->sample_grid;
	float *buf = malloc(8 * f->m * sizeof *buf);
	float *ref[4], *cl[4];
	for (int c = 0; c < 4; c++) {
		ref[c] = buf + (size_t)c * f->m;
		cl[c] = buf + (size_t)(4 + c) * f->m;
	}
	/* The samples repel each other: queries are the grid's own points. */
	dp_repulsion_args a = {
		.data = g, .w = f->attr, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = f->h,
		.theta_k = 16.0f, .min_d2 = min_d2(f->h),
		.out_x = ref[0], .out_y = ref[1], .out_z = ref[2], .out_w = ref[3],
	};
	dp_error err = {0};
	assert_int_equal(dp_op_repulsion(tk_ref_context(), &a, &err), DP_OK);
	a.out_x = cl[0];
	a.out_y = cl[1];
	a.out_z = cl[2];
	a.out_w = cl[3];
	if (dp_op_repulsion(tk_cl_context(), &a, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_offsets_close((const float **)cl, (const float **)ref, g->n, f->h, "wlop_repulsion");
	for (size_t i = 0; i < g->n; i++)
		assert_true(isfinite(cl[3][i]));
	free(buf);
}

/* Fewer points than a kernel's vector width: every candidate goes through the
 * one-at-a-time path of the kernels, which the big fixture barely reaches. */
#define TINY_N 11

typedef struct tiny_out {
	float density[TINY_N];
	float att[4][TINY_N], rep[4][TINY_N];
} tiny_out;

static void tiny_run(dp_context *ctx, const dp_grid *g, const float *attr, float h, tiny_out *o)
{
	dp_error err = {0};
	dp_density_args d = {.data = g, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = h,
			     .theta_k = 4.0f, .min_d2 = min_d2(h), .out = o->density};
	dp_attraction_args a = {.data = g, .inv_v = attr, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z,
				.h = h, .theta_k = 4.0f, .min_d2 = min_d2(h), .out_x = o->att[0],
				.out_y = o->att[1], .out_z = o->att[2], .out_w = o->att[3]};
	dp_repulsion_args r = {.data = g, .w = attr, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = h,
			       .theta_k = 4.0f, .min_d2 = min_d2(h), .out_x = o->rep[0], .out_y = o->rep[1],
			       .out_z = o->rep[2], .out_w = o->rep[3]};
	if (dp_op_density(ctx, &d, &err) != DP_OK || dp_op_attraction(ctx, &a, &err) != DP_OK ||
	    dp_op_repulsion(ctx, &r, &err) != DP_OK)
		fail_msg("%s", err.message);
}

static void test_tiny_grid(void **state)
{
	(void)state;
	float x[TINY_N], y[TINY_N], z[TINY_N], attr[TINY_N];
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	for (int i = 0; i < TINY_N; i++) {
		x[i] = (float)dp_rng_uniform(&rng);
		y[i] = (float)dp_rng_uniform(&rng);
		z[i] = (float)dp_rng_uniform(&rng);
		attr[i] = (float)(0.5 + dp_rng_uniform(&rng));
	}
	/* one exact duplicate */
	x[TINY_N - 1] = x[0];
	y[TINY_N - 1] = y[0];
	z[TINY_N - 1] = z[0];
	float h = 0.6f;
	dp_grid g = {0};
	dp_error err = {0};
	assert_int_equal(dp_grid_build(&g, TINY_N, x, y, z, h, &err), DP_OK);
	tiny_out ref, cl;
	tiny_run(tk_ref_context(), &g, attr, h, &ref);
	tiny_run(tk_cl_context(), &g, attr, h, &cl);
	tk_assert_close(cl.density, ref.density, TINY_N, RTOL, 1e-6f, "tiny density");
	const float *c[4], *r[4];
	for (int k = 0; k < 4; k++) {
		c[k] = cl.att[k];
		r[k] = ref.att[k];
	}
	assert_offsets_close(c, r, TINY_N, h, "tiny attraction");
	for (int k = 0; k < 4; k++) {
		c[k] = cl.rep[k];
		r[k] = ref.rep[k];
	}
	assert_offsets_close(c, r, TINY_N, h, "tiny repulsion");
	dp_grid_free(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_density),
		cmocka_unit_test(test_attraction),
		cmocka_unit_test(test_repulsion),
		cmocka_unit_test(test_tiny_grid),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
