/* The scan's outline (host/stages/silhouette.h, dp_surface_params.silhouette):
 * the view axis is found where a scanner's normals leave it, and only there;
 * points outside the outline come back across the axis, holes in it are
 * filled; anchors sunk out of the scan's outline come back into it; the pipeline
 * reports the axis and keeps every point inside. */
#include "testkit.h"

#include "core/common.h"
#include "stages/silhouette.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NORMALS 4000

static double angle_deg(const float a[3], const double b[3])
{
	double bl = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
	double c = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / bl;
	return acos(fmin(c, 1.0)) * 180.0 / M_PI;
}

/* A one-view scan's normals face the eye, none within 10° of grazing
 * (here: all within 75° of it): the axis is found, up to its sign. */
static void test_axis_one_view(void **state)
{
	(void)state;
	float nx[NORMALS], ny[NORMALS], nz[NORMALS], axis[3];
	const double eye[3] = {0.6, -0.3, 0.74};
	tk_normals_in_cap(NORMALS, eye, 75.0, nx, ny, nz);
	int found = 0;
	double fraction = 1.0;
	dp_silhouette_axis(NORMALS, nx, ny, nz, 0.065, &found, axis, &fraction);
	printf("one view: found %d, axis %.1f deg from the eye, grazing %.4f\n", found, angle_deg(axis, eye), fraction);
	assert_true(found);
	assert_true(angle_deg(axis, eye) < 3.0);
	assert_true(fraction < 0.01);
}

/* Normals over every direction (a complete scan) put about 17% near any
 * axis: none found. Too few normals: none found either, fraction 1. */
static void test_axis_none(void **state)
{
	(void)state;
	float nx[NORMALS], ny[NORMALS], nz[NORMALS], axis[3];
	const double z[3] = {0.0, 0.0, 1.0};
	tk_normals_in_cap(NORMALS, z, 180.0, nx, ny, nz);
	int found = 1;
	double fraction = 0.0;
	dp_silhouette_axis(NORMALS, nx, ny, nz, 0.065, &found, axis, &fraction);
	printf("all round: found %d, grazing %.4f\n", found, fraction);
	assert_false(found);
	assert_true(fraction > 0.12 && fraction < 0.22);
	tk_normals_in_cap(DP_SILHOUETTE_MIN_NORMALS - 1, z, 75.0, nx, ny, nz);
	dp_silhouette_axis(DP_SILHOUETTE_MIN_NORMALS - 1, nx, ny, nz, 0.065, &found, axis, &fraction);
	assert_false(found);
	assert_true(fraction == 1.0);
}

/* A box's normals (three faces seen from one octant) leave every direction
 * oblique to all of them free of grazing normals: no unique axis. */
static void test_axis_box(void **state)
{
	(void)state;
	float nx[NORMALS], ny[NORMALS], nz[NORMALS], axis[3];
	for (size_t i = 0; i < NORMALS; i++) {
		nx[i] = i % 3 == 0, ny[i] = i % 3 == 1, nz[i] = i % 3 == 2;
	}
	int found = 1;
	double fraction = 1.0;
	dp_silhouette_axis(NORMALS, nx, ny, nz, 0.065, &found, axis, &fraction);
	printf("box: found %d, grazing %.4f\n", found, fraction);
	assert_true(fraction == 0.0);
	assert_false(found);
}

/* Input filling the annulus 0.5 <= rho <= 1 across z, at every height in
 * [-1, 1], seen along z. */
static void annulus(dp_cloud *in)
{
	dp_error err = {0};
	const size_t rings = 40, around = 200;
	if (dp_cloud_alloc(in, rings * around, 0, &err) != DP_OK)
		fail_msg("%s", err.message);
	for (size_t k = 0; k < rings; k++)
		for (size_t j = 0; j < around; j++) {
			size_t i = k * around + j;
			double rho = 0.5 + 0.5 * (double)k / (double)(rings - 1), t = 2.0 * M_PI * (double)j / (double)around;
			in->x[i] = (float)(rho * cos(t)), in->y[i] = (float)(rho * sin(t));
			in->z[i] = (float)(-1.0 + 2.0 * (double)((i * 7919) % 1000) / 999.0);
		}
}

/* Outside the disc a point comes back across z to within the margin and a
 * cell of the rim, its z untouched; inside (the hole in the middle too) and
 * far along z nothing moves; a point far off the grid comes back too. */
static void test_hold(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud in = {0};
	annulus(&in);
	dp_silhouette s = {0};
	const float axis[3] = {0.0f, 0.0f, 1.0f};
	const double cell = 0.02, margin = 0.1;
	if (dp_silhouette_build(&s, &in, axis, cell, margin, NULL, 0.0, &err) != DP_OK)
		fail_msg("%s", err.message);
	float x[5] = {2.0f, 0.0f, 0.6f, -300.0f, 0.7f}, y[5] = {0.0f, 0.0f, 0.3f, 40.0f, -0.7f};
	float z[5] = {0.3f, 0.2f, 5.0f, -0.5f, 0.0f};
	size_t moved = dp_silhouette_hold(&s, 5, x, y, z);
	double rho0 = hypot(x[0], y[0]), rho3 = hypot(x[3], y[3]);
	printf("hold: moved %zu, to rho %.4f and %.4f\n", moved, rho0, rho3);
	assert_int_equal(moved, 2);
	assert_true(rho0 > 1.0 && rho0 <= 1.0 + margin + 2.0 * cell);
	assert_true(fabsf(y[0]) < 2.0 * cell && z[0] == 0.3f);
	assert_true(rho3 > 1.0 && rho3 <= 1.0 + margin + 3.0 * cell && z[3] == -0.5f);
	assert_true(x[1] == 0.0f && y[1] == 0.0f && z[2] == 5.0f && x[4] == 0.7f);
	/* all of the unmoved ones are inside: a second pass moves none */
	assert_int_equal(dp_silhouette_hold(&s, 5, x, y, z), 0);
	dp_silhouette_free(&s);
	/* bad arguments */
	assert_int_equal(dp_silhouette_build(&s, &in, axis, 0.0, margin, NULL, 0.0, &err), DP_ERR_ARG);
	assert_int_equal(dp_silhouette_build(&s, &in, axis, cell, -1.0, NULL, 0.0, &err), DP_ERR_ARG);
	dp_cloud_free(&in);
}

/* Over the unit disc of the xy plane, a spherical cap on each half about the
 * z axis with unit normals: x < 0 rising to `left` degrees from the axis at
 * its rim, x >= 0 to `right` (0: flat, 90: a hemisphere), so that seen
 * along z each half's edge faces the scanner or turns away from it. */
static void two_caps(dp_cloud *in, double left, double right)
{
	dp_error err = {0};
	const size_t n = 6000;
	if (dp_cloud_alloc(in, n, 1, &err) != DP_OK)
		fail_msg("%s", err.message);
	for (size_t i = 0; i < n; i++) {
		/* even in area over the disc */
		double rho = sqrt(((double)i + 0.5) / (double)n), t = (double)i * M_PI * (3.0 - sqrt(5.0));
		double x = rho * cos(t), y = rho * sin(t), rim = (x < 0.0 ? left : right) * M_PI / 180.0;
		double z = 0.0, nx = 0.0, ny = 0.0, nz = 1.0;
		if (rim > 0.0) {
			/* the sphere through the unit rim at that angle, centre below */
			double radius = 1.0 / sin(rim), below = radius * cos(rim);
			z = sqrt(fmax(0.0, radius * radius - rho * rho)) - below;
			nx = x / radius, ny = y / radius, nz = (z + below) / radius;
		}
		in->x[i] = (float)x, in->y[i] = (float)y, in->z[i] = (float)z;
		in->nx[i] = (float)nx, in->ny[i] = (float)ny, in->nz[i] = (float)nz;
	}
}

/* The edge margin: a point between it and the whole margin beyond the rim
 * comes back to within the edge margin on the half whose rim faces the
 * scanner and stays beside the half that turns away from it (normals more
 * than 50° from the axis at the rim grow the whole margin), on either side
 * (flat against a hemisphere, then caps of 40° against 60°); without
 * samples, or with an edge margin above the margin, the whole margin holds
 * all round. */
static void test_edge_margin(void **state)
{
	(void)state;
	dp_error err = {0};
	const float axis[3] = {0.0f, 0.0f, 1.0f};
	const double cell = 0.02, margin = 0.1, edge = 0.02;
	const double halves[4][2] = {{0.0, 90.0}, {90.0, 0.0}, {40.0, 60.0}, {60.0, 40.0}};
	for (int h = 0; h < 4; h++) {
		dp_cloud in = {0};
		two_caps(&in, halves[h][0], halves[h][1]);
		const double edges[3] = {edge, edge, 2.0 * margin};
		for (int k = 0; k < 3; k++) {
			dp_silhouette s = {0};
			const dp_cloud *facing = k == 1 ? NULL : &in;
			if (dp_silhouette_build(&s, &in, axis, cell, margin, facing, edges[k], &err) != DP_OK)
				fail_msg("%s", err.message);
			for (int side = 0; side < 2; side++) {
				float x = side ? 1.07f : -1.07f, y = 0.0f, z = 0.5f;
				size_t moved = dp_silhouette_hold(&s, 1, &x, &y, &z);
				int faces = halves[h][side] < 50.0;
				printf("caps %2.0f/%2.0f, facing %s, edge margin %.2f, %s rim: %s to x = %.4f\n",
				       halves[h][0], halves[h][1], facing ? "given" : "none", edges[k],
				       side ? "right" : "left", moved ? "moved" : "stays", (double)x);
				if (k == 0 && faces) {
					assert_int_equal(moved, 1);
					assert_true(fabsf(x) > 1.0f && fabsf(x) <= (float)(1.0 + edge + 2.0 * cell));
				} else {
					assert_int_equal(moved, 0);
				}
			}
			assert_true(s.margin == margin);
			dp_silhouette_free(&s);
		}
		dp_cloud_free(&in);
	}
	/* a negative edge margin, or samples without normals */
	dp_cloud in = {0}, bare = {0};
	two_caps(&in, 0.0, 0.0);
	dp_silhouette s = {0};
	assert_int_equal(dp_silhouette_build(&s, &in, axis, cell, margin, &in, -1.0, &err), DP_ERR_ARG);
	if (dp_cloud_alloc(&bare, 3, 0, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(dp_silhouette_build(&s, &in, axis, cell, margin, &bare, edge, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "without normals"));
	dp_cloud_free(&bare);
	dp_cloud_free(&in);
}

/* The grid against brute force on an outline with holes, dents and islands:
 * each cell's inset is its distance to the nearest cell outside, each
 * outside cell's nearest cell inside is a nearest one. */
static void test_grid_exact(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud in = {0};
	const size_t n = 3000;
	if (dp_cloud_alloc(&in, n, 0, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	for (size_t i = 0; i < n; i++) {
		/* three blobs of different sizes, some points far out alone */
		double cx[3] = {0.0, 1.3, -0.4}, cy[3] = {0.0, 0.2, 1.1}, rad[3] = {0.8, 0.35, 0.2};
		int b = (int)(i % 3);
		double a = 2.0 * M_PI * dp_rng_uniform(&rng), t = rad[b] * sqrt(dp_rng_uniform(&rng));
		in.x[i] = (float)(cx[b] + t * cos(a)), in.y[i] = (float)(cy[b] + t * sin(a));
		in.z[i] = (float)dp_rng_uniform(&rng);
	}
	dp_silhouette s = {0};
	const float axis[3] = {0.0f, 0.0f, 1.0f};
	if (dp_silhouette_build(&s, &in, axis, 0.05, 0.07, NULL, 0.0, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t cells = (size_t)s.nu * (size_t)s.nv, inside = 0, checked = 0;
	for (size_t c = 0; c < cells; c++) {
		int ci = (int)(c % (size_t)s.nu), cj = (int)(c / (size_t)s.nu);
		int in_c = s.nearest[c] == (int32_t)c;
		inside += in_c;
		double best = INFINITY;
		for (size_t k = 0; k < cells; k++) {
			int in_k = s.nearest[k] == (int32_t)k;
			if (in_k == in_c)
				continue;
			double di = (int)(k % (size_t)s.nu) - ci, dj = (int)(k / (size_t)s.nu) - cj;
			best = fmin(best, di * di + dj * dj);
		}
		if (in_c) {
			assert_true(fabs(s.inset[c] - s.cell * sqrt(best)) < 1e-4 * s.cell);
		} else {
			int32_t k = s.nearest[c];
			double di = (int)(k % s.nu) - ci, dj = (int)(k / s.nu) - cj;
			assert_true(s.nearest[k] == k);
			assert_true(fabs(di * di + dj * dj - best) < 1e-9);
			assert_true(s.inset[c] == 0.0f);
		}
		checked++;
	}
	printf("grid %d x %d: %zu cells inside, every inset and nearest cell as brute force finds them\n", s.nu, s.nv,
	       inside);
	assert_true(inside > 0 && inside < cells && checked == cells);
	dp_silhouette_free(&s);
	dp_cloud_free(&in);
}

/* The front half of a unit sphere seen along z: its outline is the unit
 * disc (grown by 0.1). An anchor sunk from a sample at the rim straight
 * across and out the far side comes back along its line to just inside the
 * disc, a margin in; one sunk along the axis past the centre, still inside
 * seen along z, stays, as does one at the centre. */
static void test_cap(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud in = {0};
	const size_t n = 20000;
	const double margin = 0.1;
	if (dp_cloud_alloc(&in, n, 0, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double z[3] = {0.0, 0.0, 1.0};
	tk_normals_in_cap(n, z, 90.0, in.x, in.y, in.z);
	dp_silhouette s = {0};
	const float axis[3] = {0.0f, 0.0f, 1.0f};
	if (dp_silhouette_build(&s, &in, axis, 0.01, margin, NULL, 0.0, &err) != DP_OK)
		fail_msg("%s", err.message);
	float p[3] = {0.99f, 0.0f, 0.14f}, q[3] = {-1.6f, 0.0f, 0.14f};
	assert_int_equal(dp_silhouette_cap(&s, p, q), 1);
	printf("cap: anchor sunk 2.6 across the disc ends at x = %.4f\n", q[0]);
	assert_true(q[0] < -0.95 && q[0] > -1.0 - 0.02 && q[1] == 0.0f && q[2] == 0.14f);
	float a[3] = {0.0f, 0.0f, 1.0f}, b[3] = {0.0f, 0.0f, -3.0f}, c[3] = {0.0f, 0.0f, 0.0f};
	assert_int_equal(dp_silhouette_cap(&s, a, b), 0);
	assert_true(b[2] == -3.0f);
	assert_int_equal(dp_silhouette_cap(&s, a, c), 0);
	/* a sample off the outline leaves its anchor where it is */
	float off[3] = {3.0f, 0.0f, 0.0f}, far[3] = {6.0f, 0.0f, 0.0f};
	assert_int_equal(dp_silhouette_cap(&s, off, far), 0);
	assert_true(far[0] == 6.0f);
	dp_silhouette_free(&s);
	/* with no margin the outline itself bounds the anchor */
	if (dp_silhouette_build(&s, &in, axis, 0.01, 0.0, NULL, 0.0, &err) != DP_OK)
		fail_msg("%s", err.message);
	float q0[3] = {-5.0f, 0.0f, 0.14f};
	assert_int_equal(dp_silhouette_cap(&s, p, q0), 1);
	assert_true(q0[0] < -0.97f && q0[0] > -1.0f - 0.02f);
	dp_silhouette_free(&s);
	/* an axis not of unit length is refused */
	const float half[3] = {0.0f, 0.0f, 0.5f};
	assert_int_equal(dp_silhouette_build(&s, &in, half, 0.01, 0.0, NULL, 0.0, &err), DP_ERR_ARG);
	dp_cloud_free(&in);
}

/* Seen along the axis found, every surface point of a one-view scan of the
 * built-in torus lies inside the input's outline grown by the margin, and
 * the run reports the axis; with the outline off none is reported. */
static void test_pipeline(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud scan = {0};
	tk_scan_shape("torus", 1, 96, 0.002, 1, NULL, NULL, &scan);
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = 1500;
	p.refine.coarse_samples = 1000;
	dp_result on = {0}, off = {0};
	if (dp_consolidate(tk_cl_context(), &scan, &p, &on, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double *a = on.surface_stats.silhouette_axis;
	printf("torus one view: axis (%.3f %.3f %.3f), grazing %.4f, %zu held, %zu anchors capped\n", a[0], a[1], a[2],
	       on.surface_stats.silhouette_grazing, on.surface_stats.silhouette_held, on.silhouette_capped);
	assert_true(a[0] != 0.0 || a[1] != 0.0 || a[2] != 0.0);
	tk_assert_rows_in_step(&on, 1500);
	dp_silhouette s = {0};
	const float axis[3] = {(float)a[0], (float)a[1], (float)a[2]};
	if (dp_silhouette_build(&s, &scan, axis, on.r, p.surface.silhouette_margin_r * on.r, NULL, 0.0, &err) != DP_OK)
		fail_msg("%s", err.message);
	/* r grew over the levels: the outline at the last r holds the earlier ones */
	assert_int_equal(dp_silhouette_hold(&s, on.surface.n, on.surface.x, on.surface.y, on.surface.z), 0);
	dp_silhouette_free(&s);
	p.surface.silhouette = 0;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &off, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double *b = off.surface_stats.silhouette_axis;
	assert_true(b[0] == 0.0 && b[1] == 0.0 && b[2] == 0.0);
	assert_int_equal(off.surface_stats.silhouette_held, 0);
	assert_int_equal(off.silhouette_capped, 0);
	dp_result_free(&on);
	dp_result_free(&off);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_axis_one_view), cmocka_unit_test(test_axis_none), cmocka_unit_test(test_axis_box),
		cmocka_unit_test(test_hold),
		cmocka_unit_test(test_edge_margin),          cmocka_unit_test(test_grid_exact), cmocka_unit_test(test_cap),
		cmocka_unit_test(test_pipeline),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
