/* Every meso-skeleton kernel equals its scalar reference (kernels/skeleton.cl
 * vs host/ref/skeleton_ref.c): skeleton_cov, skeleton_semiaxes,
 * skeleton_median, skeleton_repulse; and the weighted sums' per-query scans
 * (dp_skeleton_reach boxes on a grid with cells smaller than the reach) find
 * every point of the ellipsoid: the reference equals an all-pairs sum. */
#include "testkit.h"

#include "backend/ops.h"
#include "core/eig3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Spacing r of the synthetic set and the operator radii derived from it. */
#define OPS_R 0.1f
#define OPS_NEAR (2.0f * OPS_R)
#define OPS_CUTOFF 3.0f
#define OPS_MAX_SEMI 5.0f
#define OPS_REACH (OPS_CUTOFF * OPS_MAX_SEMI * OPS_R)
#define OPS_MIN_D2 ((DP_PAIR_EPS * OPS_R) * (DP_PAIR_EPS * OPS_R))
/* The weighted sums' grid: cells of the reach of a unit semi-axis, so queries
 * scan 1 to 5 cells per side. */
#define OPS_FAR_CELL (OPS_CUTOFF * OPS_R)
/* dp_skeleton_reach adds well under 1% to the exact half-extents. */
#define OPS_REACH_SLACK 1.01f
/* Queries outside the data's box, within reach of it along one or more axes. */
#define OPS_OUTSIDE 6
static const float outside[OPS_OUTSIDE][3] = {{-0.3f, 3.0f, 3.0f},  {3.0f, 6.2f, 3.0f},   {3.0f, 3.0f, -1.1f},
					      {-0.4f, -0.4f, 6.3f}, {18.5f, 18.2f, 18.0f}, {6.6f, 3.0f, 19.0f}};

typedef struct queries {
	size_t m;
	const float *x, *y, *z;
	float *frames, *metric; /* 9*m */
	float *reach;           /* 3*m, dp_skeleton_reach */
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
	q->reach = malloc(3 * q->m * sizeof *q->reach);
	assert_non_null(q->frames);
	assert_non_null(q->metric);
	assert_non_null(q->reach);
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
	float longest = dp_skeleton_reach(q->m, q->metric, OPS_CUTOFF, q->reach);
	assert_true(longest <= OPS_REACH * OPS_REACH_SLACK);
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
	f->rx = realloc(f->rx, (m + OPS_OUTSIDE) * sizeof(float));
	f->ry = realloc(f->ry, (m + OPS_OUTSIDE) * sizeof(float));
	f->rz = realloc(f->rz, (m + OPS_OUTSIDE) * sizeof(float));
	assert_true(f->rx && f->ry && f->rz);
	for (int o = 0; o < OPS_OUTSIDE; o++, m++) {
		f->rx[m] = outside[o][0];
		f->ry[m] = outside[o][1];
		f->rz[m] = outside[o][2];
	}
	f->rand = (queries){.m = m, .x = f->rx, .y = f->ry, .z = f->rz};
	f->self = (queries){.m = f->n, .x = f->x, .y = f->y, .z = f->z};
	random_frames(&rng, &f->rand);
	random_frames(&rng, &f->self);
	dp_error err = {0};
	int margin = (int)ceilf(OPS_REACH * OPS_REACH_SLACK / OPS_FAR_CELL);
	if (dp_grid_build(&f->near, f->n, f->x, f->y, f->z, OPS_NEAR, &err) != DP_OK ||
	    dp_grid_build_margin(&f->far, f->n, f->x, f->y, f->z, OPS_FAR_CELL, margin, &err) != DP_OK)
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
			   f->rz, f->rand.frames, f->rand.metric, f->rand.reach, f->self.frames, f->self.metric,
			   f->self.reach};
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
			.data = &f->near, .gnx = f->gnx, .gny = f->gny, .gnz = f->gnz, .nq = q->m, .qx = q->x,
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
			.reach = q->reach, .cutoff = OPS_CUTOFF, .min_d2 = OPS_MIN_D2, .median = ref,
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
			.reach = q->reach, .cutoff = OPS_CUTOFF, .min_d2 = OPS_MIN_D2, .repulse = ref,
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

/* The weighted sums of one query set over every data point, no grid: the
 * median (repulse = 0) or the repulsion (repulse = 1) as the reference
 * defines them. */
static void all_pairs(const fixture *f, const queries *q, int repulse, float *out)
{
	float cut2 = OPS_CUTOFF * OPS_CUTOFF, min_d2 = OPS_MIN_D2;
	for (size_t i = 0; i < q->m; i++) {
		const float *m = q->metric + 9 * i;
		double w = 0.0, s[3] = {0.0, 0.0, 0.0};
		for (size_t k = 0; k < f->n; k++) {
			float d[3] = {q->x[i] - f->x[k], q->y[i] - f->y[k], q->z[i] - f->z[k]};
			float d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], u2 = 0.0f;
			for (int r = 0; r < 3; r++) {
				float a = m[3 * r] * d[0] + m[3 * r + 1] * d[1] + m[3 * r + 2] * d[2];
				u2 += a * a;
			}
			if (u2 > cut2 || d2 < min_d2)
				continue;
			double wk = repulse ? exp(-u2) / pow(u2, 2.5) : exp(-u2) / sqrt(d2);
			float p[3] = {f->x[k], f->y[k], f->z[k]};
			w += wk;
			for (int c = 0; c < 3; c++)
				s[c] += wk * (repulse ? d[c] : p[c]);
		}
		float self[3] = {q->x[i], q->y[i], q->z[i]};
		for (int c = 0; c < 3; c++)
			out[3 * i + c] = w > 0.0 ? (float)(s[c] / w) : repulse ? 0.0f : self[c];
	}
}

/* The reach boxes on a grid of cells 1/5 of the longest reach miss no point
 * of any query's ellipsoid, inside the data's box or outside it. */
static void test_reach_scan_equals_all_pairs(void **state)
{
	fixture *f = *state;
	const queries *sets[] = {&f->self, &f->rand};
	for (int s = 0; s < 2; s++) {
		const queries *q = sets[s];
		float *ref = alloc_out(3 * q->m), *all = alloc_out(3 * q->m);
		dp_skeleton_median_args ma = {
			.data = &f->far, .nq = q->m, .qx = q->x, .qy = q->y, .qz = q->z, .metric = q->metric,
			.reach = q->reach, .cutoff = OPS_CUTOFF, .min_d2 = OPS_MIN_D2, .median = ref,
		};
		dp_ref_skeleton_median(&ma);
		all_pairs(f, q, 0, all);
		tk_assert_close(ref, all, 3 * q->m, 1e-4f, 1e-5f, "median, all pairs");
		dp_skeleton_repulse_args ra = {
			.data = &f->far, .nq = q->m, .qx = q->x, .qy = q->y, .qz = q->z, .metric = q->metric,
			.reach = q->reach, .cutoff = OPS_CUTOFF, .min_d2 = OPS_MIN_D2, .repulse = ref,
		};
		dp_ref_skeleton_repulse(&ra);
		all_pairs(f, q, 1, all);
		tk_assert_close(ref, all, 3 * q->m, 1e-4f, 1e-5f * OPS_REACH, "repulse, all pairs");
		free(ref);
		free(all);
	}
}

/* A reach beyond the grid's margin is refused, not scanned short. */
static void test_reach_beyond_margin(void **state)
{
	fixture *f = *state;
	const queries *q = &f->rand;
	float *reach = alloc_out(3 * q->m), *out = alloc_out(3 * q->m);
	for (size_t k = 0; k < 3 * q->m; k++)
		reach[k] = q->reach[k];
	reach[3 * (q->m / 2) + 1] = (float)(f->far.margin + 1) * f->far.cell;
	dp_skeleton_median_args a = {
		.data = &f->far, .nq = q->m, .qx = q->x, .qy = q->y, .qz = q->z, .metric = q->metric, .reach = reach,
		.cutoff = OPS_CUTOFF, .min_d2 = 0.0f, .median = out,
	};
	dp_error err = {0};
	assert_int_equal(dp_op_skeleton_median(tk_ref_context(), &a, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "skeleton_median"));
	reach[3 * (q->m / 2) + 1] = NAN;
	assert_int_equal(dp_op_skeleton_median(tk_cl_context(), &a, &err), DP_ERR_ARG);
	free(reach);
	free(out);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_cov),
		cmocka_unit_test(test_semiaxes),
		cmocka_unit_test(test_median),
		cmocka_unit_test(test_repulse),
		cmocka_unit_test(test_reach_scan_equals_all_pairs),
		cmocka_unit_test(test_reach_beyond_margin),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
