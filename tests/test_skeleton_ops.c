/* Every meso-skeleton kernel equals its scalar reference (kernels/skeleton.cl
 * vs host/ref/skeleton_ref.c): skeleton_cov, skeleton_semiaxes,
 * skeleton_median, skeleton_repulse. */
#include "testkit.h"

#include "backend/skeleton_ops.h"
#include "core/eig3.h"

#include <math.h>
#include <stdlib.h>

/* Spacing r of the synthetic set and the operator radii derived from it. */
#define OPS_R 0.1f
#define OPS_NEAR (2.0f * OPS_R)
#define OPS_CUTOFF 3.0f
#define OPS_MAX_SEMI 5.0f
#define OPS_REACH (OPS_CUTOFF * OPS_MAX_SEMI * OPS_R)

typedef struct queries {
	size_t m;
	const float *x, *y, *z;
	float *frames, *metric; /* 9*m */
} queries;

typedef struct fixture {
	float *x, *y, *z, *nx, *ny, *nz; /* data points and their unit normals */
	size_t n;
	float *gnx, *gny, *gnz;          /* normals in the near grid's order */
	float *rx, *ry, *rz;             /* free-standing queries */
	queries self, rand;              /* queries = the data points (self pairs), and random ones */
	dp_grid near, far;
} fixture;

/* Random orthonormal axes (eigenvectors of a random symmetric matrix) and the
 * metric rows v^m / (l^m r) for random semi-axes l in [1/(1+eps), OPS_MAX_SEMI]. */
static void random_frames(dp_rng *rng, queries *q)
{
	q->frames = malloc(9 * q->m * sizeof *q->frames);
	q->metric = malloc(9 * q->m * sizeof *q->metric);
	assert_non_null(q->frames);
	assert_non_null(q->metric);
	for (size_t i = 0; i < q->m; i++) {
		double s[6], w[3], v[3][3];
		for (int k = 0; k < 6; k++)
			s[k] = dp_rng_normal(rng);
		dp_eig3_sym(s, w, v);
		for (int m = 0; m < 3; m++) {
			double l = 0.9 + dp_rng_uniform(rng) * (OPS_MAX_SEMI - 0.9);
			for (int c = 0; c < 3; c++) {
				q->frames[9 * i + 3 * m + c] = (float)v[m][c];
				q->metric[9 * i + 3 * m + c] = (float)(v[m][c] / (l * OPS_R));
			}
		}
	}
}

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	f->n = tk_random_points(&rng, 3000, 6.0f, OPS_NEAR, &f->x, &f->y, &f->z);
	f->nx = malloc(f->n * sizeof(float));
	f->ny = malloc(f->n * sizeof(float));
	f->nz = malloc(f->n * sizeof(float));
	f->gnx = malloc(f->n * sizeof(float));
	f->gny = malloc(f->n * sizeof(float));
	f->gnz = malloc(f->n * sizeof(float));
	for (size_t i = 0; i < f->n; i++) {
		double a = dp_rng_normal(&rng), b = dp_rng_normal(&rng), c = dp_rng_normal(&rng);
		double len = sqrt(a * a + b * b + c * c) + 1e-12;
		f->nx[i] = (float)(a / len);
		f->ny[i] = (float)(b / len);
		f->nz[i] = (float)(c / len);
	}
	size_t m = tk_random_points(&rng, 600, 6.0f, OPS_NEAR, &f->rx, &f->ry, &f->rz);
	f->rand = (queries){.m = m, .x = f->rx, .y = f->ry, .z = f->rz};
	f->self = (queries){.m = f->n, .x = f->x, .y = f->y, .z = f->z};
	random_frames(&rng, &f->rand);
	random_frames(&rng, &f->self);
	dp_error err = {0};
	if (dp_grid_build(&f->near, f->n, f->x, f->y, f->z, OPS_NEAR, &err) != DP_OK ||
	    dp_grid_build(&f->far, f->n, f->x, f->y, f->z, OPS_REACH, &err) != DP_OK)
		return -1;
	dp_grid_gather(&f->near, f->nx, f->gnx);
	dp_grid_gather(&f->near, f->ny, f->gny);
	dp_grid_gather(&f->near, f->nz, f->gnz);
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	float *arrays[] = {f->x,   f->y,   f->z,   f->nx, f->ny, f->nz, f->gnx, f->gny, f->gnz, f->rx, f->ry,
			   f->rz, f->rand.frames, f->rand.metric, f->self.frames, f->self.metric};
	for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
		free(arrays[k]);
	dp_grid_free(&f->near);
	dp_grid_free(&f->far);
	free(f);
	return 0;
}

static float *alloc_out(size_t n)
{
	float *p = malloc(n * sizeof *p);
	assert_non_null(p);
	return p;
}

static void test_cov(void **state)
{
	fixture *f = *state;
	const queries *sets[] = {&f->self, &f->rand};
	for (int s = 0; s < 2; s++) {
		const queries *q = sets[s];
		float *cref = alloc_out(q->m), *ccl = alloc_out(q->m);
		float *vref = alloc_out(6 * q->m), *vcl = alloc_out(6 * q->m);
		dp_skeleton_cov_args a = {
			.data = &f->near, .nq = q->m, .qx = q->x, .qy = q->y, .qz = q->z, .radius = OPS_NEAR,
			.count = cref, .cov = vref,
		};
		dp_error err = {0};
		assert_int_equal(dp_op_skeleton_cov(tk_ref_context(), &a, &err), DP_OK);
		a.count = ccl;
		a.cov = vcl;
		if (dp_op_skeleton_cov(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		tk_assert_close(ccl, cref, q->m, 0.0f, 0.0f, "cov count");
		tk_assert_close(vcl, vref, 6 * q->m, 1e-4f, 1e-5f * OPS_NEAR * OPS_NEAR, "cov");
		free(cref);
		free(ccl);
		free(vref);
		free(vcl);
	}
}

static void test_semiaxes(void **state)
{
	fixture *f = *state;
	const queries *sets[] = {&f->self, &f->rand};
	for (int s = 0; s < 2; s++) {
		const queries *q = sets[s];
		float *ref = alloc_out(3 * q->m), *cl = alloc_out(3 * q->m);
		dp_skeleton_semiaxes_args a = {
			.data = &f->near, .nx = f->gnx, .ny = f->gny, .nz = f->gnz, .nq = q->m, .qx = q->x,
			.qy = q->y, .qz = q->z, .frames = q->frames, .radius = OPS_NEAR, .eps = 0.1f, .semi = ref,
		};
		dp_error err = {0};
		assert_int_equal(dp_op_skeleton_semiaxes(tk_ref_context(), &a, &err), DP_OK);
		a.semi = cl;
		if (dp_op_skeleton_semiaxes(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		tk_assert_close(cl, ref, 3 * q->m, 1e-4f, 1e-6f, "semiaxes");
		free(ref);
		free(cl);
	}
}

static void test_median(void **state)
{
	fixture *f = *state;
	const queries *sets[] = {&f->self, &f->rand};
	for (int s = 0; s < 2; s++) {
		const queries *q = sets[s];
		float *ref = alloc_out(3 * q->m), *cl = alloc_out(3 * q->m);
		dp_skeleton_median_args a = {
			.data = &f->far, .nq = q->m, .qx = q->x, .qy = q->y, .qz = q->z, .metric = q->metric,
			.cutoff = OPS_CUTOFF, .min_d2 = (DP_PAIR_EPS * OPS_R) * (DP_PAIR_EPS * OPS_R), .median = ref,
		};
		dp_error err = {0};
		assert_int_equal(dp_op_skeleton_median(tk_ref_context(), &a, &err), DP_OK);
		a.median = cl;
		if (dp_op_skeleton_median(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		tk_assert_close(cl, ref, 3 * q->m, 1e-4f, 1e-5f, "median");
		free(ref);
		free(cl);
	}
}

static void test_repulse(void **state)
{
	fixture *f = *state;
	const queries *sets[] = {&f->self, &f->rand};
	for (int s = 0; s < 2; s++) {
		const queries *q = sets[s];
		float *ref = alloc_out(3 * q->m), *cl = alloc_out(3 * q->m);
		dp_skeleton_repulse_args a = {
			.data = &f->far, .nq = q->m, .qx = q->x, .qy = q->y, .qz = q->z, .metric = q->metric,
			.cutoff = OPS_CUTOFF, .min_d2 = (DP_PAIR_EPS * OPS_R) * (DP_PAIR_EPS * OPS_R),
			.repulse = ref,
		};
		dp_error err = {0};
		assert_int_equal(dp_op_skeleton_repulse(tk_ref_context(), &a, &err), DP_OK);
		a.repulse = cl;
		if (dp_op_skeleton_repulse(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		tk_assert_close(cl, ref, 3 * q->m, 1e-4f, 1e-5f * OPS_REACH, "repulse");
		free(ref);
		free(cl);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_cov),
		cmocka_unit_test(test_semiaxes),
		cmocka_unit_test(test_median),
		cmocka_unit_test(test_repulse),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
