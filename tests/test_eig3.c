/* dp_eig3_sym: A v = w v, orthonormal vectors, ascending values.
 * dp_eig3_smallest: the same values to 1e-7 of the matrix's size (the
 * closed form's accuracy where two meet) and, wherever the smallest is 1e-3
 * apart from the middle one, the same vector up to sign; A v0 = w[0] v0
 * always. */
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

/* Against dp_eig3_sym; `gap_min` is the relative gap w[1] - w[0] from which
 * v0 must be Jacobi's v[0] up to sign. */
static int fast_answers; /* how many checks the closed form answered */

static void check_smallest(const double s[6], double gap_min)
{
	double w[3], v[3][3], ws[3], v0[3];
	dp_eig3_sym(s, w, v);
	int fast = dp_eig3_smallest(s, ws, v0);
	fast_answers += fast;
	/* well apart (twice the cut, in the matrix's size |q| + p), the closed
	 * form must answer: a fallback everywhere would pass every other check */
	double q = (w[0] + w[1] + w[2]) / 3.0;
	double p = sqrt(((w[0] - q) * (w[0] - q) + (w[1] - q) * (w[1] - q) + (w[2] - q) * (w[2] - q)) / 6.0);
	if (w[1] - w[0] > 2e-3 * (fabs(q) + p) && !fast)
		fail_msg("gap %g of size %g: Jacobi answered", w[1] - w[0], fabs(q) + p);
	double a[3][3] = {{s[0], s[1], s[2]}, {s[1], s[3], s[4]}, {s[2], s[4], s[5]}};
	double scale = fabs(w[0]) + fabs(w[2]) + 1e-30;
	for (int m = 0; m < 3; m++)
		if (!(fabs(ws[m] - w[m]) < 1e-7 * scale))
			fail_msg("eigenvalue %d: %.17g, Jacobi %.17g", m, ws[m], w[m]);
	assert_true(fabs(v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2] - 1.0) < 1e-12);
	for (int r = 0; r < 3; r++) {
		double av = a[r][0] * v0[0] + a[r][1] * v0[1] + a[r][2] * v0[2];
		if (!(fabs(av - ws[0] * v0[r]) < 1e-8 * scale))
			fail_msg("row %d: |A v0 - w0 v0| = %g of %g", r, fabs(av - ws[0] * v0[r]), scale);
	}
	if (w[1] - w[0] > gap_min * scale) {
		double d = fabs(v0[0] * v[0][0] + v0[1] * v[0][1] + v0[2] * v[0][2]);
		if (!(d > 1.0 - 1e-9))
			fail_msg("v0 at |cos| %.17g from Jacobi's", d);
	}
}

/* Covariances of neighbourhoods as the surface stage sees them: a patch of
 * spread 1 with a normal spread `thin`, tilted at random, plus the
 * degenerate shapes. */
static void test_smallest(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 9);
	const double thin[] = {1.0, 0.3, 1e-2, 1e-4, 1e-8};
	for (int t = 0; t < 2000; t++) {
		double s[6];
		if (t % 2 == 0) {
			for (int k = 0; k < 6; k++)
				s[k] = dp_rng_normal(&rng);
		} else {
			/* R diag(1, u, thin) R^T with a random orthonormal R */
			double e[3] = {thin[t / 2 % 5], dp_rng_uniform(&rng) + 0.05, 1.0};
			double x[3], y[3], z[3];
			for (int k = 0; k < 3; k++)
				x[k] = dp_rng_normal(&rng), y[k] = dp_rng_normal(&rng);
			double lx = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
			for (int k = 0; k < 3; k++)
				x[k] /= lx;
			double dy = y[0] * x[0] + y[1] * x[1] + y[2] * x[2];
			for (int k = 0; k < 3; k++)
				y[k] -= dy * x[k];
			double ly = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
			for (int k = 0; k < 3; k++)
				y[k] /= ly;
			z[0] = x[1] * y[2] - x[2] * y[1], z[1] = x[2] * y[0] - x[0] * y[2], z[2] = x[0] * y[1] - x[1] * y[0];
			const double *axis[3] = {x, y, z};
			int idx[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
			for (int k = 0; k < 6; k++) {
				s[k] = 0.0;
				for (int m = 0; m < 3; m++)
					s[k] += e[m] * axis[m][idx[k][0]] * axis[m][idx[k][1]];
			}
		}
		check_smallest(s, 1e-3);
	}
	const double zero[6] = {0}, iso[6] = {2, 0, 0, 2, 0, 2}, plane[6] = {1, 0, 0, 1, 0, 0},
		     line[6] = {1, 1, 1, 1, 1, 1}, shifted[6] = {1e6 + 1, 0, 0, 1e6 + 2, 0, 1e6};
	check_smallest(zero, 1e-3);
	check_smallest(iso, 1e-3);
	check_smallest(plane, 1e-3);
	check_smallest(line, 1e-3);
	check_smallest(shifted, 1e-3);
	double w[3], v0[3];
	assert_int_equal(dp_eig3_smallest(plane, w, v0), 1);
	assert_true(fabs(fabs(v0[2]) - 1.0) < 1e-12);
	assert_int_equal(dp_eig3_smallest(iso, w, v0), 0);
	assert_int_equal(dp_eig3_smallest(zero, w, v0), 0);
	/* scale: the rows are normalised, so huge and tiny matrices work too */
	const double huge[6] = {3e150, 1e150, 0, 2e150, 0, 1e149}, tiny[6] = {3e-150, 1e-150, 0, 2e-150, 0, 1e-151};
	assert_int_equal(dp_eig3_smallest(huge, w, v0), 1);
	assert_true(fabs(v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2] - 1.0) < 1e-12);
	check_smallest(huge, 1e-3);
	check_smallest(tiny, 1e-3);
	assert_true(fast_answers > 1000);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_random_symmetric),
		cmocka_unit_test(test_degenerate),
		cmocka_unit_test(test_smallest),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
