/* Issue 9, defect 2: coordinates so far apart that squared distances
 * overflow a float. FLANN then finds fewer neighbours than asked and left the
 * rest of its buffers unwritten, which the normals read as neighbour ids (a
 * segfault). Such inputs are refused with a message; no neighbour slot is
 * ever left unwritten. */
#include "knn/knn.h"
#include "testkit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NSPHERE 20

/* NSPHERE points spread over the unit sphere, then `extra` given points;
 * with normal arrays. */
static void sphere_cloud(dp_cloud *c, const float (*extra)[3], size_t nextra)
{
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(c, NSPHERE + nextra, 1, &err), DP_OK);
	for (size_t i = 0; i < NSPHERE; i++) {
		double t = acos(1 - 2 * (i + 0.5) / NSPHERE), p = M_PI * (1 + sqrt(5.0)) * (double)i;
		c->x[i] = (float)(sin(t) * cos(p));
		c->y[i] = (float)(sin(t) * sin(p));
		c->z[i] = (float)cos(t);
	}
	for (size_t i = 0; i < nextra; i++) {
		c->x[NSPHERE + i] = extra[i][0];
		c->y[NSPHERE + i] = extra[i][1];
		c->z[NSPHERE + i] = extra[i][2];
	}
}

/* A query whose squared distance to every indexed point overflows: no
 * neighbour is found, and every slot says so instead of holding whatever the
 * buffer held. */
static void test_query_finds_nothing(void **state)
{
	(void)state;
	dp_cloud c = {0};
	dp_error err = {0};
	sphere_cloud(&c, NULL, 0);
	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, c.n, c.x, c.y, c.z, &err), DP_OK);
	enum { K = 8, NQ = 3 };
	float qx[NQ] = {1e20f, -3e19f, 0}, qy[NQ] = {0, 3e19f, 0}, qz[NQ] = {0, 0, 2e19f};
	int idx[NQ * K];
	float d2[NQ * K];
	memset(idx, 0, sizeof idx);
	memset(d2, 0, sizeof d2);
	assert_int_equal(dp_knn_query(&knn, NQ, qx, qy, qz, K, idx, d2, &err), DP_OK);
	for (int j = 0; j < NQ * K; j++) {
		if (idx[j] != -1 || !isinf(d2[j]))
			fail_msg("slot %d: index %d, d2 %g; expected -1 and infinity (nothing found)", j, idx[j],
				 (double)d2[j]);
	}
	dp_knn_free(&knn);
	dp_cloud_free(&c);
}

/* Twenty points on a unit sphere and one at 1e20 (the input). */
static void test_far_outlier_refused(void **state)
{
	(void)state;
	const float far[1][3] = {{1e20f, 0, 0}};
	dp_cloud c = {0};
	dp_error err = {0};
	sphere_cloud(&c, far, 1);
	assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "too large a range"));
	assert_null(strchr(err.message, '\n'));

	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = c.n;
	dp_cloud s = {0};
	assert_int_equal(dp_wlop(tk_ref_context(), &c, &p, &s, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "too large a range"));
	assert_null(s.x);

	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, c.n, c.x, c.y, c.z, &err), DP_ERR_ARG);
	dp_cloud_free(&c);

	/* far, but squared distances still fit: accepted, every slot a real point */
	const float near_enough[1][3] = {{1e18f, 0, 0}};
	sphere_cloud(&c, near_enough, 1);
	assert_int_equal(dp_knn_build(&knn, c.n, c.x, c.y, c.z, &err), DP_OK);
	int idx[(NSPHERE + 1) * 4];
	float d2[(NSPHERE + 1) * 4];
	assert_int_equal(dp_knn_self(&knn, 4, idx, d2, &err), DP_OK);
	for (size_t j = 0; j < c.n * 4; j++)
		assert_true(idx[j] >= 0 && (size_t)idx[j] < c.n && isfinite(d2[j]));
	dp_knn_free(&knn);
	dp_cloud_free(&c);
}

/* --radius 1e30: h^2 overflows in every kernel. */
static void test_huge_radius_refused(void **state)
{
	(void)state;
	dp_cloud c = {0}, s = {0};
	dp_error err = {0};
	sphere_cloud(&c, NULL, 0);
	dp_wlop_params p;
	dp_wlop_params_default(&p);
	p.samples = 10;
	p.h = 1e30;
	assert_int_equal(dp_wlop(tk_ref_context(), &c, &p, &s, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "too large"));
	assert_null(s.x);
	p.h = 1e6;
	assert_int_equal(dp_wlop(tk_ref_context(), &c, &p, &s, NULL, &err), DP_OK);
	dp_cloud_free(&s);
	dp_cloud_free(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_query_finds_nothing),
		cmocka_unit_test(test_far_outlier_refused),
		cmocka_unit_test(test_huge_radius_refused),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
