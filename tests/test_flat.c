/* The flat-face depth of sinking (host/stages/flat.h) on inner points whose
 * answer is known: a flat face takes the median depth of the evidence at its
 * rim, a curved one does not pass it on beyond the angle, and only points
 * that stopped without evidence (slow-down, the width bound) ever move, never
 * deeper; a rounded crease's samples stop on the face's medial plane. */
#include "testkit.h"

#include "stages/flat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* n samples with normals and inner points at `depth` below them. */
typedef struct pts {
	size_t n;
	float *p[3], *nrm[3], *q[3];
	unsigned char *why;
} pts;

static void pts_alloc(pts *s, size_t n)
{
	s->n = n;
	for (int c = 0; c < 3; c++) {
		s->p[c] = calloc(n, sizeof(float));
		s->nrm[c] = calloc(n, sizeof(float));
		s->q[c] = calloc(n, sizeof(float));
		assert_true(s->p[c] && s->nrm[c] && s->q[c]);
	}
	s->why = calloc(n, 1);
	assert_non_null(s->why);
}

static void pts_free(pts *s)
{
	for (int c = 0; c < 3; c++) {
		free(s->p[c]);
		free(s->nrm[c]);
		free(s->q[c]);
	}
	free(s->why);
}

static void set(pts *s, size_t i, const double p[3], const double n[3], double depth, dp_settle why)
{
	for (int c = 0; c < 3; c++) {
		s->p[c][i] = (float)p[c];
		s->nrm[c][i] = (float)n[c];
		s->q[c][i] = (float)(p[c] - depth * n[c]);
	}
	s->why[i] = (unsigned char)why;
}

static double depth(const pts *s, size_t i)
{
	double d = 0.0;
	for (int c = 0; c < 3; c++)
		d += ((double)s->p[c][i] - s->q[c][i]) * ((double)s->p[c][i] - s->q[c][i]);
	return sqrt(d);
}

static size_t run(pts *s, double angle)
{
	size_t capped = 0;
	dp_error err = {0};
	const float *p[3] = {s->p[0], s->p[1], s->p[2]}, *n[3] = {s->nrm[0], s->nrm[1], s->nrm[2]};
	if (dp_flat_cap(2, s->n, p, n, s->q, s->why, 1.0, angle, &capped, &err) != DP_OK)
		fail_msg("%s", err.message);
	return capped;
}

/* Which ring of a side x side face (0: the outermost) sample (i, j) is in. */
static int ring_of(int i, int j, int side)
{
	int ring = i < j ? i : j;
	ring = ring < side - 1 - i ? ring : side - 1 - i;
	return ring < side - 1 - j ? ring : side - 1 - j;
}

/* A 41 x 41 face at spacing 1 facing up. Its outer three rings settled on
 * evidence at depths 1, 2 and 3 (outermost 1), as a rim's points meet the
 * side faces' fronts, except for one point at 0.1; the rest stopped by
 * slow-down at 8, one by the width bound at 9 (an upper bound, not a depth:
 * it is capped like them) and one by the width bound at 0.5, above the
 * face's depth (it stays). */
static void test_plate(void **state)
{
	(void)state;
	pts s;
	int side = 41;
	pts_alloc(&s, (size_t)side * side);
	double up[3] = {0, 0, 1};
	size_t width_point = 0, shallow = 0, width_shallow = 0;
	for (int i = 0; i < side; i++)
		for (int j = 0; j < side; j++) {
			size_t k = (size_t)i * side + (size_t)j;
			int ring = ring_of(i, j, side);
			double p[3] = {i, j, 0};
			if (ring < 3)
				set(&s, k, p, up, ring + 1.0, DP_SETTLE_FRONT);
			else
				set(&s, k, p, up, 8.0, DP_SETTLE_SLOW);
			if (i == 20 && j == 21) {
				set(&s, k, p, up, 9.0, DP_SETTLE_WIDTH);
				width_point = k;
			}
			if (i == 0 && j == 20) {
				set(&s, k, p, up, 0.1, DP_SETTLE_MEDIAL);
				shallow = k;
			}
			if (i == 10 && j == 30) {
				set(&s, k, p, up, 0.5, DP_SETTLE_WIDTH);
				width_shallow = k;
			}
		}
	size_t capped = run(&s, 10.0), slow = 0;
	for (size_t k = 0; k < s.n; k++) {
		if (k == width_shallow || s.why[k] == DP_SETTLE_FRONT || s.why[k] == DP_SETTLE_MEDIAL)
			continue;
		slow++;
		assert_int_equal(s.why[k], DP_SETTLE_FLAT);
		/* the median of 1, 2, 3 over the rim, not the one shallow point */
		assert_true(depth(&s, k) >= 1.0 && depth(&s, k) <= 3.0);
		/* moved towards its sample, along its line */
		assert_true(fabsf(s.q[0][k] - s.p[0][k]) < 1e-5f && fabsf(s.q[1][k] - s.p[1][k]) < 1e-5f);
	}
	printf("  plate: %zu of %zu slow and width-bound points capped, middle at %.2f, width-bound one at %.2f\n",
	       capped, slow, depth(&s, 20 * 41 + 20), depth(&s, width_point));
	assert_int_equal(capped, slow);
	assert_int_equal(s.why[width_point], DP_SETTLE_FLAT);
	/* a cap never deepens: a width-bound point above its face's depth stays */
	assert_int_equal(s.why[width_shallow], DP_SETTLE_WIDTH);
	assert_true(fabs(depth(&s, width_shallow) - 0.5) < 1e-5);
	assert_true(fabs(depth(&s, shallow) - 0.1) < 1e-5);
	pts_free(&s);
}

/* The plate of test_plate with side samples at spacing 1 half a step outside
 * its rim, normals out, in `rows` rows going down (dir -1: an edge band) or
 * up (+1: a wall rising from the face's edge), settled on evidence. The
 * rim's evidence says 3, 3.5 and 4 (deeper than a thin plate's half), its
 * normals turned `tilt` degrees about the x axis (a crease's PCA normals).
 * Returns the middle's depth. */
static double plate_with_side(int rows, double dir, double tilt)
{
	int side = 41;
	size_t face = (size_t)side * side, n = face + 4 * (size_t)side * (size_t)rows;
	pts s;
	pts_alloc(&s, n);
	double up[3] = {0, 0, 1}, turned[3] = {0, sin(tilt * M_PI / 180.0), cos(tilt * M_PI / 180.0)};
	for (int i = 0; i < side; i++)
		for (int j = 0; j < side; j++) {
			size_t k = (size_t)i * side + (size_t)j;
			int ring = ring_of(i, j, side);
			double p[3] = {i, j, 0};
			set(&s, k, p, ring < 3 ? turned : up, ring < 3 ? 3.0 + 0.5 * ring : 8.0,
			    ring < 3 ? DP_SETTLE_FRONT : DP_SETTLE_SLOW);
		}
	size_t k = face;
	for (int e = 0; e < side; e++)
		for (int h = 1; h <= rows; h++) {
			double z = dir * (h - 0.5);
			double ps[4][3] = {{-0.5, e, z}, {side - 0.5, e, z}, {e, -0.5, z}, {e, side - 0.5, z}};
			double ns[4][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}};
			for (int f = 0; f < 4; f++)
				set(&s, k++, ps[f], ns[f], 1.0, DP_SETTLE_FRONT);
		}
	run(&s, 10.0);
	double middle = depth(&s, 20 * 41 + 20);
	for (size_t m = 0; m < face; m++)
		if (s.why[m] == DP_SETTLE_FLAT)
			assert_true(fabs(depth(&s, m) - middle) < 1e-5); /* one depth for the whole face */
	printf("  plate with %d rows of side samples %s: middle at %.2f\n", rows, dir < 0 ? "below" : "above",
	       middle);
	pts_free(&s);
	return middle;
}

static double plate_with_band(int rows)
{
	return plate_with_side(rows, -1.0, 0.0);
}

static void test_plate_band(void **state)
{
	(void)state;
	/* the band's lowest samples lie 2.5 below the face, and a band is read
	 * one spacing taller than that (flat.h): half of 3.5 */
	assert_true(fabs(plate_with_band(3) - 1.75) < 1e-4);
	/* a side as tall as the search ball shows is no plate's edge: the
	 * median of the rim's evidence, 3.5 */
	assert_true(fabs(plate_with_band(12) - 3.5) < 1e-4);
	/* a wall rising from the face (a chair's back from its seat) is no edge */
	assert_true(fabs(plate_with_side(3, 1.0, 0.0) - 3.5) < 1e-4);
	/* evidence whose normals are turned round the crease can neither read
	 * the band nor pass its depth to the face; the face's own samples read
	 * the band (without them the middle stayed 8 deep) */
	assert_true(fabs(plate_with_side(3, -1.0, 30.0) - 1.75) < 1e-4);
}

/* A sphere of radius 20 at spacing about 1, normals out, every point slowed
 * at depth 20 but one at the north pole settled at depth 2. Only points
 * whose normal is within the angle of the pole's take its depth. */
static void test_curved(void **state)
{
	(void)state;
	pts s;
	double radius = 20.0, angle = 10.0;
	size_t n = (size_t)(4.0 * M_PI * radius * radius);
	pts_alloc(&s, n);
	double golden = M_PI * (3.0 - sqrt(5.0));
	for (size_t i = 0; i < n; i++) {
		double z = 1.0 - 2.0 * ((double)i + 0.5) / (double)n, rho = sqrt(1.0 - z * z), a = golden * (double)i;
		double nrm[3] = {rho * cos(a), rho * sin(a), z}, p[3] = {radius * nrm[0], radius * nrm[1], radius * nrm[2]};
		set(&s, i, p, nrm, i == 0 ? 2.0 : radius, i == 0 ? DP_SETTLE_FRONT : DP_SETTLE_SLOW);
	}
	size_t capped = run(&s, angle);
	double cos_angle = cos(angle * M_PI / 180.0);
	for (size_t i = 1; i < n; i++) {
		double c = (double)s.nrm[0][i] * s.nrm[0][0] + (double)s.nrm[1][i] * s.nrm[1][0] +
			   (double)s.nrm[2][i] * s.nrm[2][0];
		if (c < cos_angle - 1e-6)
			assert_true(fabs(depth(&s, i) - radius) < 1e-4);
		if (s.why[i] == DP_SETTLE_FLAT)
			assert_true(c >= cos_angle - 1e-6 && fabs(depth(&s, i) - 2.0) < 1e-4);
	}
	printf("  sphere of %zu points: %zu capped within %g degrees of the pole\n", n, capped, angle);
	assert_true(capped > 0 && capped < 60);
	pts_free(&s);
}

/* Five samples 2 apart on a bend: A (depth 3, normal tilted 12 degrees)
 * and B (depth 2, 0 degrees) on evidence, and between them j (6 degrees),
 * x (3) and, off j, i (14 degrees, within the angle of A's normal, not of
 * B's). B's depth reaches j through x, A's directly. The smaller travels
 * first: j and x take 2, and i, which B's depth may not reach, keeps its own
 * 8, in either order of the samples (a pass in index order gave i A's 3 when
 * it came after j and nothing when it came before). */
static void test_order_bend(void **state)
{
	(void)state;
	static const char *names[2] = {"jxiAB", "ixjAB"};
	for (int o = 0; o < 2; o++) {
		pts s;
		pts_alloc(&s, 5);
		for (int k = 0; k < 5; k++) {
			char c = names[o][k];
			double x = c == 'A' ? -2 : c == 'x' ? 2 : c == 'B' ? 4 : 0, y = c == 'i' ? 2 : 0;
			double tilt = (c == 'A' ? 12 : c == 'j' ? 6 : c == 'x' ? 3 : c == 'B' ? 0 : 14) * M_PI / 180.0;
			double p[3] = {x, y, 0.0}, nrm[3] = {sin(tilt), 0.0, cos(tilt)};
			double d = c == 'A' ? 3.0 : c == 'B' ? 2.0 : 8.0;
			set(&s, (size_t)k, p, nrm, d, c == 'A' || c == 'B' ? DP_SETTLE_FRONT : DP_SETTLE_SLOW);
		}
		assert_int_equal(run(&s, 10.0), 2);
		for (int k = 0; k < 5; k++) {
			char c = names[o][k];
			double want = c == 'A' ? 3.0 : c == 'i' ? 8.0 : 2.0;
			assert_true(fabs(depth(&s, (size_t)k) - want) < 1e-5);
		}
		pts_free(&s);
	}
}

/* Nothing to do: too few points, no evidence, or evidence only. */
static void test_nothing(void **state)
{
	(void)state;
	pts s;
	pts_alloc(&s, 1);
	double p[3] = {0, 0, 0}, n[3] = {0, 0, 1};
	set(&s, 0, p, n, 5.0, DP_SETTLE_SLOW);
	assert_int_equal(run(&s, 10.0), 0);
	assert_int_equal(s.why[0], DP_SETTLE_SLOW);
	pts_free(&s);
	for (int evidence = 0; evidence < 2; evidence++) {
		pts_alloc(&s, 100);
		for (size_t i = 0; i < 100; i++) {
			double q[3] = {(double)(i % 10), (double)(i / 10), 0.0};
			set(&s, i, q, n, 1.0 + (double)(i % 3), evidence ? DP_SETTLE_MEDIAL : DP_SETTLE_SLOW);
		}
		assert_int_equal(run(&s, 10.0), 0);
		for (size_t i = 0; i < 100; i++)
			assert_true(fabs(depth(&s, i) - (1.0 + (double)(i % 3))) < 1e-6);
		pts_free(&s);
	}
}

/* A 31 x 31 face at spacing 1 facing up, on evidence at depth 2 but for its
 * next-to-last row, at 6 (the median, not the mean or the deepest, of the
 * crossings counts), and with the last two rows' samples from x = 20 on
 * stopped by slow-down 8 deep, which the face's depth caps to 2 first (faces
 * settled on their face count). Beyond its y = 30 edge the rounded crease to
 * a wall: a row at y = 31 whose normals are turned 30 degrees towards -y,
 * stopped by slow-down 8 deep (one by the width bound, one at 1.5, one
 * smoothed 10 degrees off its normal's line, one smoothed to 65 degrees from
 * the vertical, too oblique to the face's plane to read a crossing), and
 * another at y = 32 turned 70 degrees. The 30-degree row meets the face's medial plane z = -2 at
 * depth 2 / cos 30 (not at its neighbours' depth 2); the smoothed one meets
 * it along its own line; the 70-degree row has no face within 60 degrees and
 * stays; the shallow one stays. Apart, a 30-degree sample beside only two
 * face samples stays. */
static void test_crease(void **state)
{
	(void)state;
	pts s;
	int side = 31, slow_from = 20;
	pts_alloc(&s, (size_t)side * (side + 2) + 3);
	double up[3] = {0, 0, 1};
	double a30 = 30.0 * M_PI / 180.0, a40 = 40.0 * M_PI / 180.0, a65 = 65.0 * M_PI / 180.0;
	double a70 = 70.0 * M_PI / 180.0;
	double n30[3] = {0, -sin(a30), cos(a30)}, n70[3] = {0, -sin(a70), cos(a70)};
	size_t k = 0, shallow = 0, smoothed = 0, grazing = 0;
	for (int i = 0; i < side; i++)
		for (int j = 0; j < side; j++) {
			double p[3] = {i, j, 0};
			if (j >= side - 2 && i >= slow_from)
				set(&s, k++, p, up, 8.0, DP_SETTLE_SLOW);
			else
				set(&s, k++, p, up, j == side - 2 ? 6.0 : 2.0, DP_SETTLE_FRONT);
		}
	size_t row30 = k;
	for (int i = 0; i < side; i++) {
		double p[3] = {i, side, 0};
		if (i == side / 2)
			shallow = k;
		if (i == 7)
			smoothed = k;
		if (i == 11)
			grazing = k;
		set(&s, k, p, n30, i == side / 2 ? 1.5 : 8.0, i == 3 ? DP_SETTLE_WIDTH : DP_SETTLE_SLOW);
		if (i == 7 || i == 11) {
			double tilt = i == 7 ? a40 : a65;
			s.q[1][k] = (float)(p[1] + 8.0 * sin(tilt));
			s.q[2][k] = (float)(p[2] - 8.0 * cos(tilt));
		}
		k++;
	}
	size_t row70 = k;
	for (int i = 0; i < side; i++) {
		double p[3] = {i, side + 1, 0};
		set(&s, k++, p, n70, 8.0, DP_SETTLE_SLOW);
	}
	size_t apart = k;
	double f0[3] = {100, 0, 0}, f1[3] = {101, 0, 0}, c[3] = {100.5, 1, 0};
	set(&s, k++, f0, up, 2.0, DP_SETTLE_FRONT);
	set(&s, k++, f1, up, 2.0, DP_SETTLE_FRONT);
	set(&s, k++, c, n30, 8.0, DP_SETTLE_SLOW);
	size_t capped = run(&s, 10.0);
	double want = 2.0 / cos(a30);
	printf("  crease: %zu capped, the 30-degree row at %.3f (the face's plane: %.3f)\n", capped,
	       depth(&s, row30 + 3), want);
	assert_int_equal(capped, (size_t)(side - 2 + 2 * (side - slow_from)));
	for (int i = slow_from; i < side; i++)
		for (int j = side - 2; j < side; j++) {
			size_t f = (size_t)i * (size_t)side + (size_t)j;
			assert_int_equal(s.why[f], DP_SETTLE_FLAT);
			assert_true(fabs(depth(&s, f) - 2.0) < 1e-3);
		}
	for (int i = 0; i < side; i++) {
		size_t a = row30 + (size_t)i, b = row70 + (size_t)i;
		if (a == shallow || a == grazing) {
			assert_int_equal(s.why[a], DP_SETTLE_SLOW);
			assert_true(fabs(depth(&s, a) - (a == shallow ? 1.5 : 8.0)) < 1e-5);
		} else if (a == smoothed) {
			assert_int_equal(s.why[a], DP_SETTLE_FLAT);
			assert_true(fabs(s.q[2][a] + 2.0f) < 1e-3f);
			assert_true(fabs(depth(&s, a) - 2.0 / cos(a40)) < 1e-3);
		} else {
			assert_int_equal(s.why[a], DP_SETTLE_FLAT);
			assert_true(fabs(depth(&s, a) - want) < 1e-3);
			/* along its own line */
			assert_true(fabsf(s.q[0][a] - s.p[0][a]) < 1e-5f);
		}
		assert_int_equal(s.why[b], DP_SETTLE_SLOW);
		assert_true(fabs(depth(&s, b) - 8.0) < 1e-5);
	}
	assert_int_equal(s.why[apart + 2], DP_SETTLE_SLOW);
	assert_true(fabs(depth(&s, apart + 2) - 8.0) < 1e-5);
	pts_free(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plate),
		cmocka_unit_test(test_plate_band),
		cmocka_unit_test(test_curved),
		cmocka_unit_test(test_order_bend),
		cmocka_unit_test(test_nothing),
		cmocka_unit_test(test_crease),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
