/* The kd-tree's ball test and nearest-in-a-ball search (host/knn/kdtree.h)
 * equal a brute-force scan of the same float predicate: random balls around
 * random, clustered and coordinate-tied point sets, radii at exact point
 * distances (the strict comparison's edge), tiny trees, and queries that are
 * NaN or have r2 <= 0. */
#include "testkit.h"

#include "core/common.h"
#include "knn/kdtree.h"

#include <math.h>
#include <stdlib.h>

#define NPOINTS 3000
#define NQUERIES 4000

static int by_float(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/* The nearest `cap` within r2: as many as a brute-force scan finds (at most
 * cap), each a real point at its true squared distance, no point twice, and
 * the same distances as the brute force's nearest (ties may swap points). */
static void check_nearest(const dp_kdtree *t, size_t n, const float *x, const float *y, const float *z, float qx,
			  float qy, float qz, float r2, size_t cap, float *all, uint32_t *idx, float *d2,
			  unsigned char *seen)
{
	size_t m = 0;
	for (size_t k = 0; k < n; k++) {
		float dx = x[k] - qx, dy = y[k] - qy, dz = z[k] - qz, e = dx * dx + dy * dy + dz * dz;
		if (e < r2)
			all[m++] = e;
	}
	qsort(all, m, sizeof *all, by_float);
	size_t got = dp_kdtree_nearest_within(t, qx, qy, qz, r2, cap, idx, d2);
	size_t want = m < cap ? m : cap;
	if (got != want)
		fail_msg("n %zu cap %zu r2 %g: %zu found, brute force %zu", n, cap, (double)r2, got, want);
	for (size_t j = 0; j < got; j++) {
		assert_true(idx[j] < n);
		assert_false(seen[idx[j]]);
		seen[idx[j]] = 1;
		float dx = x[idx[j]] - qx, dy = y[idx[j]] - qy, dz = z[idx[j]] - qz;
		assert_true(d2[j] == dx * dx + dy * dy + dz * dz);
	}
	for (size_t j = 0; j < got; j++)
		seen[idx[j]] = 0;
	qsort(d2, got, sizeof *d2, by_float);
	for (size_t j = 0; j < got; j++)
		assert_true(d2[j] == all[j]);
}

static int brute(size_t n, const float *x, const float *y, const float *z, float qx, float qy, float qz, float r2)
{
	for (size_t k = 0; k < n; k++) {
		float dx = x[k] - qx, dy = y[k] - qy, dz = z[k] - qz;
		if (dx * dx + dy * dy + dz * dz < r2)
			return 1;
	}
	return 0;
}

/* Points of one of three kinds: uniform in a box, on a sphere shell (a
 * surface, as the sinking stage gives it) or on a coarse lattice, where many
 * share a coordinate with a split point. */
static void fill(dp_rng *rng, int kind, size_t n, float *x, float *y, float *z)
{
	for (size_t k = 0; k < n; k++) {
		float v[3];
		for (int a = 0; a < 3; a++)
			v[a] = (float)(dp_rng_uniform(rng) * 2.0 - 1.0);
		if (kind == 1) {
			float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
			for (int a = 0; a < 3; a++)
				v[a] = len > 0.0f ? v[a] / len : 1.0f;
		} else if (kind == 2) {
			for (int a = 0; a < 3; a++)
				v[a] = roundf(v[a] * 4.0f) / 4.0f;
		}
		x[k] = v[0];
		y[k] = v[1];
		z[k] = v[2];
	}
}

static void compare(dp_rng *rng, size_t n, const float *x, const float *y, const float *z, size_t *hits)
{
	dp_kdtree t;
	dp_error err = {0};
	assert_int_equal(dp_kdtree_build(&t, n, x, y, z, &err), DP_OK);
	float *all = malloc(NPOINTS * sizeof *all), *d2 = malloc(NPOINTS * sizeof *d2);
	uint32_t *idx = malloc(NPOINTS * sizeof *idx);
	unsigned char *seen = calloc(NPOINTS, 1);
	assert_true(all && d2 && idx && seen);
	for (int q = 0; q < NQUERIES; q++) {
		float qx = (float)(dp_rng_uniform(rng) * 2.4 - 1.2), qy = (float)(dp_rng_uniform(rng) * 2.4 - 1.2),
		      qz = (float)(dp_rng_uniform(rng) * 2.4 - 1.2);
		float r = (float)(dp_rng_uniform(rng) * 0.3);
		float r2 = r * r;
		if (n > 0 && q % 4 == 0) {
			/* exactly some point's distance: that point does not count */
			size_t k = (size_t)(dp_rng_uniform(rng) * (double)n) % n;
			float dx = x[k] - qx, dy = y[k] - qy, dz = z[k] - qz;
			r2 = dx * dx + dy * dy + dz * dz;
		}
		const size_t caps[] = {1, 5, 40, NPOINTS};
		check_nearest(&t, n, x, y, z, qx, qy, qz, r2, caps[q % 4], all, idx, d2, seen);
		int want = brute(n, x, y, z, qx, qy, qz, r2);
		int got = dp_kdtree_any_within(&t, qx, qy, qz, r2);
		if (got != want)
			fail_msg("n %zu query (%g, %g, %g) r2 %g: tree says %d, brute force %d", n, (double)qx,
				 (double)qy, (double)qz, (double)r2, got, want);
		*hits += (size_t)want;
	}
	assert_false(dp_kdtree_any_within(&t, NAN, 0.0f, 0.0f, 1.0f));
	assert_false(dp_kdtree_any_within(&t, 0.0f, 0.0f, 0.0f, 0.0f));
	assert_int_equal(dp_kdtree_nearest_within(&t, NAN, 0.0f, 0.0f, 1.0f, 10, idx, d2), 0);
	assert_int_equal(dp_kdtree_nearest_within(&t, 0.0f, 0.0f, 0.0f, 0.0f, 10, idx, d2), 0);
	free(all);
	free(d2);
	free(idx);
	free(seen);
	dp_kdtree_free(&t);
}

static void test_equals_brute_force(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	float *x = malloc(NPOINTS * sizeof *x), *y = malloc(NPOINTS * sizeof *y), *z = malloc(NPOINTS * sizeof *z);
	assert_true(x && y && z);
	const size_t sizes[] = {0, 1, 7, 8, 9, 17, 100, NPOINTS};
	for (int kind = 0; kind < 3; kind++)
		for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
			size_t hits = 0;
			fill(&rng, kind, sizes[s], x, y, z);
			compare(&rng, sizes[s], x, y, z, &hits);
			/* both answers occur, or the comparison says little */
			if (sizes[s] >= 100)
				assert_true(hits > NQUERIES / 20 && hits < NQUERIES - NQUERIES / 20);
		}
	free(x);
	free(y);
	free(z);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_equals_brute_force),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
