/* The width bound of sinking (host/stages/width.h) on sample sets whose answer
 * is known: a plane and the rim of a one-sided scan are never bounded, a
 * strip and a pole are bounded at a few times their half-width, and a
 * one-sided scan of a ball is bounded only beyond its centre. Samples are
 * about r apart, like WLOP's output, in random order. */
#include "testkit.h"

#include "core/common.h"
#include "stages/width.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define FACTOR 2.0
/* positional jitter, in r */
#define JITTER 0.1

typedef struct samples {
	size_t n, cap;
	float *x, *y, *z;
} samples;

static void add(samples *s, dp_rng *rng, double x, double y, double z)
{
	if (s->n == s->cap) {
		s->cap = s->cap ? 2 * s->cap : 1024;
		s->x = realloc(s->x, s->cap * sizeof(float));
		s->y = realloc(s->y, s->cap * sizeof(float));
		s->z = realloc(s->z, s->cap * sizeof(float));
		assert_non_null(s->x);
		assert_non_null(s->y);
		assert_non_null(s->z);
	}
	s->x[s->n] = (float)(x + JITTER * dp_rng_normal(rng));
	s->y[s->n] = (float)(y + JITTER * dp_rng_normal(rng));
	s->z[s->n] = (float)(z + JITTER * dp_rng_normal(rng));
	s->n++;
}

/* Fisher-Yates: WLOP leaves its samples in random order (the bound's
 * choice of samples at wide scales does not depend on it). */
static void shuffle(samples *s, dp_rng *rng)
{
	for (size_t i = s->n; i > 1; i--) {
		size_t j = (size_t)(dp_rng_uniform(rng) * (double)i);
		if (j >= i)
			j = i - 1;
		float t;
		t = s->x[i - 1], s->x[i - 1] = s->x[j], s->x[j] = t;
		t = s->y[i - 1], s->y[i - 1] = s->y[j], s->y[j] = t;
		t = s->z[i - 1], s->z[i - 1] = s->z[j], s->z[j] = t;
	}
}

static float *bounds(const samples *s)
{
	float *b = malloc(s->n * sizeof *b);
	assert_non_null(b);
	dp_error err = {0};
	if (dp_width_bound(s->n, s->x, s->y, s->z, 1.0, FACTOR, b, &err) != DP_OK)
		fail_msg("%s", err.message);
	return b;
}

static void samples_free(samples *s)
{
	free(s->x);
	free(s->y);
	free(s->z);
}

/* A rectangle w x h of samples 1 apart in the plane z = 0. */
static void rectangle(samples *s, dp_rng *rng, int w, int h)
{
	for (int i = 0; i < w; i++)
		for (int j = 0; j < h; j++)
			add(s, rng, i, j, 0.0);
	shuffle(s, rng);
}

static void test_plane_unbounded(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 1);
	samples s = {0};
	rectangle(&s, &rng, 160, 160);
	float *b = bounds(&s);
	size_t finite = 0;
	for (size_t i = 0; i < s.n; i++)
		finite += isfinite(b[i]) != 0;
	printf("  plane of %zu samples, its rim included: %zu bounded\n", s.n, finite);
	assert_int_equal(finite, 0);
	free(b);
	samples_free(&s);
}

static void test_strip_bounded(void **state)
{
	(void)state;
	const int half = 3; /* half-width a, in r */
	dp_rng rng;
	dp_rng_seed(&rng, 2);
	samples s = {0};
	rectangle(&s, &rng, 200, 2 * half + 1);
	float *b = bounds(&s);
	float lo = INFINITY, hi = 0.0f;
	for (size_t i = 0; i < s.n; i++) {
		lo = fminf(lo, b[i]);
		hi = fmaxf(hi, b[i]);
	}
	printf("  strip of half-width %d r: bounds %.1f..%.1f r\n", half, lo, hi);
	/* Never inside the part, never far beyond it: a sample on the strip's
	 * edge spreads 2a/sqrt(3) across it, which the doubling scales bound at
	 * up to 4.6a, and sampling noise at the scales that read one sample in 4
	 * can push it one scale further. */
	assert_true(lo >= (float)half);
	assert_true(hi <= 6.0f * (float)half);
	free(b);
	samples_free(&s);
}

/* The side of a pole of radius a, rings 1 apart, about 2 pi a samples each. */
static void test_pole_bounded(void **state)
{
	(void)state;
	const double a = 2.5;
	dp_rng rng;
	dp_rng_seed(&rng, 3);
	samples s = {0};
	int around = (int)ceil(2.0 * M_PI * a);
	for (int k = 0; k < 200; k++)
		for (int j = 0; j < around; j++) {
			double t = 2.0 * M_PI * (j + 0.5 * (k % 2)) / around;
			add(&s, &rng, a * cos(t), a * sin(t), k);
		}
	shuffle(&s, &rng);
	float *b = bounds(&s);
	float hi = 0.0f;
	for (size_t i = 0; i < s.n; i++)
		hi = fmaxf(hi, b[i]);
	printf("  pole of radius %.1f r: bounds at most %.1f r\n", a, hi);
	assert_true(hi <= 4.0f * (float)a);
	free(b);
	samples_free(&s);
}

/* A hemisphere of radius R (a one-view scan of a ball): sinking must be free
 * to reach the centre, R deep, from everywhere, the rim included. */
static void test_hemisphere_beyond_centre(void **state)
{
	(void)state;
	/* 2R just above the 16 r scale: the widest ball short of holding the
	 * whole half, the closest the bound comes to R */
	const double R = 8.2;
	dp_rng rng;
	dp_rng_seed(&rng, 4);
	samples s = {0};
	/* a Fibonacci lattice of the sphere with about one sample per r², upper half */
	size_t total = (size_t)(4.0 * M_PI * R * R);
	for (size_t i = 0; i < total; i++) {
		double z = 1.0 - (2.0 * (double)i + 1.0) / (double)total;
		if (z < 0.0)
			break;
		double rho = sqrt(1.0 - z * z), t = M_PI * (3.0 - sqrt(5.0)) * (double)i;
		add(&s, &rng, R * rho * cos(t), R * rho * sin(t), R * z);
	}
	shuffle(&s, &rng);
	float *b = bounds(&s);
	float lo = INFINITY;
	for (size_t i = 0; i < s.n; i++)
		lo = fminf(lo, b[i]);
	printf("  hemisphere of radius %.1f r, %zu samples: smallest bound %.1f r\n", R, s.n, lo);
	assert_true(lo > (float)R);
	free(b);
	samples_free(&s);
}

/* An outlier far from a plane: no ball around it holds a part, so only the
 * widest bounds it; a straggler just beyond the plane's edge, whose small
 * balls are sparse, is left to sink with its neighbours. */
static void test_outlier_bounded(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	samples s = {0};
	rectangle(&s, &rng, 60, 60);
	add(&s, &rng, 30.0, 30.0, 200.0);
	add(&s, &rng, 62.5, 30.0, 0.0);
	float *b = bounds(&s);
	size_t plane = 0;
	for (size_t i = 0; i + 2 < s.n; i++)
		plane += isfinite(b[i]) != 0;
	printf("  outlier bounded at %.1f r, straggler at %.1f r, %zu plane samples bounded\n", b[s.n - 2], b[s.n - 1],
	       plane);
	assert_true(b[s.n - 2] == (float)(0.5 * DP_WIDTH_MIN_SCALE_R * (1 << (DP_WIDTH_SCALES - 1))));
	assert_false(isfinite(b[s.n - 1]));
	assert_int_equal(plane, 0);
	free(b);
	samples_free(&s);
}

/* Read lazily, a scale is measured only once a point is half that scale
 * deep, and the bound found is the one every scale read at once gives. */
static void test_lazy_same(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 6);
	samples s = {0};
	rectangle(&s, &rng, 200, 7);
	float *all = bounds(&s);
	dp_width w;
	dp_error err = {0};
	assert_int_equal(dp_width_init(&w, s.n, s.x, s.y, s.z, 1.0, FACTOR, &err), DP_OK);
	for (size_t i = 0; i < s.n; i++) {
		assert_false(dp_width_too_deep(&w, i, 1.0f));
		assert_int_equal(w.level[i], 0);
		/* beyond the widest scale's bound, 32 r, nothing changes */
		float depth = 0.0f;
		while (depth <= 40.0f && !dp_width_too_deep(&w, i, depth))
			depth += 0.5f;
		if (isfinite(all[i]))
			assert_true(depth >= all[i] && depth < all[i] + 0.5f);
		else
			assert_true(depth > 40.0f);
		assert_true(w.bound[i] == all[i]);
	}
	dp_width_free(&w);
	free(all);
	samples_free(&s);
}

static void test_empty(void **state)
{
	(void)state;
	dp_error err = {0};
	assert_int_equal(dp_width_bound(0, NULL, NULL, NULL, 1.0, FACTOR, NULL, &err), DP_OK);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plane_unbounded),
		cmocka_unit_test(test_strip_bounded),
		cmocka_unit_test(test_pole_bounded),
		cmocka_unit_test(test_hemisphere_beyond_centre),
		cmocka_unit_test(test_outlier_bounded),
		cmocka_unit_test(test_lazy_same),
		cmocka_unit_test(test_empty),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
