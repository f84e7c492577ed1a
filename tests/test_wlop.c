/* The WLOP stage (host/stages/wlop.c): input checks, both backends giving the
 * same samples, and the denoising/uniformity targets of issue 2 on CGAL's
 * noisy sphere. */
#include "testkit.h"

#include "knn/knn.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Small noisy sphere for the backend comparison. */
#define SMALL_N 4000
#define SMALL_M 400
#define SMALL_NOISE 0.02
#define SMALL_ITERS 6
/* Float sums in a different order drift by ~1e-6 per step; a sample that
 * differs by more than this fraction of h has followed another path. */
#define AGREE_TOL_H 1e-4

/* Issue 2's targets on cgal/sphere_20k.xyz (unit sphere, noise sigma 0.04). */
#define SPHERE_FILE "cgal/sphere_20k.xyz"
#define SPHERE_M 2100
#define SPHERE_MAX_RADIAL_STD 0.005
#define SPHERE_MAX_SPACING_CV 0.25
#define SPHERE_MIN_OUTWARD 0.99

static void noisy_sphere(dp_cloud *c, size_t n, double noise, uint64_t seed)
{
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(c, n, 0, &err), DP_OK);
	dp_rng rng;
	dp_rng_seed(&rng, seed);
	for (size_t i = 0; i < n; i++) {
		double v[3], len;
		do {
			for (int a = 0; a < 3; a++)
				v[a] = dp_rng_normal(&rng);
			len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
		} while (len < 1e-6);
		c->x[i] = (float)(v[0] / len + noise * dp_rng_normal(&rng));
		c->y[i] = (float)(v[1] / len + noise * dp_rng_normal(&rng));
		c->z[i] = (float)(v[2] / len + noise * dp_rng_normal(&rng));
	}
}

static dp_status run(dp_context *ctx, const dp_cloud *in, const dp_wlop_params *p, dp_cloud *out,
		     dp_wlop_stats *st, dp_error *err)
{
	memset(err, 0, sizeof *err);
	return dp_wlop(ctx, in, p, out, st, err);
}

static void test_rejects_bad_input(void **state)
{
	(void)state;
	dp_context *ctx = tk_ref_context();
	dp_cloud in, out;
	dp_error err;
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	noisy_sphere(&in, 100, 0.0, 1);

	dp_cloud empty = {0};
	assert_int_equal(run(ctx, &empty, &p, &out, NULL, &err), DP_ERR_EMPTY);
	assert_non_null(strstr(err.message, "wlop"));
	assert_null(out.x);

	p.samples = 101;
	assert_int_equal(run(ctx, &in, &p, &out, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "101"));
	assert_null(out.x);

	p.samples = 0;
	p.ratio = 0.001; /* rounds to no sample of 100 points */
	assert_int_equal(run(ctx, &in, &p, &out, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "no samples"));

	dp_wlop_params_default(&p);
	p.mu = 0.5;
	assert_int_equal(run(ctx, &in, &p, &out, NULL, &err), DP_ERR_ARG);
	dp_wlop_params_default(&p);
	p.theta_k = 0.0;
	assert_int_equal(run(ctx, &in, &p, &out, NULL, &err), DP_ERR_ARG);
	dp_wlop_params_default(&p);
	p.weight = (dp_wlop_weight)7;
	assert_int_equal(run(ctx, &in, &p, &out, NULL, &err), DP_ERR_ARG);

	dp_wlop_params_default(&p);
	in.y[42] = NAN;
	assert_int_equal(run(ctx, &in, &p, &out, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "42"));
	assert_null(out.x);
	dp_cloud_free(&in);
}

/* Exact duplicates in the input must not become coincident samples (they
 * would skip each other's repulsion for ever); asking for more samples than
 * there are distinct positions is an error. */
static void test_duplicates(void **state)
{
	(void)state;
	const size_t distinct = 60, copies = 4;
	dp_cloud base, in, out;
	dp_error err;
	noisy_sphere(&base, distinct, 0.0, 2);
	assert_int_equal(dp_cloud_alloc(&in, distinct * copies, 0, &err), DP_OK);
	for (size_t i = 0; i < in.n; i++) {
		in.x[i] = base.x[i % distinct];
		in.y[i] = base.y[i % distinct];
		in.z[i] = base.z[i % distinct];
	}
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = distinct;
	p.max_iters = 0;
	dp_wlop_stats st;
	assert_int_equal(run(tk_ref_context(), &in, &p, &out, &st, &err), DP_OK);
	assert_int_equal(out.n, distinct);
	for (size_t i = 0; i < out.n; i++)
		for (size_t j = 0; j < i; j++)
			assert_false(out.x[i] == out.x[j] && out.y[i] == out.y[j] && out.z[i] == out.z[j]);
	dp_cloud_free(&out);

	p.samples = distinct + 1;
	assert_int_equal(run(tk_ref_context(), &in, &p, &out, &st, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "distinct"));
	dp_cloud_free(&in);
	dp_cloud_free(&base);
}

static double worst_difference(const dp_cloud *a, const dp_cloud *b)
{
	double worst = 0.0;
	for (size_t i = 0; i < a->n; i++) {
		double dx = a->x[i] - b->x[i], dy = a->y[i] - b->y[i], dz = a->z[i] - b->z[i];
		worst = fmax(worst, sqrt(dx * dx + dy * dy + dz * dz));
	}
	return worst;
}

static void compare_backends(const dp_cloud *in, const dp_wlop_params *p, const char *what)
{
	dp_cloud ref, cl;
	dp_wlop_stats sr, sc;
	dp_error err;
	assert_int_equal(run(tk_ref_context(), in, p, &ref, &sr, &err), DP_OK);
	if (run(tk_cl_context(), in, p, &cl, &sc, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(ref.n, SMALL_M);
	assert_int_equal(cl.n, SMALL_M);
	assert_int_equal(sr.iterations, SMALL_ITERS);
	assert_int_equal(sc.iterations, SMALL_ITERS);
	assert_true(fabs(sr.h - sc.h) <= 1e-6 * sr.h);
	assert_true(sr.pair_evaluations > 0.0 && sr.pair_evaluations == sc.pair_evaluations);
	/* The samples really moved, so the agreement below means something. */
	dp_cloud start;
	dp_wlop_params p0 = *p;
	p0.max_iters = 0;
	assert_int_equal(run(tk_ref_context(), in, &p0, &start, NULL, &err), DP_OK);
	double moved = worst_difference(&ref, &start), diff = worst_difference(&ref, &cl);
	printf("%s: h %.4f, largest move %.3g h, largest backend difference %.3g h\n", what, sr.h, moved / sr.h,
	       diff / sr.h);
	assert_true(moved > 0.1 * sr.h);
	if (!(diff <= AGREE_TOL_H * sr.h))
		fail_msg("%s: ref and cl samples differ by %.3g h", what, diff / sr.h);
	dp_cloud_free(&start);
	dp_cloud_free(&ref);
	dp_cloud_free(&cl);
}

static void test_backends_agree(void **state)
{
	(void)state;
	dp_cloud in;
	noisy_sphere(&in, SMALL_N, SMALL_NOISE, 3);
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = SMALL_M;
	p.max_iters = SMALL_ITERS;
	p.tol = 0.0;
	compare_backends(&in, &p, "defaults");
	/* Every variant flipped: Huang et al.'s L1 weight and θ, sqrt density. */
	p.weight = DP_WLOP_L1;
	p.theta_k = 16.0;
	p.sqrt_density = 1;
	p.h_factor = 8.0;
	compare_backends(&in, &p, "variants");
	dp_cloud_free(&in);
}

/* Radial deviation and nearest-neighbour spacing uniformity on CGAL's noisy
 * unit sphere, on the OpenCL backend (the reference would take too long). */
static void test_sphere_20k(void **state)
{
	(void)state;
	const char *path = tk_data_path(SPHERE_FILE);
	if (!path)
		skip();
	dp_cloud in, out;
	dp_error err = {0};
	if (dp_cloud_read(path, &in, DP_READ_POINTS, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = SPHERE_M;
	dp_wlop_stats st;
	if (run(tk_cl_context(), &in, &p, &out, &st, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(out.n, SPHERE_M);

	double sum = 0.0, sum2 = 0.0;
	for (size_t i = 0; i < out.n; i++) {
		double r = sqrt((double)out.x[i] * out.x[i] + (double)out.y[i] * out.y[i] + (double)out.z[i] * out.z[i]);
		sum += r;
		sum2 += r * r;
	}
	double mean = sum / (double)out.n, radial_std = sqrt(fmax(sum2 / (double)out.n - mean * mean, 0.0));

	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, out.n, out.x, out.y, out.z, &err), DP_OK);
	int *idx = malloc(out.n * sizeof *idx);
	float *d2 = malloc(out.n * sizeof *d2);
	assert_int_equal(dp_knn_self(&knn, 1, idx, d2, &err), DP_OK);
	double s = 0.0, s2 = 0.0;
	for (size_t i = 0; i < out.n; i++) {
		double d = sqrt((double)d2[i]);
		s += d;
		s2 += d * d;
	}
	double nn_mean = s / (double)out.n, cv = sqrt(fmax(s2 / (double)out.n - nn_mean * nn_mean, 0.0)) / nn_mean;
	printf("sphere_20k -> %d: h %.4f, %d iterations (converged %d, last mean move %.4f h, largest %.4f h), "
	       "radius %.4f with std %.5f, NN spacing %.4f with variation %.3f, %.2f s\n",
	       SPHERE_M, st.h, st.iterations, st.converged, st.last_mean_move, st.last_max_move, mean, radial_std,
	       nn_mean, cv, st.seconds);
	assert_true(st.converged);
	assert_true(radial_std < SPHERE_MAX_RADIAL_STD);
	assert_true(cv < SPHERE_MAX_SPACING_CV);

	/* the stage's output with its oriented normals, as `dpoints wlop` writes it */
	assert_int_equal(dp_estimate_normals(&out, NULL, &err), DP_OK);
	size_t outward = 0;
	for (size_t i = 0; i < out.n; i++)
		outward += out.nx[i] * out.x[i] + out.ny[i] * out.y[i] + out.nz[i] * out.z[i] > 0.0f;
	printf("sphere_20k -> %d: %.4f of the normals point outwards\n", SPHERE_M, (double)outward / (double)out.n);
	assert_true((double)outward >= SPHERE_MIN_OUTWARD * (double)out.n);
	free(idx);
	free(d2);
	dp_knn_free(&knn);
	dp_cloud_free(&in);
	dp_cloud_free(&out);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_rejects_bad_input),
		cmocka_unit_test(test_duplicates),
		cmocka_unit_test(test_backends_agree),
		cmocka_unit_test(test_sphere_20k),
	};
	int rc = cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
	return tk_exit_status(rc);
}
