/* Facing the scanner (host/stages/scanner.h, dp_surface_params.face_scanner):
 * a scan is one-sided when its clearly axial normals point one way along the
 * view axis, or nearly so with its samples in one layer along it; the
 * surface stage turns held points' normals that face away from the scanner,
 * and leaves them without it; the pipeline finds the side of a one-view scan
 * and none for two opposite views, and takes a side given. */
#include "testkit.h"

#include "core/common.h"
#include "stages/scanner.h"
#include "stages/silhouette.h"
#include "tools/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NORMALS 4000
/* radius of the negated patch, r */
#define PATCH_R 4.0

static double dot(const float *x, const float *y, const float *z, size_t i, const float t[3])
{
	return (double)x[i] * t[0] + (double)y[i] * t[1] + (double)z[i] * t[2];
}

/* Every k-th normal negated. */
static void negate_every(size_t n, size_t k, float *nx, float *ny, float *nz)
{
	for (size_t i = 0; i < n; i += k)
		nx[i] = -nx[i], ny[i] = -ny[i], nz[i] = -nz[i];
}

/* n points 1 apart on a square grid across the unit `axis`, at depth 0,
 * or, with `layers` 2, every other one at depth `apart` instead. */
static void grid_across(size_t n, const float axis[3], int layers, double apart, float *x, float *y, float *z)
{
	float u[3], v[3];
	dp_silhouette_across(axis, u, v);
	size_t side = (size_t)ceil(sqrt((double)n));
	for (size_t i = 0; i < n; i++) {
		double a = (double)(i % side), b = (double)(i / side), d = layers == 2 && i % 2 ? apart : 0.0;
		x[i] = (float)(a * u[0] + b * v[0] + d * axis[0]);
		y[i] = (float)(a * u[1] + b * v[1] + d * axis[1]);
		z[i] = (float)(a * u[2] + b * v[2] + d * axis[2]);
	}
}

/* Swaps the points into an order unrelated to their depth (a fixed
 * permutation: multiplying by a number prime to n). */
static void shuffle(size_t n, float *x, float *y, float *z)
{
	static float t[3][NORMALS];
	for (size_t i = 0; i < n; i++) {
		size_t j = (i * 2654435761u) % n;
		t[0][j] = x[i], t[1][j] = y[i], t[2][j] = z[i];
	}
	memcpy(x, t[0], n * sizeof(float));
	memcpy(y, t[1], n * sizeof(float));
	memcpy(z, t[2], n * sizeof(float));
}

static double layered_of(float *x, float *y, float *z, const float axis[3])
{
	dp_error err = {0};
	double layered = -1.0;
	shuffle(NORMALS, x, y, z);
	assert_int_equal(dp_scanner_layered(NORMALS, x, y, z, axis, 1.0, &layered, &err), DP_OK);
	return layered;
}

/* Points 1 apart, in no particular order: one layer across the axis; one
 * steep layer (80° to it, sampled 1 apart along itself: rows along x, the
 * slope along y); two halves side by side across the axis, 10 apart along
 * it (a step, still one layer per column but at the step's edge); and two
 * layers 10 apart over the same columns. A spacing of 0 is refused. */
static void test_layered(void **state)
{
	(void)state;
	static float x[NORMALS], y[NORMALS], z[NORMALS];
	const float axis[3] = {0.0f, 0.0f, 1.0f};
	dp_error err = {0};
	double layered;
	grid_across(NORMALS, axis, 1, 0.0, x, y, z);
	assert_true(layered_of(x, y, z, axis) == 0.0);
	for (size_t i = 0; i < NORMALS; i++) {
		double b = (double)(i / 64);
		x[i] = (float)(i % 64);
		y[i] = (float)(b * cos(80.0 * M_PI / 180.0));
		z[i] = (float)(b * sin(80.0 * M_PI / 180.0));
	}
	assert_true(layered_of(x, y, z, axis) == 0.0);
	grid_across(NORMALS, axis, 1, 0.0, x, y, z);
	/* the step runs along y and x both, so that columns told apart by
	 * either direction alone would merge the halves */
	for (size_t i = 0; i < NORMALS; i++)
		z[i] = x[i] + y[i] < 0.0f ? 0.0f : 10.0f;
	layered = layered_of(x, y, z, axis);
	printf("a step: %.3f of the points where a second layer is\n", layered);
	assert_true(layered < 0.05);
	grid_across(NORMALS, axis, 2, 10.0, x, y, z);
	layered = layered_of(x, y, z, axis);
	printf("two layers: %.3f of the points where a second one is\n", layered);
	assert_true(layered > 0.95);
	assert_int_equal(dp_scanner_layered(NORMALS, x, y, z, axis, 0.0, &layered, &err), DP_ERR_ARG);
}

/* Normals within 75° of the eye face it: that side, and the other side
 * along the opposite axis. One in 200 of them negated (orientation's slips)
 * leave it one-sided whatever the samples' layers; one in 50 only in one
 * layer, one in 3 never. A whole sphere of normals is two-sided, and
 * normals all across the axis say nothing. */
static void test_side(void **state)
{
	(void)state;
	static float x[NORMALS], y[NORMALS], z[NORMALS], nx[NORMALS], ny[NORMALS], nz[NORMALS];
	const double eye[3] = {0.6, -0.3, 0.74};
	double len = sqrt(eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2]);
	const float axis[3] = {(float)(eye[0] / len), (float)(eye[1] / len), (float)(eye[2] / len)};
	const float back[3] = {-axis[0], -axis[1], -axis[2]};
	dp_error err = {0};
	int one = 0, two = 0;
#define SIDE(out) \
	assert_int_equal(dp_scanner_side(NORMALS, x, y, z, nx, ny, nz, axis, 0.5, 1.0, &out, &err), DP_OK)
	tk_normals_in_cap(NORMALS, eye, 75.0, nx, ny, nz);
	grid_across(NORMALS, axis, 2, 10.0, x, y, z);
	SIDE(two);
	assert_int_equal(two, 1);
	assert_int_equal(dp_scanner_side(NORMALS, x, y, z, nx, ny, nz, back, 0.5, 1.0, &two, &err), DP_OK);
	assert_int_equal(two, -1);
	negate_every(NORMALS, 200, nx, ny, nz);
	SIDE(two);
	assert_int_equal(two, 1);
	tk_normals_in_cap(NORMALS, eye, 75.0, nx, ny, nz);
	negate_every(NORMALS, 50, nx, ny, nz);
	SIDE(two);
	grid_across(NORMALS, axis, 1, 0.0, x, y, z);
	SIDE(one);
	assert_int_equal(two, 0);
	assert_int_equal(one, 1);
	tk_normals_in_cap(NORMALS, eye, 75.0, nx, ny, nz);
	negate_every(NORMALS, 3, nx, ny, nz);
	SIDE(one);
	assert_int_equal(one, 0);
	tk_normals_in_cap(NORMALS, eye, 180.0, nx, ny, nz);
	SIDE(one);
	assert_int_equal(one, 0);
	for (size_t i = 0; i < NORMALS; i++)
		nx[i] = axis[1], ny[i] = -axis[0], nz[i] = 0.0f;
	SIDE(one);
	assert_int_equal(one, 0);
#undef SIDE
}

/* Of normals within 75° of the eye with every 20th negated, exactly the
 * negated ones within 60° of pointing straight away are turned back. */
static void test_face(void **state)
{
	(void)state;
	float nx[NORMALS], ny[NORMALS], nz[NORMALS];
	const double eye[3] = {0.0, 0.0, 1.0};
	const float toward[3] = {0.0f, 0.0f, 1.0f};
	tk_normals_in_cap(NORMALS, eye, 75.0, nx, ny, nz);
	negate_every(NORMALS, 20, nx, ny, nz);
	size_t away = 0, grazing = 0;
	for (size_t i = 0; i < NORMALS; i++) {
		away += nz[i] < -0.5f;
		grazing += nz[i] < 0.0f && nz[i] >= -0.5f;
	}
	assert_true(away > 0 && grazing > 0);
	assert_int_equal(dp_scanner_face(NORMALS, nx, ny, nz, toward, 0.5), away);
	size_t left = 0;
	for (size_t i = 0; i < NORMALS; i++) {
		assert_true(nz[i] >= -0.5f);
		left += nz[i] < 0.0f;
	}
	assert_int_equal(left, grazing);
}

/* The built-in torus seen from `views` eyes on the ring at `elevation`
 * degrees (at 0 two of them face each other along x), `distance` diagonals
 * from its centre, res x res rays each; the first eye's position into eye
 * unless it is NULL. */
static void scan_torus_from(int views, double elevation, double distance, int res, dp_cloud *scan, double eye[3])
{
	dp_error err = {0};
	dp_shape shape;
	dp_cloud mesh = {0};
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = views;
	sp.res = res;
	sp.noise = 0.002;
	sp.normals = 0;
	sp.elevation_deg = elevation;
	sp.distance = distance;
	if (dp_shape_default("torus", &shape, &err) != DP_OK || dp_shape_mesh(&shape, &mesh, &err) != DP_OK ||
	    dp_scan(&mesh, &sp, scan, NULL, &err) != DP_OK)
		fail_msg("%s", err.message);
	if (eye) {
		/* as host/tools/scan.c places it: azimuth 0, z up */
		double lo[3], hi[3], el = elevation * M_PI / 180.0, far = dp_mesh_diagonal(&mesh) * distance;
		dp_mesh_bbox(&mesh, lo, hi);
		for (int c = 0; c < 3; c++)
			eye[c] = 0.5 * (lo[c] + hi[c]);
		eye[0] += far * cos(el);
		eye[2] += far * sin(el);
	}
	dp_cloud_free(&mesh);
}

static void scan_torus(int views, dp_cloud *scan)
{
	scan_torus_from(views, 0.0, 2.0, 96, scan, NULL);
}

/* Runs the pipeline on `scan` with 1500 deep points from 1000 coarse ones. */
static void consolidate(const dp_cloud *scan, dp_params *p, dp_result *res)
{
	dp_error err = {0};
	p->wlop.samples = 1500;
	p->refine.coarse_samples = 1000;
	if (dp_consolidate(tk_cl_context(), scan, p, res, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double *t = res->surface_stats.scanner, *a = res->surface_stats.silhouette_axis;
	printf("axis (%.3f %.3f %.3f), scanner (%.3f %.3f %.3f), %zu samples and %zu held normals turned\n", a[0], a[1],
	       a[2], t[0], t[1], t[2], res->samples_turned, res->surface_stats.scanner_turned);
	tk_assert_rows_in_step(res, 1500);
}

/* The direction from sample i towards the scanner: `toward`, or towards
 * `eye` when that is not NULL. */
static void towards(const dp_cloud *s, size_t i, const float toward[3], const double *eye, float t[3])
{
	if (!eye) {
		memcpy(t, toward, 3 * sizeof(float));
		return;
	}
	double d[3] = {eye[0] - s->x[i], eye[1] - s->y[i], eye[2] - s->z[i]};
	double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	for (int c = 0; c < 3; c++)
		t[c] = (float)(d[c] / len);
}

/* The surface stage on a one-view scan, from its own consolidation's
 * samples and inner ends, the normals of a patch that faces the scanner
 * negated. Input holds those points, so without the rule many keep the
 * negated sign (a held point's normal keeps its sign); with it every one
 * faces the scanner again: along the axis found, or towards `eye` (per
 * point) when that is not NULL. */
static void turn_held_patch(const dp_cloud *scan, const double *eye)
{
	dp_error err = {0};
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = 1500;
	p.refine.coarse_samples = 0;
	p.surface.face_scanner = 0;
	if (eye) {
		p.normals.use_viewpoint = 1;
		memcpy(p.normals.viewpoint, eye, sizeof p.normals.viewpoint);
	}
	dp_result res = {0};
	if (dp_consolidate(tk_cl_context(), scan, &p, &res, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_cloud *s = &res.wlop;
	float axis[3] = {0.0f, 0.0f, 0.0f}, toward[3] = {0.0f, 0.0f, 0.0f}, t[3], tc[3];
	int side = 0;
	if (!eye) {
		int found = 0;
		double fraction;
		dp_silhouette_axis(s->n, s->nx, s->ny, s->nz, p.surface.silhouette_grazing, &found, axis, &fraction);
		assert_true(found);
		if (dp_scanner_side(s->n, s->x, s->y, s->z, s->nx, s->ny, s->nz, axis, p.surface.face_scanner_cos, res.r,
				    &side, &err) != DP_OK)
			fail_msg("%s", err.message);
		assert_int_not_equal(side, 0);
		for (int c = 0; c < 3; c++)
			toward[c] = (float)side * axis[c];
	}
	/* a patch, as orientation gets a region wrong: the samples within 4 r
	 * of the one that faces the scanner most squarely */
	size_t centre = 0;
	for (size_t i = 1; i < s->n; i++) {
		towards(s, i, toward, eye, t);
		towards(s, centre, toward, eye, tc);
		if (dot(s->nx, s->ny, s->nz, i, t) > dot(s->nx, s->ny, s->nz, centre, tc))
			centre = i;
	}
	unsigned char *negated = calloc(s->n, 1);
	assert_non_null(negated);
	size_t count = 0;
	double reach2 = (PATCH_R * res.r) * (PATCH_R * res.r);
	for (size_t i = 0; i < s->n; i++) {
		double dx = s->x[i] - s->x[centre], dy = s->y[i] - s->y[centre], dz = s->z[i] - s->z[centre];
		if (dx * dx + dy * dy + dz * dz < reach2) {
			s->nx[i] = -s->nx[i], s->ny[i] = -s->ny[i], s->nz[i] = -s->nz[i];
			negated[i] = 1;
			count++;
		}
	}
	size_t away[2] = {0, 0};
	size_t turned = 0;
	for (int on = 0; on <= 1; on++) {
		dp_surface_params sp;
		dp_surface_params_default(&sp);
		sp.face_scanner = on;
		if (eye) {
			sp.use_viewpoint = 1;
			memcpy(sp.viewpoint, eye, sizeof sp.viewpoint);
		} else {
			/* as dp_consolidate passes them on */
			sp.scanner_side = side;
			for (int c = 0; c < 3; c++)
				sp.silhouette_axis[c] = axis[c];
		}
		dp_cloud skeleton = {0}, out = {0};
		dp_surface_stats st = {0};
		if (dp_cloud_alloc(&skeleton, res.skeleton.n, 0, &err) != DP_OK)
			fail_msg("%s", err.message);
		memcpy(skeleton.x, res.skeleton.x, s->n * sizeof(float));
		memcpy(skeleton.y, res.skeleton.y, s->n * sizeof(float));
		memcpy(skeleton.z, res.skeleton.z, s->n * sizeof(float));
		if (dp_surface(tk_cl_context(), scan, s, &skeleton, NULL, res.r, &sp, &out, NULL, &st, &err) != DP_OK)
			fail_msg("%s", err.message);
		for (size_t i = 0; i < s->n; i++) {
			towards(&out, i, toward, eye, t);
			away[on] += negated[i] && dot(out.nx, out.ny, out.nz, i, t) < 0.0;
		}
		double d = st.scanner[0] * toward[0] + st.scanner[1] * toward[1] + st.scanner[2] * toward[2];
		if (on) {
			turned = st.scanner_turned;
			/* with an eye there is no one direction to report */
			assert_true(eye ? st.scanner[0] == 0.0 && st.scanner[1] == 0.0 && st.scanner[2] == 0.0 : d > 0.999);
		} else {
			assert_true(st.scanner[0] == 0.0 && st.scanner[1] == 0.0 && st.scanner[2] == 0.0);
			assert_int_equal(st.scanner_turned, 0);
		}
		dp_cloud_free(&skeleton);
		dp_cloud_free(&out);
	}
	printf("torus one view%s: %zu of %zu held normals negated; facing away at the end: %zu without the rule, %zu "
	       "with it (%zu turns)\n",
	       eye ? " from a near eye" : "", count, s->n, away[0], away[1], turned);
	assert_true(count >= 30);
	assert_true(away[0] * 4 >= count);
	assert_int_equal(away[1], 0);
	assert_true(turned >= count);
	free(negated);
	dp_result_free(&res);
}

/* Along the axis found (20 of 54 stay negated without the rule when
 * measured). */
static void test_surface_turns_held(void **state)
{
	(void)state;
	dp_cloud scan = {0};
	scan_torus_from(1, 20.0, 2.0, 96, &scan, NULL);
	turn_held_patch(&scan, NULL);
	dp_cloud_free(&scan);
}

/* A perspective scanner 0.6 diagonals from the torus's centre, its eye
 * given: each held point faces the eye itself. */
static void test_surface_faces_eye(void **state)
{
	(void)state;
	dp_cloud scan = {0};
	double eye[3];
	scan_torus_from(1, 20.0, 0.6, 160, &scan, eye);
	turn_held_patch(&scan, eye);
	/* The pipeline takes the normals' viewpoint as the eye (no axis side
	 * then, so no direction reported) ... */
	dp_params p;
	dp_params_default(&p);
	p.normals.use_viewpoint = 1;
	memcpy(p.normals.viewpoint, eye, sizeof p.normals.viewpoint);
	dp_result res = {0};
	consolidate(&scan, &p, &res);
	const double *t = res.surface_stats.scanner, *a = res.surface_stats.silhouette_axis;
	assert_true(a[0] != 0.0 || a[1] != 0.0 || a[2] != 0.0);
	assert_true(t[0] == 0.0 && t[1] == 0.0 && t[2] == 0.0);
	assert_true(res.surface_stats.scanner_at_eye);
	dp_result_free(&res);
	/* ... and faces an eye of its own, here one on the far side, mirrored
	 * through the torus's centre with the normals left to the MST: the
	 * samples are turned towards it, and the points the input holds end
	 * facing it where they point clearly to or from it; without the rule
	 * many do not (351 of 532 when measured). */
	double far[3], lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
	for (size_t i = 0; i < scan.n; i++) {
		const float q[3] = {scan.x[i], scan.y[i], scan.z[i]};
		for (int c = 0; c < 3; c++)
			lo[c] = fmin(lo[c], q[c]), hi[c] = fmax(hi[c], q[c]);
	}
	for (int c = 0; c < 3; c++)
		far[c] = (lo[c] + hi[c]) - eye[c];
	size_t away[2] = {0, 0}, held = 0;
	for (int on = 0; on <= 1; on++) {
		dp_params_default(&p);
		p.surface.face_scanner = on;
		p.surface.use_viewpoint = 1;
		memcpy(p.surface.viewpoint, far, sizeof p.surface.viewpoint);
		consolidate(&scan, &p, &res);
		if (on) {
			assert_true(res.surface_stats.scanner_at_eye);
			assert_true(res.samples_turned * 2 > res.wlop.n);
		} else {
			assert_int_equal(res.samples_turned + res.surface_stats.scanner_turned, 0);
		}
		for (size_t i = 0; i < res.surface.n; i++) {
			if (res.eta[i] - 1.0f < 1.0f)
				continue;
			float to[3];
			towards(&res.surface, i, NULL, far, to);
			held += on;
			away[on] += dot(res.surface.nx, res.surface.ny, res.surface.nz, i, to) < -p.surface.face_scanner_cos;
		}
		dp_result_free(&res);
	}
	printf("pipeline with an eye on the far side: %zu held points, facing away from it %zu without the rule, %zu "
	       "with it\n",
	       held, away[0], away[1]);
	assert_true(held > 100);
	assert_true(away[0] * 2 > held);
	/* the PCA normal faces it; the normal blends in the deep point's
	 * direction, which a point that barely holds may follow (1 of 532 when
	 * measured) */
	assert_true(away[1] * 100 <= held);
	dp_cloud_free(&scan);
}

/* Every WLOP sample's normal within acos(-cos_min) of `toward`. */
static void assert_samples_face(const dp_result *res, const double toward[3], double cos_min)
{
	const dp_cloud *w = &res->wlop;
	for (size_t i = 0; i < w->n; i++)
		assert_true(w->nx[i] * toward[0] + w->ny[i] * toward[1] + w->nz[i] * toward[2] >= -cos_min);
}

/* The pipeline: a one-view scan of the torus (its eye along +x) is found
 * one-sided, with the outline on or off; two opposite views, along the axis
 * they share, are not; with the rule off no side is reported. A side given
 * is taken whatever the normals say (here the wrong one, so that the
 * samples are turned towards it), and needs an axis. */
static void test_pipeline_side(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud one = {0}, two = {0};
	scan_torus(1, &one);
	scan_torus(2, &two);
	const double eye[3] = {1.0, 0.0, 0.0}, away[3] = {-1.0, 0.0, 0.0};
	for (int outline = 0; outline <= 1; outline++) {
		dp_params p;
		dp_params_default(&p);
		p.surface.silhouette = outline;
		dp_result res = {0};
		consolidate(&one, &p, &res);
		const double *t = res.surface_stats.scanner;
		assert_true(fabs(sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) - 1.0) < 1e-6);
		assert_true(t[0] > 0.99);
		assert_samples_face(&res, t, p.surface.face_scanner_cos);
		dp_result_free(&res);
	}
	for (int views = 1; views <= 2; views++) {
		dp_params p;
		dp_params_default(&p);
		p.surface.face_scanner = views == 2;
		p.surface.silhouette_axis[0] = 1.0;
		dp_result res = {0};
		consolidate(views == 1 ? &one : &two, &p, &res);
		const double *t = res.surface_stats.scanner;
		assert_true(t[0] == 0.0 && t[1] == 0.0 && t[2] == 0.0);
		assert_int_equal(res.samples_turned + res.surface_stats.scanner_turned, 0);
		dp_result_free(&res);
	}
	dp_params p;
	dp_params_default(&p);
	p.surface.silhouette_axis[0] = 2.0;
	p.surface.scanner_side = -1;
	dp_result res = {0};
	consolidate(&one, &p, &res);
	assert_true(res.surface_stats.scanner[0] < -0.99);
	assert_true(res.samples_turned > 100);
	assert_samples_face(&res, away, p.surface.face_scanner_cos);
	dp_result_free(&res);
	p.surface.scanner_side = 1;
	consolidate(&one, &p, &res);
	assert_true(res.surface_stats.scanner[0] > 0.99);
	assert_int_equal(res.samples_turned, 0);
	assert_samples_face(&res, eye, p.surface.face_scanner_cos);
	dp_result_free(&res);
	p.surface.silhouette_axis[0] = 0.0;
	assert_int_equal(dp_consolidate(tk_cl_context(), &one, &p, &res, &err), DP_ERR_ARG);
	printf("%s\n", err.message);
	assert_non_null(strstr(err.message, "scanner side"));
	dp_cloud_free(&one);
	dp_cloud_free(&two);
}

/* dp_surface alone: a side given without an axis is refused. */
static void test_surface_side_needs_axis(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud input = {0}, samples = {0}, skeleton = {0}, out = {0};
	if (dp_cloud_alloc(&input, 4, 0, &err) != DP_OK || dp_cloud_alloc(&samples, 4, 1, &err) != DP_OK ||
	    dp_cloud_alloc(&skeleton, 4, 0, &err) != DP_OK)
		fail_msg("%s", err.message);
	for (size_t i = 0; i < 4; i++) {
		input.x[i] = samples.x[i] = (float)(i % 2);
		input.y[i] = samples.y[i] = (float)(i / 2);
		input.z[i] = samples.z[i] = 0.0f;
		samples.nx[i] = samples.ny[i] = 0.0f;
		samples.nz[i] = 1.0f;
		skeleton.x[i] = samples.x[i], skeleton.y[i] = samples.y[i], skeleton.z[i] = -1.0f;
	}
	dp_surface_params sp;
	dp_surface_params_default(&sp);
	sp.scanner_side = 1;
	assert_int_equal(dp_surface(tk_cl_context(), &input, &samples, &skeleton, NULL, 1.0, &sp, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	printf("%s\n", err.message);
	assert_non_null(strstr(err.message, "scanner side"));
	sp.scanner_side = 2;
	sp.silhouette_axis[2] = 1.0;
	assert_int_equal(dp_surface(tk_cl_context(), &input, &samples, &skeleton, NULL, 1.0, &sp, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	sp.scanner_side = 1;
	sp.use_viewpoint = 1;
	assert_int_equal(dp_surface(tk_cl_context(), &input, &samples, &skeleton, NULL, 1.0, &sp, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	printf("%s\n", err.message);
	assert_non_null(strstr(err.message, "side and a viewpoint"));
	sp.scanner_side = 0;
	sp.viewpoint[1] = NAN;
	assert_int_equal(dp_surface(tk_cl_context(), &input, &samples, &skeleton, NULL, 1.0, &sp, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	assert_non_null(strstr(err.message, "viewpoint is not finite"));
	sp.use_viewpoint = 0;
	sp.face_scanner_cos = NAN;
	assert_int_equal(dp_surface(tk_cl_context(), &input, &samples, &skeleton, NULL, 1.0, &sp, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	assert_non_null(strstr(err.message, "face-scanner cosine"));
	dp_cloud_free(&input);
	dp_cloud_free(&samples);
	dp_cloud_free(&skeleton);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_layered),
		cmocka_unit_test(test_side),
		cmocka_unit_test(test_face),
		cmocka_unit_test(test_surface_turns_held),
		cmocka_unit_test(test_surface_faces_eye),
		cmocka_unit_test(test_pipeline_side),
		cmocka_unit_test(test_surface_side_needs_axis),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
