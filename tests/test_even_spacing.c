/* Even-spacing rounds (dp_refine_even, dp_refine_params.even_rounds): points
 * move from a dense half of a sphere to its sparse half with their inner
 * ends, an even sampling is left alone, and the pipeline on a one-view scan
 * ends with a more even spacing and every output in step. */
#include "testkit.h"

#include "stages/refine.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Points on the unit sphere with outward normals and inner ends at half the
 * radius: `upper` spread evenly over z > 0 and `lower` over z < 0, or with
 * `lower` 0 `upper` spread evenly over the whole sphere. */
static void two_density_sphere(size_t upper, size_t lower, dp_cloud *s, dp_cloud *k)
{
	dp_error err = {0};
	size_t n = upper + lower;
	if (dp_cloud_alloc(s, n, 1, &err) != DP_OK || dp_cloud_alloc(k, n, 1, &err) != DP_OK)
		fail_msg("%s", err.message);
	double golden = M_PI * (3.0 - sqrt(5.0));
	for (size_t i = 0; i < n; i++) {
		int top = i < upper;
		size_t j = top ? i : i - upper, m = top ? upper : lower;
		/* even in z over a hemisphere is even in area (Archimedes) */
		double z = lower ? (top ? 1.0 : -1.0) * (1.0 - ((double)j + 0.5) / (double)m)
				 : 1.0 - 2.0 * ((double)i + 0.5) / (double)n;
		double rho = sqrt(1.0 - z * z), a = golden * (double)j;
		s->x[i] = s->nx[i] = (float)(rho * cos(a));
		s->y[i] = s->ny[i] = (float)(rho * sin(a));
		s->z[i] = s->nz[i] = (float)z;
		k->x[i] = 0.5f * s->x[i], k->y[i] = 0.5f * s->y[i], k->z[i] = 0.5f * s->z[i];
		k->nx[i] = s->nx[i], k->ny[i] = s->ny[i], k->nz[i] = s->nz[i];
	}
	s->n = k->n = n;
}

static size_t below_equator(const dp_cloud *s)
{
	size_t c = 0;
	for (size_t i = 0; i < s->n; i++)
		c += s->z[i] < 0.0f;
	return c;
}

/* Whether (x, y, z) is one of the first n inner ends of k0. */
static int is_inner_end(const dp_cloud *k0, size_t n, float x, float y, float z)
{
	for (size_t j = 0; j < n; j++)
		if (k0->x[j] == x && k0->y[j] == y && k0->z[j] == z)
			return 1;
	return 0;
}

/* A sphere sampled five times as densely on top (the one-view bunny's
 * scanned side is about four times as dense as its completed side, with 72%
 * of the points, at 4026 deep points): the count stays, points
 * go from the top to the bottom, every point stays on the sphere, and every
 * row's inner end is an original inner end (a kept point keeps its own).
 * A kept point keeps its row too, and each moved one's row, marked as
 * replaced, holds a new point in the sparse half: the pipeline's inside test
 * names deep points by row. */
static void test_moves_dense_to_sparse(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud s = {0}, k = {0}, s0 = {0}, k0 = {0};
	two_density_sphere(1000, 200, &s, &k);
	two_density_sphere(1000, 200, &s0, &k0);
	size_t n = s.n, moved = 0, lower0 = below_equator(&s);
	unsigned char *replaced = calloc(n, 1);
	assert_non_null(replaced);
	if (dp_refine_even(&s, &k, replaced, &moved, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t marked = 0;
	for (size_t i = 0; i < n; i++) {
		int same = s.x[i] == s0.x[i] && s.y[i] == s0.y[i] && s.z[i] == s0.z[i] && s.nx[i] == s0.nx[i] &&
			   s.ny[i] == s0.ny[i] && s.nz[i] == s0.nz[i] && k.x[i] == k0.x[i] && k.y[i] == k0.y[i] &&
			   k.z[i] == k0.z[i];
		marked += replaced[i];
		if (replaced[i]) {
			assert_true(s0.z[i] > 0.0f && s.z[i] < 0.0f);
		} else {
			assert_true(same);
		}
	}
	assert_int_equal(marked, moved);
	free(replaced);
	size_t lower = below_equator(&s);
	printf("1200 points, 1000 on top: moved %zu, below the equator %zu -> %zu\n", moved, lower0, lower);
	assert_int_equal(s.n, n);
	assert_int_equal(k.n, n);
	assert_true(moved > 0 && moved <= n / 10);
	/* every moved point landed in the sparse half */
	assert_int_equal(lower, lower0 + moved);
	for (size_t i = 0; i < n; i++) {
		float rad = sqrtf(s.x[i] * s.x[i] + s.y[i] * s.y[i] + s.z[i] * s.z[i]);
		assert_true(fabsf(rad - 1.0f) < 0.01f);
		assert_true(fabsf(s.nx[i] * s.nx[i] + s.ny[i] * s.ny[i] + s.nz[i] * s.nz[i] - 1.0f) < 1e-3f);
		assert_true(is_inner_end(&k0, n, k.x[i], k.y[i], k.z[i]));
		for (size_t j = 0; j < n; j++)
			if (s0.x[j] == s.x[i] && s0.y[j] == s.y[i] && s0.z[j] == s.z[i]) {
				assert_true(k.x[i] == k0.x[j] && k.y[i] == k0.y[j] && k.z[i] == k0.z[j]);
				break;
			}
	}
	dp_cloud_free(&s);
	dp_cloud_free(&k);
	dp_cloud_free(&s0);
	dp_cloud_free(&k0);
}

/* An even sampling has no spot denser than the threshold: nothing moves and
 * the rows come back as they were. */
static void test_even_left_alone(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud s = {0}, k = {0}, s0 = {0}, k0 = {0};
	two_density_sphere(1200, 0, &s, &k);
	two_density_sphere(1200, 0, &s0, &k0);
	size_t moved = 1;
	if (dp_refine_even(&s, &k, NULL, &moved, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(moved, 0);
	assert_int_equal(s.n, s0.n);
	size_t bytes = s.n * sizeof(float);
	assert_memory_equal(s.x, s0.x, bytes);
	assert_memory_equal(s.nz, s0.nz, bytes);
	assert_memory_equal(k.y, k0.y, bytes);
	dp_cloud_free(&s);
	dp_cloud_free(&k);
	dp_cloud_free(&s0);
	dp_cloud_free(&k0);
}

/* Mismatched rows are refused, not read past. */
static void test_refuses_mismatch(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud s = {0}, k = {0};
	two_density_sphere(60, 60, &s, &k);
	k.n = 100;
	size_t moved = 7;
	assert_int_equal(dp_refine_even(&s, &k, NULL, &moved, &err), DP_ERR_ARG);
	assert_int_equal(moved, 0);
	k.n = s.n;
	dp_cloud_free(&s);
	dp_cloud_free(&k);
}

/* The pipeline on a one-view sphere scan: with the rounds the spacing is more
 * even than without, the outputs stay in step, and the moves are reported. */
static void test_pipeline_one_view(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud mesh = {0}, scan = {0};
	tk_scan_shape("sphere", 1, 48, 0.002, 1, NULL, &mesh, &scan);
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = 1500;
	dp_result off = {0}, on = {0};
	if (dp_consolidate(tk_cl_context(), &scan, &p, &off, &err) != DP_OK)
		fail_msg("%s", err.message);
	p.refine.even_rounds = 3;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &on, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_eval_result eo, ee;
	if (dp_eval(&mesh, &off.surface, NULL, &eo, &err) != DP_OK || dp_eval(&mesh, &on.surface, NULL, &ee, &err) != DP_OK)
		fail_msg("%s", err.message);
	double cv_off = eo.spacing_cv, cv_on = ee.spacing_cv;
	printf("one-view sphere, 1500 deep points: spacing variation %.3f -> %.3f, coverage %.3f -> %.3f, "
	       "flipped %.4f -> %.4f, %zu moved\n",
	       cv_off, cv_on, eo.coverage, ee.coverage, eo.normal_flipped, ee.normal_flipped, on.even_moved);
	assert_int_equal(off.even_moved, 0);
	assert_true(on.even_moved > 0);
	tk_assert_rows_in_step(&on, 1500);
	assert_true(cv_on < cv_off);
	assert_true(ee.coverage >= 0.9);
	assert_true(ee.normal_flipped <= 0.01);
	dp_result_free(&off);
	dp_result_free(&on);
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_moves_dense_to_sparse),
		cmocka_unit_test(test_even_left_alone),
		cmocka_unit_test(test_refuses_mismatch),
		cmocka_unit_test(test_pipeline_one_view),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
