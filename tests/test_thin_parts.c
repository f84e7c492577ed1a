/* Thin parts through the whole pipeline at the default options: the built-in
 * rods (radius under 3 r at the default deep-point count, thinner than the
 * σp = 5 r neighbourhoods of sinking and surface) scanned from two sides.
 * The surface must stay on the rods and the skeleton inside them, not turn
 * into a cloud around them. */
#include "testkit.h"

#include <math.h>

/* Targets, in units of r: the surface within half a spacing of the true
 * surface on average; the skeleton points inside the rods. */
#define SURFACE_MEAN_R 0.5
#define INSIDE_FRACTION 0.95

static void test_rods_two_views(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_shape shape;
	dp_cloud scan = {0};
	tk_scan_shape("rods", 2, 200, 0.003, 7, &shape, NULL, &scan);
	dp_result res = {0};
	if (dp_consolidate(tk_cl_context(), &scan, NULL, &res, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_shape_fit su, sk;
	if (dp_shape_fit_points(&shape, &res.surface, shape.radius, &su, &err) != DP_OK ||
	    dp_shape_fit_points(&shape, &res.skeleton, shape.radius, &sk, &err) != DP_OK)
		fail_msg("%s", err.message);
	double inside = (double)sk.inside / (double)sk.points;
	printf("rods of radius %.2f r, %zu raw -> %zu deep points: surface %.3f r from the rods, skeleton %.3f r "
	       "from the axes, %.3f of it inside the rods\n",
	       shape.radius / res.r, scan.n, res.surface.n, su.surface_mean / res.r, sk.skeleton_mean / res.r,
	       inside);
	assert_true(shape.radius / res.r < 3.0);
	assert_true(su.surface_mean / res.r <= SURFACE_MEAN_R);
	assert_true(inside >= INSIDE_FRACTION);
	dp_result_free(&res);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_rods_two_views),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
