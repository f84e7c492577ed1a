/* Points stranded in a skeletal sheet (host/stages/sheet_points.h) on a
 * plate whose answer is known: a plate 4 r thick, its skeleton a sheet of
 * spots r apart in its mid-plane z = 0, its top face sampled r apart and
 * held by input, its bottom face completed and sampled 2 r apart. Points
 * lying in the mid-plane with their deep points along it move to the bottom
 * face (the less sampled one) or to the face whose side they lie on, with
 * the face's normal; the faces' own points, a held point, a point off the
 * sheet, a point over a skeletal curve and a rim point beyond the sheet's
 * edge stay. */
#include "testkit.h"

#include "core/common.h"
#include "stages/sheet_points.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define R 1.0
#define HALF 2.0   /* half thickness, in r */
#define EXTENT 12  /* the plate spans [-EXTENT, EXTENT] r in x and y */
#define MAX_POINTS 2048

typedef struct scene {
	size_t n, spots;
	float px[MAX_POINTS], py[MAX_POINTS], pz[MAX_POINTS], nx[MAX_POINTS], ny[MAX_POINTS], nz[MAX_POINTS];
	float hx[MAX_POINTS], hy[MAX_POINTS], hz[MAX_POINTS], eta[MAX_POINTS];
	float sx[MAX_POINTS], sy[MAX_POINTS], sz[MAX_POINTS];
	float scratch[4][MAX_POINTS];
} scene;

static size_t add_point(scene *s, float x, float y, float z, float hx, float hy, float hz, float eta)
{
	size_t i = s->n++;
	assert_true(i < MAX_POINTS);
	s->px[i] = x, s->py[i] = y, s->pz[i] = z;
	s->hx[i] = hx, s->hy[i] = hy, s->hz[i] = hz;
	float d[3] = {x - hx, y - hy, z - hz}, len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	s->nx[i] = d[0] / len, s->ny[i] = d[1] / len, s->nz[i] = d[2] / len;
	s->eta[i] = eta;
	return i;
}

/* The plate, its bottom face sampled every bottom_step r; *curve_h receives
 * a spot of a skeletal curve beside it. */
static void plate(scene *s, float curve_h[3], int bottom_step)
{
	s->n = s->spots = 0;
	for (int i = -EXTENT; i <= EXTENT; i++)
		for (int j = -EXTENT; j <= EXTENT; j++) {
			size_t k = s->spots++;
			s->sx[k] = (float)(i * R), s->sy[k] = (float)(j * R), s->sz[k] = 0.0f;
			/* top: held by input */
			add_point(s, (float)(i * R), (float)(j * R), (float)(HALF * R), s->sx[k], s->sy[k], 0.0f, 20.0f);
			/* bottom: completed */
			if (i % bottom_step == 0 && j % bottom_step == 0)
				add_point(s, (float)(i * R), (float)(j * R), (float)(-HALF * R), s->sx[k], s->sy[k], 0.0f,
					  1.0f);
		}
	/* a skeletal curve along x, far from the plate */
	for (int i = -6; i <= 6; i++) {
		size_t k = s->spots++;
		s->sx[k] = (float)(i * R), s->sy[k] = 40.0f * R, s->sz[k] = 0.0f;
	}
	curve_h[0] = 0.0f, curve_h[1] = 40.0f * R, curve_h[2] = 0.0f;
}

static size_t lift(scene *s)
{
	dp_sheet_points_args a = {
		.n = s->n, .px = s->px, .py = s->py, .pz = s->pz, .nx = s->nx, .ny = s->ny, .nz = s->nz,
		.hx = s->hx, .hy = s->hy, .hz = s->hz, .eta = s->eta, .held_support = 1.0f,
		.spots = s->spots, .sx = s->sx, .sy = s->sy, .sz = s->sz, .r = R,
		.to_x = s->scratch[0], .to_y = s->scratch[1], .to_z = s->scratch[2], .chosen = s->scratch[3],
	};
	size_t moved = 0;
	dp_error err = {0};
	if (dp_sheet_points_lift(&a, &moved, &err) != DP_OK)
		fail_msg("%s", err.message);
	return moved;
}

static void test_stranded_points_cross(void **state)
{
	(void)state;
	static scene s;
	float curve_h[3];
	plate(&s, curve_h, 2);
	size_t faces = s.n;
	/* in the mid-plane, deep point along x: the bottom face samples less */
	size_t mid = add_point(&s, 0.5f, 0.5f, 0.1f, 2.0f, 0.5f, 0.0f, 1.0f);
	/* 0.4 r above the plane, beyond SHEET_SIDE_R: its own side, the top */
	size_t above = add_point(&s, -3.5f, 2.5f, 0.4f, -5.0f, 2.5f, 0.0f, 1.0f);
	/* held by input: stays */
	size_t held = add_point(&s, 3.5f, -2.5f, 0.1f, 5.0f, -2.5f, 0.0f, 5.0f);
	/* 1 r off the plane: an oblique deep point, not a stranded point */
	size_t off = add_point(&s, -2.5f, -3.5f, -1.0f, -4.5f, -3.5f, 0.0f, 1.0f);
	/* over a curve: no sheet to cross */
	size_t curve = add_point(&s, 1.5f, 40.0f, 0.1f, curve_h[0], curve_h[1], curve_h[2], 1.0f);
	/* the plate's rim face, 2 r beyond the sheet's last row, its deep point
	 * running outwards along the sheet: stays */
	size_t rim = add_point(&s, (float)(EXTENT + 2) * R, 0.5f, 0.1f, (float)EXTENT * R, 0.5f, 0.0f, 1.0f);
	float before[6][3];
	const size_t watch[6] = {mid, above, held, off, curve, rim};
	for (int k = 0; k < 6; k++)
		before[k][0] = s.px[watch[k]], before[k][1] = s.py[watch[k]], before[k][2] = s.pz[watch[k]];
	float face_z[MAX_POINTS];
	for (size_t i = 0; i < faces; i++)
		face_z[i] = s.pz[i];
	size_t moved = lift(&s);
	printf("plate %g r thick: %zu moved; mid-plane point to z = %.3f (normal z %.2f), the one above to z = %.3f\n",
	       2.0 * HALF, moved, s.pz[mid], s.nz[mid], s.pz[above]);
	assert_int_equal(moved, 2);
	/* to the bottom face, the lateral offset kept, facing down */
	assert_float_equal(s.pz[mid], -HALF * R, 1e-4);
	assert_float_equal(s.px[mid], before[0][0], 1e-5);
	assert_float_equal(s.py[mid], before[0][1], 1e-5);
	assert_float_equal(s.nz[mid], -1.0f, 1e-5);
	assert_float_equal(s.pz[above], HALF * R, 1e-4);
	assert_float_equal(s.nz[above], 1.0f, 1e-5);
	for (int k = 2; k < 6; k++)
		assert_true(s.px[watch[k]] == before[k][0] && s.py[watch[k]] == before[k][1] &&
			    s.pz[watch[k]] == before[k][2]);
	for (size_t i = 0; i < faces; i++)
		assert_true(s.pz[i] == face_z[i]);
}

/* The less sampled face decides: with the top completed and sparse and the
 * bottom held and dense, a mid-plane point goes up. */
static void test_side_by_sampling(void **state)
{
	(void)state;
	static scene s;
	float curve_h[3];
	plate(&s, curve_h, 2);
	for (size_t i = 0; i < s.n; i++)
		s.pz[i] = -s.pz[i], s.nz[i] = -s.nz[i];
	size_t mid = add_point(&s, 0.5f, 0.5f, -0.1f, 2.0f, 0.5f, 0.0f, 1.0f);
	assert_int_equal(lift(&s), 1);
	assert_float_equal(s.pz[mid], HALF * R, 1e-4);
	assert_float_equal(s.nz[mid], 1.0f, 1e-5);
}

/* The depth is the median across the sheet: with every face's deep point
 * leaning (one spot along x; 2.24 r long, 2 r across) and five held points
 * nearby whose deep points reach 9 r across, the mid-plane point still lands
 * on the face, 2 r down (a mean would put it 2.7 r down, whole lengths 2.24 r). */
static void test_depth_is_median_across(void **state)
{
	(void)state;
	static scene s;
	float curve_h[3];
	plate(&s, curve_h, 2);
	size_t faces = s.n;
	for (size_t i = 0; i < faces; i++) {
		float lean = s.pz[i] > 0.0f ? -1.0f : 1.0f;
		if (fabsf(s.hx[i] + lean) <= EXTENT * R)
			s.hx[i] += lean * (float)R;
	}
	for (int k = 0; k < 5; k++)
		add_point(&s, (float)(-0.5 - 0.25 * k), 0.5f, 1.0f, (float)(-0.5 - 0.25 * k), 0.5f, -8.0f, 20.0f);
	size_t mid = add_point(&s, 0.5f, 0.5f, 0.1f, 2.0f, 0.5f, 0.0f, 1.0f);
	assert_int_equal(lift(&s), 1);
	assert_float_equal(s.pz[mid], -HALF * R, 1e-4);
}

/* Faces sampled alike: the point goes to the face it lies towards, however
 * close to the plane, whichever sign the sheet's normal came out with. */
static void test_tie_goes_to_its_side(void **state)
{
	(void)state;
	static scene s;
	float curve_h[3];
	plate(&s, curve_h, 1);
	size_t up = add_point(&s, 0.5f, 0.5f, 0.05f, 2.0f, 0.5f, 0.0f, 1.0f);
	size_t down = add_point(&s, -4.5f, -4.5f, -0.05f, -6.0f, -4.5f, 0.0f, 1.0f);
	assert_int_equal(lift(&s), 2);
	assert_float_equal(s.pz[up], HALF * R, 1e-4);
	assert_float_equal(s.nz[up], 1.0f, 1e-5);
	assert_float_equal(s.pz[down], -HALF * R, 1e-4);
	assert_float_equal(s.nz[down], -1.0f, 1e-5);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stranded_points_cross),
		cmocka_unit_test(test_side_by_sampling),
		cmocka_unit_test(test_depth_is_median_across),
		cmocka_unit_test(test_tie_goes_to_its_side),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
