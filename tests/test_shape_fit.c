/* dp_shape_fit_points on point sets whose answers follow by hand. */
#include "testkit.h"

#include <math.h>
#include <string.h>

#define TOL 1e-5

static void put(dp_cloud *c, size_t i, double x, double y, double z)
{
	c->x[i] = (float)x;
	c->y[i] = (float)y;
	c->z[i] = (float)z;
}

static dp_shape shape(const char *name)
{
	dp_shape s;
	dp_error err = {0};
	assert_int_equal(dp_shape_default(name, &s, &err), DP_OK);
	return s;
}

/* Ten points evenly on the core circle and one stray outside the tube in
 * the middle of a gap: the stray counts for the distances, not the gap. */
static void test_torus(void **state)
{
	(void)state;
	dp_shape s = shape("torus");
	dp_cloud c = {0};
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(&c, 11, 0, &err), DP_OK);
	for (int k = 0; k < 10; k++)
		put(&c, (size_t)k, s.radius * cos(0.2 * M_PI * k), s.radius * sin(0.2 * M_PI * k), 0.0);
	double a = 0.1 * M_PI, far = s.radius + 2.0 * s.tube;
	put(&c, 10, far * cos(a), far * sin(a), 0.0);
	double len = 2.0 * M_PI * s.radius, cell = len / 40.0;
	dp_shape_fit f;
	assert_int_equal(dp_shape_fit_points(&s, &c, cell, &f, &err), DP_OK);
	assert_int_equal(f.points, 11);
	assert_int_equal(f.inside, 10);
	assert_true(fabs(f.largest_gap - 0.1) < TOL);
	assert_true(fabs(f.spread - 0.25) < TOL); /* 10 cells of a quarter gap each */
	assert_true(fabs(f.skeleton_mean - 2.0 * s.tube / 11.0) < TOL);
	assert_true(fabs(f.surface_mean - (10.0 * s.tube + s.tube) / 11.0) < TOL);
	/* A cell longer than the gaps covers the circle once, not more. */
	assert_int_equal(dp_shape_fit_points(&s, &c, len / 5.0, &f, &err), DP_OK);
	assert_true(fabs(f.spread - 1.0) < TOL);
	dp_cloud_free(&c);
}

/* Two points on the axis at a quarter of the length from each end: they
 * cover one cell each, and the gap is the half between them. */
static void test_cylinder(void **state)
{
	(void)state;
	dp_shape s = shape("cylinder");
	dp_cloud c = {0};
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(&c, 2, 0, &err), DP_OK);
	put(&c, 0, 0.0, 0.0, -0.25 * s.length);
	put(&c, 1, 0.0, 0.0, 0.25 * s.length);
	dp_shape_fit f;
	double cell = 0.1 * s.length;
	assert_int_equal(dp_shape_fit_points(&s, &c, cell, &f, &err), DP_OK);
	assert_int_equal(f.inside, 2);
	assert_true(fabs(f.spread - 0.2) < TOL);
	assert_true(fabs(f.largest_gap - 0.5) < TOL);
	assert_true(fabs(f.skeleton_mean) < TOL);
	assert_true(fabs(f.surface_mean - s.radius) < TOL);
	/* Near the ends a point covers only what lies inside the length. */
	put(&c, 0, 0.0, 0.0, -0.5 * s.length);
	assert_int_equal(dp_shape_fit_points(&s, &c, cell, &f, &err), DP_OK);
	assert_true(fabs(f.spread - 0.15) < TOL);
	dp_cloud_free(&c);
}

/* Points in 3 of the 4 quarters of the mid-plane (cell W/2), one of them
 * twice, and one above the slab that does not count. */
static void test_slab(void **state)
{
	(void)state;
	dp_shape s = shape("slab");
	dp_cloud c = {0};
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(&c, 5, 0, &err), DP_OK);
	double q = 0.25 * s.width;
	put(&c, 0, -q, -q, 0.0);
	put(&c, 1, q, -q, 0.0);
	put(&c, 2, -q, q, 0.0);
	put(&c, 3, -q, q + 0.1 * q, 0.0);
	put(&c, 4, q, q, s.thickness);
	dp_shape_fit f;
	assert_int_equal(dp_shape_fit_points(&s, &c, 0.5 * s.width, &f, &err), DP_OK);
	assert_int_equal(f.inside, 4);
	assert_true(fabs(f.spread - 0.75) < TOL);
	assert_true(isnan(f.largest_gap));
	assert_true(fabs(f.skeleton_mean - s.thickness / 5.0) < TOL);
	dp_cloud_free(&c);
}

static void test_sphere_and_errors(void **state)
{
	(void)state;
	dp_shape s = shape("sphere");
	dp_cloud c = {0};
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(&c, 2, 0, &err), DP_OK);
	put(&c, 0, 0.0, 0.0, 0.0);
	put(&c, 1, 2.0 * s.radius, 0.0, 0.0);
	dp_shape_fit f;
	assert_int_equal(dp_shape_fit_points(&s, &c, 0.1, &f, &err), DP_OK);
	assert_true(isnan(f.spread) && isnan(f.largest_gap));
	assert_true(fabs(f.skeleton_mean - s.radius) < TOL);
	assert_true(fabs(f.surface_mean - s.radius) < TOL);

	assert_int_equal(dp_shape_fit_points(&s, &c, 0.0, &f, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "shape fit"));
	c.x[1] = NAN;
	assert_int_equal(dp_shape_fit_points(&s, &c, 0.1, &f, &err), DP_ERR_ARG);
	dp_cloud empty = {0};
	assert_int_equal(dp_shape_fit_points(&s, &empty, 0.1, &f, &err), DP_ERR_EMPTY);
	s.radius = -1.0;
	assert_int_equal(dp_shape_fit_points(&s, &c, 0.1, &f, &err), DP_ERR_ARG);
	dp_shape slab = shape("slab");
	assert_int_equal(dp_shape_fit_points(&slab, &c, 1e-6, &f, &err), DP_ERR_ARG);
	dp_cloud_free(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_torus),
		cmocka_unit_test(test_cylinder),
		cmocka_unit_test(test_slab),
		cmocka_unit_test(test_sphere_and_errors),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
