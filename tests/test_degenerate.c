/* Issue 9, defect 6: inputs that span no volume (3 points, a line, a plane)
 * went through consolidate with exit 0 and a skeleton far outside the input's
 * box. They are refused before any stage runs, and a result point far from
 * the input is an error, never an output. */
#include "stages/input_check.h"
#include "testkit.h"

#include <math.h>
#include <string.h>

static int is_zeroed(const dp_result *r)
{
	static const dp_result zero;
	return memcmp(r, &zero, sizeof zero) == 0;
}

static void expect_refused(dp_cloud *in, const char *needle)
{
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = in->n < 20 ? in->n : 20;
	dp_result res;
	memset(&res, 0xab, sizeof res);
	dp_error err = {0};
	dp_status st = dp_consolidate(tk_ref_context(), in, &p, &res, &err);
	if (st != DP_ERR_ARG || !strstr(err.message, needle))
		fail_msg("%zu points: expected DP_ERR_ARG with '%s', got %d: %s", in->n, needle, st, err.message);
	assert_null(strchr(err.message, '\n'));
	assert_true(is_zeroed(&res));
	dp_cloud_free(in);
}

static void test_no_volume(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud c = {0};
	/* the first case: three points in a 2-unit box */
	assert_int_equal(dp_cloud_alloc(&c, 3, 0, &err), DP_OK);
	const float three[3][3] = {{-1, -1, -1}, {1, 0.5f, -0.2f}, {0.3f, 1, 1}};
	for (int i = 0; i < 3; i++) {
		c.x[i] = three[i][0];
		c.y[i] = three[i][1];
		c.z[i] = three[i][2];
	}
	expect_refused(&c, "span no volume");

	/* collinear, on a slanted line far from the origin */
	assert_int_equal(dp_cloud_alloc(&c, 200, 0, &err), DP_OK);
	for (size_t i = 0; i < c.n; i++) {
		float t = (float)i / 100.0f;
		c.x[i] = 100 + t;
		c.y[i] = -50 + 2 * t;
		c.z[i] = 3 * t;
	}
	expect_refused(&c, "on a line");

	/* coplanar: a jittered grid in a slanted plane */
	dp_rng rng;
	dp_rng_seed(&rng, 3);
	assert_int_equal(dp_cloud_alloc(&c, 400, 0, &err), DP_OK);
	for (size_t i = 0; i < c.n; i++) {
		double u = (double)(i % 20) + 0.3 * dp_rng_uniform(&rng), v = (double)(i / 20) + 0.3 * dp_rng_uniform(&rng);
		c.x[i] = (float)u;
		c.y[i] = (float)v;
		c.z[i] = (float)(0.5 * u - 0.25 * v);
	}
	expect_refused(&c, "in a plane");

	/* all at one position: WLOP's count of distinct positions says so */
	assert_int_equal(dp_cloud_alloc(&c, 50, 0, &err), DP_OK);
	for (size_t i = 0; i < c.n; i++)
		c.x[i] = c.y[i] = c.z[i] = 7;
	expect_refused(&c, "1 distinct position,");
}

/* A thin but solid slab (a thousandth of its extent) is not flat. */
static void test_thin_solid_accepted(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud c = {0};
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	assert_int_equal(dp_cloud_alloc(&c, 400, 0, &err), DP_OK);
	for (size_t i = 0; i < c.n; i++) {
		c.x[i] = (float)dp_rng_uniform(&rng);
		c.y[i] = (float)dp_rng_uniform(&rng);
		c.z[i] = (float)(0.001 * dp_rng_uniform(&rng));
	}
	assert_int_equal(dp_check_volume(&c, &err), DP_OK);
	dp_cloud_free(&c);
}

/* The bound every stage's points must keep: the input's box grown by its
 * diagonal. */
static void test_result_bounds(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud in = {0};
	assert_int_equal(dp_cloud_alloc(&in, 2, 0, &err), DP_OK);
	in.x[0] = in.y[0] = in.z[0] = -1;
	in.x[1] = in.y[1] = in.z[1] = 1;
	dp_result res;
	memset(&res, 0, sizeof res);
	dp_cloud *sets[] = {&res.wlop, &res.skeleton, &res.surface};
	for (int k = 0; k < 3; k++) {
		assert_int_equal(dp_cloud_alloc(sets[k], 2, 0, &err), DP_OK);
		/* 1 + diagonal (3.46) is the bound: 4 is inside */
		sets[k]->x[0] = 4;
		sets[k]->y[0] = -4;
		sets[k]->z[0] = 0;
	}
	assert_int_equal(dp_check_result_bounds(&in, &res, &err), DP_OK);
	const char *names[] = {"wlop", "skeleton", "surface"};
	for (int k = 0; k < 3; k++) {
		/* the skeleton: 89 units outside a 2-unit box */
		sets[k]->x[1] = 90;
		assert_int_equal(dp_check_result_bounds(&in, &res, &err), DP_ERR_ARG);
		assert_non_null(strstr(err.message, names[k]));
		assert_non_null(strstr(err.message, "far outside"));
		sets[k]->x[1] = NAN;
		assert_int_equal(dp_check_result_bounds(&in, &res, &err), DP_ERR_ARG);
		sets[k]->x[1] = 0;
	}
	assert_int_equal(dp_check_result_bounds(&in, &res, &err), DP_OK);
	dp_result_free(&res);
	dp_cloud_free(&in);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_no_volume),
		cmocka_unit_test(test_thin_solid_accepted),
		cmocka_unit_test(test_result_bounds),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
