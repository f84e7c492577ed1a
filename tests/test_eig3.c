/* dp_eig3_sym: A v = w v, orthonormal vectors, ascending values. */
#include "testkit.h"

#include "core/eig3.h"

#include <math.h>

static void check(const double s[6])
{
	double w[3], v[3][3];
	dp_eig3_sym(s, w, v);
	double a[3][3] = {{s[0], s[1], s[2]}, {s[1], s[3], s[4]}, {s[2], s[4], s[5]}};
	double scale = fabs(w[0]) + fabs(w[2]) + 1e-30;
	assert_true(w[0] <= w[1] && w[1] <= w[2]);
	for (int m = 0; m < 3; m++) {
		for (int r = 0; r < 3; r++) {
			double av = a[r][0] * v[m][0] + a[r][1] * v[m][1] + a[r][2] * v[m][2];
			assert_true(fabs(av - w[m] * v[m][r]) < 1e-10 * scale);
		}
		for (int q = 0; q < 3; q++) {
			double d = v[m][0] * v[q][0] + v[m][1] * v[q][1] + v[m][2] * v[q][2];
			assert_true(fabs(d - (m == q ? 1.0 : 0.0)) < 1e-10);
		}
	}
}

static void test_random_symmetric(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	for (int t = 0; t < 1000; t++) {
		double s[6];
		for (int k = 0; k < 6; k++)
			s[k] = dp_rng_normal(&rng);
		check(s);
	}
}

static void test_degenerate(void **state)
{
	(void)state;
	const double zero[6] = {0}, iso[6] = {2, 0, 0, 2, 0, 2}, plane[6] = {1, 0, 0, 1, 0, 0},
		     line[6] = {1, 1, 1, 1, 1, 1};
	check(zero);
	check(iso);
	check(plane);
	check(line);
	double w[3], v[3][3];
	dp_eig3_sym(plane, w, v);
	assert_true(fabs(fabs(v[0][2]) - 1.0) < 1e-12); /* normal of the xy plane is z */
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_random_symmetric),
		cmocka_unit_test(test_degenerate),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
