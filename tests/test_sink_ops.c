/* Every sinking kernel equals its scalar reference (kernels/sink.cl vs
 * host/ref/sink_ref.c), and the reference equals a brute-force evaluation of
 * its definition (host/ops/operators.h) over all pairs. */
#include "testkit.h"

#include "backend/ops.h"

#include <math.h>
#include <stdlib.h>

typedef struct fixture {
	size_t n;
	float *px, *py, *pz; /* surface points */
	float *nx, *ny, *nz; /* their unit normals */
	float *qx, *qy, *qz; /* inner points, independent of the surface points */
	float *move;
	float *stop, *depth; /* where settled points stopped (+inf: moving); each query's depth */
	dp_grid inner, surface;
	/* attributes in the inner grid's order, then in the surface grid's */
	float *iq_px, *iq_py, *iq_pz, *iq_nx, *iq_ny, *iq_nz;
	float *sf_nx, *sf_ny, *sf_nz, *sf_qx, *sf_qy, *sf_qz, *sf_move, *sf_stop;
} fixture;

/* Radii: the settle test in the inner grid, P_i in the surface grid. The far
 * test distance is about the mean distance of two random points in the box,
 * so both outcomes are common. */
#define EXTENT 8.0f
#define FRONT_RADIUS 0.9f
#define FAR_DIST 4.0f
#define WALL_MIN 0.3f
#define STATIC_RADIUS 1.5f
#define SPACING 0.3f
#define COS_OMEGA 0.70710678f
/* Depths of the step's queries and stops, and the margin: every outcome of
 * the stop test is common. */
#define STOP_DEPTH 3.0f
#define STOP_MARGIN 0.5f

static float *gathered(const dp_grid *g, const float *src)
{
	float *dst = malloc(g->n * sizeof *dst);
	assert_non_null(dst);
	dp_grid_gather(g, src, dst);
	return dst;
}

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	f->n = tk_random_points(&rng, 3000, EXTENT, STATIC_RADIUS, &f->px, &f->py, &f->pz);
	size_t nq = tk_random_points(&rng, 3000, EXTENT, FRONT_RADIUS, &f->qx, &f->qy, &f->qz);
	if (nq != f->n)
		return -1;
	f->nx = malloc(f->n * sizeof(float));
	f->ny = malloc(f->n * sizeof(float));
	f->nz = malloc(f->n * sizeof(float));
	f->move = malloc(f->n * sizeof(float));
	f->stop = malloc(f->n * sizeof(float));
	f->depth = malloc(f->n * sizeof(float));
	for (size_t i = 0; i < f->n; i++) {
		double v[3], len;
		do {
			for (int c = 0; c < 3; c++)
				v[c] = dp_rng_normal(&rng);
			len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
		} while (len < 1e-3);
		f->nx[i] = (float)(v[0] / len);
		f->ny[i] = (float)(v[1] / len);
		f->nz[i] = (float)(v[2] / len);
		f->move[i] = (float)dp_rng_uniform(&rng);
		/* a third still moving, the rest stopped at depths in [0, 3) */
		f->stop[i] = dp_rng_uniform(&rng) < 1.0 / 3.0 ? INFINITY : (float)(STOP_DEPTH * dp_rng_uniform(&rng));
		f->depth[i] = (float)(STOP_DEPTH * dp_rng_uniform(&rng));
	}
	dp_error err = {0};
	if (dp_grid_build(&f->inner, f->n, f->qx, f->qy, f->qz, FRONT_RADIUS, &err) != DP_OK ||
	    dp_grid_build(&f->surface, f->n, f->px, f->py, f->pz, STATIC_RADIUS, &err) != DP_OK)
		return -1;
	f->iq_px = gathered(&f->inner, f->px);
	f->iq_py = gathered(&f->inner, f->py);
	f->iq_pz = gathered(&f->inner, f->pz);
	f->iq_nx = gathered(&f->inner, f->nx);
	f->iq_ny = gathered(&f->inner, f->ny);
	f->iq_nz = gathered(&f->inner, f->nz);
	f->sf_nx = gathered(&f->surface, f->nx);
	f->sf_ny = gathered(&f->surface, f->ny);
	f->sf_nz = gathered(&f->surface, f->nz);
	f->sf_qx = gathered(&f->surface, f->qx);
	f->sf_qy = gathered(&f->surface, f->qy);
	f->sf_qz = gathered(&f->surface, f->qz);
	f->sf_move = gathered(&f->surface, f->move);
	f->sf_stop = gathered(&f->surface, f->stop);
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	float *arrays[] = {f->px, f->py, f->pz, f->nx, f->ny, f->nz, f->qx, f->qy, f->qz, f->move, f->stop, f->depth,
			   f->iq_px, f->iq_py, f->iq_pz, f->iq_nx, f->iq_ny, f->iq_nz, f->sf_nx, f->sf_ny,
			   f->sf_nz, f->sf_qx, f->sf_qy, f->sf_qz, f->sf_move, f->sf_stop};
	for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
		free(arrays[k]);
	dp_grid_free(&f->inner);
	dp_grid_free(&f->surface);
	free(f);
	return 0;
}

static float dist2(const float *ax, const float *ay, const float *az, size_t i, size_t k)
{
	float dx = ax[i] - ax[k], dy = ay[i] - ay[k], dz = az[i] - az[k];
	return dx * dx + dy * dy + dz * dz;
}

static float dot(const fixture *f, size_t i, size_t k)
{
	return f->nx[i] * f->nx[k] + f->ny[i] * f->ny[k] + f->nz[i] * f->nz[k];
}

/* Whether partner k is the far face of a wall for query i (the front
 * test's second way in); *walls counts the pairs only it lets in. */
static size_t walls;
static int wall(const fixture *f, size_t i, size_t k)
{
	float behind = f->nx[k] * (f->px[k] - f->px[i]) + f->ny[k] * (f->py[k] - f->py[i]) +
		       f->nz[k] * (f->pz[k] - f->pz[i]);
	int in = dot(f, i, k) < DP_SINK_OPPOSITE_COS && behind > WALL_MIN;
	walls += in && !(dist2(f->px, f->py, f->pz, i, k) > FAR_DIST * FAR_DIST);
	return in;
}

static dp_sink_front_args front_args(const fixture *f, float *out)
{
	return (dp_sink_front_args){
		.inner = &f->inner,
		.sx = f->iq_px, .sy = f->iq_py, .sz = f->iq_pz,
		.nx = f->iq_nx, .ny = f->iq_ny, .nz = f->iq_nz,
		.nq = f->n,
		.qx = f->qx, .qy = f->qy, .qz = f->qz,
		.px = f->px, .py = f->py, .pz = f->pz,
		.qnx = f->nx, .qny = f->ny, .qnz = f->nz,
		.radius = FRONT_RADIUS, .far_d2 = FAR_DIST * FAR_DIST, .wall_min = WALL_MIN, .min_dot = out,
	};
}

static void test_front(void **state)
{
	fixture *f = *state;
	float *ref = malloc(f->n * sizeof *ref), *cl = malloc(f->n * sizeof *cl), *brute = malloc(f->n * sizeof *brute);
	dp_sink_front_args a = front_args(f, ref);
	dp_error err = {0};
	assert_int_equal(dp_op_sink_front(tk_ref_context(), &a, &err), DP_OK);
	a.min_dot = cl;
	if (dp_op_sink_front(tk_cl_context(), &a, &err) != DP_OK)
		fail_msg("%s", err.message);
	tk_assert_close(cl, ref, f->n, 1e-4f, 1e-5f, "sink_front");

	size_t fronts = 0, settles = 0;
	for (size_t i = 0; i < f->n; i++) {
		brute[i] = DP_SINK_NO_FRONT;
		for (size_t k = 0; k < f->n; k++)
			if (dist2(f->qx, f->qy, f->qz, i, k) < FRONT_RADIUS * FRONT_RADIUS &&
			    (dist2(f->px, f->py, f->pz, i, k) > FAR_DIST * FAR_DIST || wall(f, i, k)))
				brute[i] = fminf(brute[i], dot(f, i, k));
		fronts += brute[i] != DP_SINK_NO_FRONT;
		settles += brute[i] <= COS_OMEGA;
	}
	tk_assert_close(ref, brute, f->n, 1e-5f, 1e-6f, "sink_front vs brute force");
	/* The inputs exercise every outcome: no front, a front that does not
	 * settle, a front that settles, a partner only the thin-wall rule lets in. */
	assert_true(fronts < f->n && settles < fronts && settles > 0);
	assert_true(walls > 0);
	free(ref);
	free(cl);
	free(brute);
}

static void test_step(void **state)
{
	fixture *f = *state;
	float *ref = malloc(f->n * sizeof *ref), *cl = malloc(f->n * sizeof *cl), *brute = malloc(f->n * sizeof *brute);
	dp_sink_step_args a = {
		.surface = &f->surface, .move = f->sf_move, .stop = f->sf_stop, .nq = f->n, .px = f->px, .py = f->py,
		.pz = f->pz, .depth = f->depth, .radius = STATIC_RADIUS, .margin = STOP_MARGIN, .mean = ref,
	};
	dp_error err = {0};
	assert_int_equal(dp_op_sink_step(tk_ref_context(), &a, &err), DP_OK);
	a.mean = cl;
	if (dp_op_sink_step(tk_cl_context(), &a, &err) != DP_OK)
		fail_msg("%s", err.message);
	tk_assert_close(cl, ref, f->n, 1e-4f, 1e-6f, "sink_step");

	size_t dropped = 0, empty = 0;
	for (size_t i = 0; i < f->n; i++) {
		double sum = 0.0;
		int count = 0;
		for (size_t k = 0; k < f->n; k++) {
			if (!(dist2(f->px, f->py, f->pz, i, k) < STATIC_RADIUS * STATIC_RADIUS))
				continue;
			if (f->stop[k] < f->depth[i] - STOP_MARGIN) {
				dropped++;
				continue;
			}
			sum += f->move[k];
			count++;
		}
		empty += count == 0;
		brute[i] = count ? (float)(sum / count) : 0.0f;
	}
	/* Neighbours that stopped too shallow were left out, and some queries
	 * kept none. */
	assert_true(dropped > 0 && empty > 0);
	tk_assert_close(ref, brute, f->n, 1e-4f, 1e-6f, "sink_step vs brute force");

	/* Queries away from every surface point get 0. */
	float far_x = 10.0f * EXTENT, far_y = 0.0f, far_z = 0.0f, far_depth = 0.0f, out = -1.0f;
	a.nq = 1;
	a.px = &far_x;
	a.py = &far_y;
	a.pz = &far_z;
	a.depth = &far_depth;
	a.mean = &out;
	assert_int_equal(dp_op_sink_step(tk_cl_context(), &a, &err), DP_OK);
	assert_true(out == 0.0f);
	free(ref);
	free(cl);
	free(brute);
}

static void test_smooth(void **state)
{
	fixture *f = *state;
	size_t n = f->n;
	float *out[2][4];
	for (int b = 0; b < 2; b++)
		for (int c = 0; c < 4; c++)
			out[b][c] = malloc(n * sizeof(float));
	float phi_scale = 1.0f / (1.0f - COS_OMEGA);
	for (int b = 0; b < 2; b++) {
		dp_sink_smooth_args a = {
			.surface = &f->surface,
			.nx = f->sf_nx, .ny = f->sf_ny, .nz = f->sf_nz,
			.ix = f->sf_qx, .iy = f->sf_qy, .iz = f->sf_qz,
			.nq = n,
			.px = f->px, .py = f->py, .pz = f->pz,
			.qnx = f->nx, .qny = f->ny, .qnz = f->nz,
			.qx = f->qx, .qy = f->qy, .qz = f->qz,
			.radius = STATIC_RADIUS, .inv_r2 = 1.0f / (SPACING * SPACING), .phi_scale = phi_scale,
			.out_x = out[b][0], .out_y = out[b][1], .out_z = out[b][2], .out_w = out[b][3],
		};
		dp_error err = {0};
		if (dp_op_sink_smooth(b ? tk_cl_context() : tk_ref_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
	}
	const char *names[4] = {"sink_smooth x", "sink_smooth y", "sink_smooth z", "sink_smooth w"};
	for (int c = 0; c < 4; c++)
		tk_assert_close(out[1][c], out[0][c], n, 1e-4f, 1e-5f, names[c]);

	float *brute[4];
	for (int c = 0; c < 4; c++)
		brute[c] = malloc(n * sizeof(float));
	for (size_t i = 0; i < n; i++) {
		double s[4] = {0, 0, 0, 0};
		for (size_t k = 0; k < n; k++) {
			float d2 = dist2(f->px, f->py, f->pz, i, k);
			if (d2 >= STATIC_RADIUS * STATIC_RADIUS)
				continue;
			double u = (1.0 - dot(f, i, k)) * phi_scale;
			double w = exp(-d2 / (SPACING * SPACING) - u * u);
			s[0] += w * (f->qx[k] - f->qx[i]);
			s[1] += w * (f->qy[k] - f->qy[i]);
			s[2] += w * (f->qz[k] - f->qz[i]);
			s[3] += w;
		}
		assert_true(s[3] >= 1.0 - 1e-6); /* the point itself weighs 1 */
		for (int c = 0; c < 4; c++)
			brute[c][i] = (float)s[c];
	}
	for (int c = 0; c < 4; c++)
		tk_assert_close(out[0][c], brute[c], n, 1e-4f, 1e-5f, names[c]);
	for (int c = 0; c < 4; c++) {
		free(brute[c]);
		free(out[0][c]);
		free(out[1][c]);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_front),
		cmocka_unit_test(test_step),
		cmocka_unit_test(test_smooth),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
