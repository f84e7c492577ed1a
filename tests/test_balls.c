/* The surface stage's ball set (host/stages/balls.h): contained balls are
 * pruned, and the deepest ball a point faces is found, or none. */
#include "testkit.h"

#include "stages/balls.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Balls on the x axis: a big one at 0 (radius 10), one inside it, a copy of
 * the big one, one with no radius, and a small one sticking out of it at
 * x = 12. */
static const float BX[5] = {0.0f, 3.0f, 0.0f, 5.0f, 12.0f}, BR[5] = {10.0f, 4.0f, 10.0f, 0.0f, 3.0f};
static const float ZERO[5] = {0};

static void build(dp_ball_set *set)
{
	dp_balls in = {5, BX, ZERO, ZERO, BR};
	dp_error err = {0};
	if (dp_ball_set_build(set, &in, 0.0f, &err) != DP_OK)
		fail_msg("%s", err.message);
}

static uint32_t row_of(const dp_ball_set *set, int32_t k)
{
	assert_true(k >= 0 && (size_t)k < set->n);
	return set->row[k];
}

static void test_prune(void **state)
{
	(void)state;
	dp_ball_set set = {0};
	build(&set);
	/* the big ball (its lower row of the two copies) and the one sticking out */
	assert_int_equal(set.n, 2);
	int rows = 0;
	for (size_t k = 0; k < set.n; k++)
		rows |= 1 << set.row[k];
	assert_int_equal(rows, (1 << 0) | (1 << 4));
	dp_ball_set_free(&set);
	assert_int_equal(set.n, 0);
	/* the small ball sticks out by 5; a slack of 5 takes it in */
	dp_balls in = {5, BX, ZERO, ZERO, BR};
	dp_error err = {0};
	assert_int_equal(dp_ball_set_build(&set, &in, 4.9f, &err), DP_OK);
	assert_int_equal(set.n, 2);
	assert_int_equal(dp_ball_set_build(&set, &in, 5.0f, &err), DP_OK);
	assert_int_equal(set.n, 1);
	assert_int_equal(set.row[0], 0);
	dp_ball_set_free(&set);
}

static void test_deepest(void **state)
{
	(void)state;
	dp_ball_set set = {0};
	build(&set);
	float dist = -1.0f;
	/* at x = 2 facing -x: 8 deep in the big ball */
	int32_t k = dp_ball_set_deepest(&set, 2.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f, 1.0f, &dist);
	assert_int_equal(row_of(&set, k), 0);
	assert_true(fabsf(dist - 2.0f) < 1e-6f);
	/* facing +x, away from the big ball's centre, towards the small one's,
	 * which it is not inside */
	assert_int_equal(dp_ball_set_deepest(&set, 2.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f, &dist), -1);
	/* at x = 11.5 facing +x: inside the small ball only (2.5 deep) */
	k = dp_ball_set_deepest(&set, 11.5f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f, &dist);
	assert_int_equal(row_of(&set, k), 4);
	/* ... but not beyond a margin of 3 */
	assert_int_equal(dp_ball_set_deepest(&set, 11.5f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 3.0f, &dist), -1);
	/* at x = 9.5 facing -x: 0.5 deep in the big one, within the margin */
	assert_int_equal(dp_ball_set_deepest(&set, 9.5f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f, 1.0f, &dist), -1);
	/* outside every ball */
	assert_int_equal(dp_ball_set_deepest(&set, 0.0f, 30.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f, &dist), -1);
	dp_ball_set_free(&set);
}

/* No ball with a radius: an empty set that finds nothing. */
static void test_empty(void **state)
{
	(void)state;
	dp_balls in = {5, BX, ZERO, ZERO, ZERO};
	dp_ball_set set = {0};
	dp_error err = {0};
	assert_int_equal(dp_ball_set_build(&set, &in, 0.0f, &err), DP_OK);
	assert_int_equal(set.n, 0);
	float dist;
	assert_int_equal(dp_ball_set_deepest(&set, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, &dist), -1);
	dp_ball_set_free(&set);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_prune),
		cmocka_unit_test(test_deepest),
		cmocka_unit_test(test_empty),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
