/* dp_distinct: coincident points map to the first of their position. */
#include "testkit.h"

#include "core/distinct.h"

static void test_groups_exact_duplicates(void **state)
{
	(void)state;
	/* 0 and 3 coincide, 2 and 4 and 5 coincide; 1 is alone; -0.0 equals 0.0 */
	const float x[] = {1.0f, 2.0f, 3.0f, 1.0f, 3.0f, 3.0f, 0.0f, -0.0f};
	const float y[] = {1.0f, 2.0f, 3.0f, 1.0f, 3.0f, 3.0f, 0.0f, 0.0f};
	const float z[] = {1.0f, 2.0f, 3.0f, 1.0f, 3.0f, 3.0f, 0.0f, 0.0f};
	const uint32_t want[] = {0, 1, 2, 0, 2, 2, 6, 6};
	uint32_t of[8];
	size_t m = 0;
	dp_error err = {0};
	assert_int_equal(dp_distinct(8, x, y, z, of, &m, &err), DP_OK);
	assert_int_equal(m, 4);
	for (int i = 0; i < 8; i++)
		assert_int_equal(of[i], want[i]);
}

static void test_nearby_points_stay_distinct(void **state)
{
	(void)state;
	const float x[] = {1.0f, 1.0000001f, 1.0f}, y[] = {0, 0, 0}, z[] = {0, 0, 1e-30f};
	uint32_t of[3];
	size_t m = 0;
	assert_int_equal(dp_distinct(3, x, y, z, of, &m, NULL), DP_OK);
	assert_int_equal(m, 3);
	assert_int_equal(dp_distinct(0, x, y, z, of, &m, NULL), DP_OK);
	assert_int_equal(m, 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_groups_exact_duplicates),
		cmocka_unit_test(test_nearby_points_stay_distinct),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
