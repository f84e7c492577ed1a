/* The virtual range scanner: coverage of complete and one-view scans,
 * exactness, requested noise, the BVH against brute force, and speed on a
 * 100K-triangle mesh. */
#include "testkit.h"

#include "tools/bvh.h"
#include "tools/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void make_shape(const char *name, int res, dp_shape *s, dp_cloud *m)
{
	dp_error err = {0};
	if (dp_shape_default(name, s, &err) != DP_OK)
		fail_msg("%s", err.message);
	if (res)
		s->resolution = res;
	if (dp_shape_mesh(s, m, &err) != DP_OK)
		fail_msg("%s", err.message);
}

static void scan(const dp_cloud *m, const dp_scan_params *p, dp_cloud *out)
{
	dp_error err = {0};
	if (dp_scan(m, p, out, NULL, &err) != DP_OK)
		fail_msg("%s", err.message);
}

static dp_eval_result evaluate(const dp_cloud *m, const dp_cloud *pts)
{
	dp_eval_result r;
	dp_error err = {0};
	if (dp_eval(m, pts, NULL, &r, &err) != DP_OK)
		fail_msg("%s", err.message);
	return r;
}

static void test_complete_scan_covers_sphere(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	make_shape("sphere", 0, &s, &m);
	dp_scan_params p;
	dp_scan_params_default(&p);
	p.layout = DP_SCAN_SPHERE;
	p.views = 6;
	p.res = 128;
	scan(&m, &p, &pts);
	dp_eval_result r = evaluate(&m, &pts);
	printf("6-view scan: %zu points, coverage %.4f, accuracy mean %.3g max %.3g\n", pts.n, r.coverage,
	       r.accuracy_mean, r.accuracy_max);
	assert_true(r.coverage > 0.95);
	/* Hits lie on the triangles up to float rounding of the output. */
	assert_true(r.accuracy_max < 1e-4);
	/* The points are also on the analytic sphere, within the chord sag. */
	double worst = 0;
	for (size_t i = 0; i < pts.n; i++) {
		double q[3] = {pts.x[i], pts.y[i], pts.z[i]};
		worst = fmax(worst, dp_shape_surface_distance(&s, q));
	}
	assert_true(worst < s.radius * M_PI * M_PI / (s.resolution * s.resolution) + 1e-6);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

static void test_one_view_covers_half(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	make_shape("sphere", 0, &s, &m);
	for (int persp = 0; persp < 2; persp++) {
		dp_scan_params p;
		dp_scan_params_default(&p);
		p.views = 1;
		p.res = 200;
		p.perspective = persp;
		scan(&m, &p, &pts);
		dp_eval_result r = evaluate(&m, &pts);
		/* Parallel rays see a hemisphere; a pinhole at distance D sees the
		 * cap (1 - R/D)/2 of the area. */
		double d = p.distance * dp_mesh_diagonal(&m), expect = persp ? 0.5 * (1.0 - s.radius / d) : 0.5;
		printf("one %s view: %zu points, coverage %.4f (visible area fraction %.4f)\n",
		       persp ? "pinhole" : "parallel", pts.n, r.coverage, expect);
		assert_true(r.coverage > 0.35 && r.coverage < 0.6);
		/* Only a band one coverage radius wide beyond the horizon can be
		 * covered without being seen. */
		assert_true(r.coverage < expect + 2 * r.coverage_radius * dp_mesh_diagonal(&m) / s.radius);
		dp_cloud_free(&pts);
	}
	dp_cloud_free(&m);
}

/* An odd ray count puts the middle column of rays in the plane through the
 * eye, the centre and the up axis: for the default view that is a meridian
 * plane of the sphere's mesh, which holds edges and bounding-box faces. Such
 * rays once passed through the front and hit the back (0.6% of a one-view
 * scan's points, 1 R behind the seen surface). Every hit must lie on the
 * hemisphere that faces the eye. */
static void test_rays_in_mesh_planes(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	make_shape("sphere", 0, &s, &m);
	dp_scan_params p;
	dp_scan_params_default(&p);
	p.views = 1;
	p.res = 201;
	scan(&m, &p, &pts);
	double mean[3] = {0, 0, 0};
	for (size_t i = 0; i < pts.n; i++) {
		mean[0] += pts.x[i];
		mean[1] += pts.y[i];
		mean[2] += pts.z[i];
	}
	double len = sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
	size_t behind = 0;
	for (size_t i = 0; i < pts.n; i++) {
		double along = (pts.x[i] * mean[0] + pts.y[i] * mean[1] + pts.z[i] * mean[2]) / len;
		behind += along < -0.01 * s.radius;
	}
	printf("one view at %d x %d rays: %zu points, %zu behind the seen hemisphere\n", p.res, p.res, pts.n,
	       behind);
	assert_int_equal(behind, 0);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

static void test_noise_level(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	make_shape("torus", 0, &s, &m);
	dp_scan_params p;
	dp_scan_params_default(&p);
	p.res = 128;
	p.noise = 0.004;
	scan(&m, &p, &pts);
	dp_eval_result r = evaluate(&m, &pts);
	/* Isotropic noise: the distance to the surface is |N(0, sigma)|, whose
	 * RMS is sigma and mean sigma sqrt(2/pi). */
	printf("noise %.4f: %zu points, accuracy rms %.5f, mean %.5f (expect %.5f)\n", p.noise, pts.n,
	       r.accuracy_rms, r.accuracy_mean, p.noise * sqrt(2.0 / M_PI));
	assert_true(fabs(r.accuracy_rms - p.noise) < 0.05 * p.noise);
	assert_true(fabs(r.accuracy_mean - p.noise * sqrt(2.0 / M_PI)) < 0.05 * p.noise);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

static void test_views_normals_and_seed(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, a, b;
	dp_error err = {0};
	make_shape("knot", 16, &s, &m);
	dp_scan_params p;
	dp_scan_params_default(&p);
	p.views = 3;
	p.res = 64;
	p.noise = 0.001;
	uint32_t *view;
	assert_int_equal(dp_scan(&m, &p, &a, &view, &err), DP_OK);
	assert_int_equal(dp_scan(&m, &p, &b, NULL, &err), DP_OK);
	assert_int_equal(a.n, b.n);
	assert_memory_equal(a.x, b.x, a.n * sizeof(float));
	assert_non_null(a.nx);
	double eyes[9], lo[3], hi[3], c[3];
	assert_int_equal(dp_scan_viewpoints(&m, &p, eyes, &err), DP_OK);
	dp_mesh_bbox(&m, lo, hi);
	for (int d = 0; d < 3; d++)
		c[d] = 0.5 * (lo[d] + hi[d]);
	double diag = dp_mesh_diagonal(&m);
	for (int v = 0; v < 3; v++) {
		double dist = sqrt(pow(eyes[3 * v] - c[0], 2) + pow(eyes[3 * v + 1] - c[1], 2) + pow(eyes[3 * v + 2] - c[2], 2));
		assert_true(fabs(dist - p.distance * diag) < 1e-9 * diag);
	}
	size_t per_view[3] = {0};
	for (size_t i = 0; i < a.n; i++) {
		assert_true(view[i] < 3);
		if (i > 0)
			assert_true(view[i] >= view[i - 1]);
		per_view[view[i]]++;
		const double *e = eyes + 3 * view[i];
		double facing = a.nx[i] * (e[0] - a.x[i]) + a.ny[i] * (e[1] - a.y[i]) + a.nz[i] * (e[2] - a.z[i]);
		assert_true(facing > 0);
	}
	printf("knot, 3 views: %zu + %zu + %zu points\n", per_view[0], per_view[1], per_view[2]);
	assert_true(per_view[0] > 0 && per_view[1] > 0 && per_view[2] > 0);
	free(view);
	dp_cloud_free(&b);
	p.seed = 2;
	assert_int_equal(dp_scan(&m, &p, &b, NULL, &err), DP_OK);
	assert_int_equal(a.n, b.n);
	assert_true(memcmp(a.x, b.x, a.n * sizeof(float)) != 0);
	dp_cloud_free(&a);
	dp_cloud_free(&b);
	dp_cloud_free(&m);
}

static void test_bvh_matches_brute_force(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m;
	dp_error err = {0};
	make_shape("chair", 8, &s, &m);
	dp_bvh bvh;
	assert_int_equal(dp_bvh_build(&bvh, &m, &err), DP_OK);
	double lo[3], hi[3];
	dp_mesh_bbox(&m, lo, hi);
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	int hits = 0, facing = 0;
	const int trials = 3000;
	for (int trial = 0; trial < trials; trial++) {
		double o[3], target[3], d[3];
		for (int k = 0; k < 3; k++) {
			double ext = hi[k] - lo[k];
			o[k] = lo[k] - ext + 3 * ext * dp_rng_uniform(&rng);
			target[k] = lo[k] + ext * dp_rng_uniform(&rng);
			d[k] = target[k] - o[k];
		}
		double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
		for (int k = 0; k < 3; k++)
			d[k] /= len;
		double best = INFINITY;
		for (size_t f = 0; f < m.nfaces; f++) {
			double a[3], b[3], c[3], e1[3], e2[3], t;
			dp_mesh_triangle(&m, f, a, b, c);
			for (int k = 0; k < 3; k++) {
				e1[k] = b[k] - a[k];
				e2[k] = c[k] - a[k];
			}
			if (dp_ray_triangle(o, d, a, e1, e2, &t) && t < best)
				best = t;
		}
		dp_bvh_hit hit;
		int found = dp_bvh_raycast(&bvh, o, d, INFINITY, &hit);
		if (found != (best < INFINITY))
			fail_msg("ray %d: BVH %s, brute force %s", trial, found ? "hits" : "misses",
				 best < INFINITY ? "hits" : "misses");
		if (found) {
			hits++;
			assert_true(hit.t == best);
		}
		/* Nearest triangle from the ray's origin and from its target. */
		for (int w = 0; w < 2; w++) {
			const double *q = w ? target : o;
			double bb = INFINITY, cp[3];
			for (size_t f = 0; f < m.nfaces; f++) {
				double a[3], b[3], c[3];
				dp_mesh_triangle(&m, f, a, b, c);
				dp_closest_point_triangle(q, a, b, c, cp);
				bb = fmin(bb, pow(q[0] - cp[0], 2) + pow(q[1] - cp[1], 2) + pow(q[2] - cp[2], 2));
			}
			uint32_t face;
			double d2 = dp_bvh_nearest(&bvh, q, cp, &face);
			if (fabs(d2 - bb) > 1e-12 * (1 + bb))
				fail_msg("point %d: BVH nearest %.17g, brute force %.17g", trial, d2, bb);
			/* A face facing a random way within a little past the nearest. */
			double n[3], reach = sqrt(bb) + 0.05 * (hi[0] - lo[0]) * dp_rng_uniform(&rng);
			for (int k = 0; k < 3; k++)
				n[k] = 2 * dp_rng_uniform(&rng) - 1;
			int brute = 0;
			for (size_t f = 0; f < m.nfaces && !brute; f++) {
				double a[3], b[3], c[3], fn[3];
				dp_mesh_triangle(&m, f, a, b, c);
				fn[0] = (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
				fn[1] = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]);
				fn[2] = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
				dp_closest_point_triangle(q, a, b, c, cp);
				brute = fn[0] * n[0] + fn[1] * n[1] + fn[2] * n[2] > 0 &&
					pow(q[0] - cp[0], 2) + pow(q[1] - cp[1], 2) + pow(q[2] - cp[2], 2) <= reach * reach;
			}
			int found = dp_bvh_facing_within(&bvh, q, reach * reach, n);
			if (found != brute)
				fail_msg("point %d: BVH %s a facing triangle, brute force %s", trial, found ? "finds" : "misses",
					 brute ? "finds one" : "none");
			facing += found;
		}
	}
	printf("BVH: %zu faces, %zu nodes, %d of %d rays hit, %d of %d points see a facing triangle near; all equal "
	       "brute force\n", bvh.ntris, bvh.nnodes, hits, trials, facing, 2 * trials);
	assert_true(hits > trials / 10 && hits < trials);
	assert_true(facing > trials / 10 && facing < 2 * trials - trials / 10);
	dp_bvh_free(&bvh);
	dp_cloud_free(&m);
}

static void test_primitives(void **state)
{
	(void)state;
	double a[3] = {0, 0, 0}, e1[3] = {1, 0, 0}, e2[3] = {0, 1, 0}, t;
	double o[3] = {0.25, 0.25, 2}, d[3] = {0, 0, -1}, back[3] = {0, 0, 1};
	assert_int_equal(dp_ray_triangle(o, d, a, e1, e2, &t), 1);
	assert_true(fabs(t - 2) < 1e-15);
	assert_int_equal(dp_ray_triangle(o, back, a, e1, e2, &t), 0);
	double o2[3] = {0.75, 0.75, 2};
	assert_int_equal(dp_ray_triangle(o2, d, a, e1, e2, &t), 0);
	double b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, q[3];
	double p1[3] = {0.2, 0.2, 3}, p2[3] = {2, -1, 0}, p3[3] = {1, 1, 0};
	dp_closest_point_triangle(p1, a, b, c, q);
	assert_true(fabs(q[0] - 0.2) + fabs(q[1] - 0.2) + fabs(q[2]) < 1e-15);
	dp_closest_point_triangle(p2, a, b, c, q);
	assert_true(fabs(q[0] - 1) + fabs(q[1]) + fabs(q[2]) < 1e-15);
	dp_closest_point_triangle(p3, a, b, c, q);
	assert_true(fabs(q[0] - 0.5) + fabs(q[1] - 0.5) < 1e-15);
	/* A collinear triangle is treated as its edges. */
	double cc[3] = {2, 0, 0}, p4[3] = {1.5, 1, 0};
	dp_closest_point_triangle(p4, a, b, cc, q);
	assert_true(fabs(q[0] - 1.5) + fabs(q[1]) + fabs(q[2]) < 1e-15);
}

static void test_large_mesh_speed(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	make_shape("sphere", 320, &s, &m);
	dp_scan_params p;
	dp_scan_params_default(&p);
	double t0 = dp_seconds();
	scan(&m, &p, &pts);
	double secs = dp_seconds() - t0;
	printf("scan of a %zu-triangle sphere: %d views x %d^2 rays -> %zu points in %.2f s\n", m.nfaces, p.views,
	       p.res, pts.n, secs);
	assert_true(m.nfaces >= 100000);
	assert_true(pts.n > 0);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

/* Ring eyes all sit at the elevation angle above the plane across the up
 * axis, evenly around it. */
static void test_up_axis(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m;
	dp_error err = {0};
	make_shape("cylinder", 8, &s, &m);
	double lo[3], hi[3], c[3], diag = dp_mesh_diagonal(&m);
	dp_mesh_bbox(&m, lo, hi);
	for (int d = 0; d < 3; d++)
		c[d] = 0.5 * (lo[d] + hi[d]);
	for (int axis = 0; axis < 3; axis++) {
		dp_scan_params p;
		dp_scan_params_default(&p);
		p.views = 4;
		p.up_axis = axis;
		double eyes[12], reach = p.distance * diag, el = p.elevation_deg * M_PI / 180.0;
		assert_int_equal(dp_scan_viewpoints(&m, &p, eyes, &err), DP_OK);
		for (int v = 0; v < 4; v++) {
			const double *e = eyes + 3 * v;
			assert_true(fabs(e[axis] - c[axis] - reach * sin(el)) < 1e-9 * reach);
			/* View 0 looks from axis up+1, view 1 from up+2 (quarter turns). */
			int along = (axis + 1 + (v & 1)) % 3;
			double sign = v < 2 ? 1.0 : -1.0;
			assert_true(fabs(e[along] - c[along] - sign * reach * cos(el)) < 1e-9 * reach);
		}
	}
	dp_cloud_free(&m);
}

static void test_bad_input(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	dp_error err = {0};
	make_shape("sphere", 8, &s, &m);
	dp_scan_params p;
	dp_scan_params_default(&p);
	p.views = 0;
	assert_int_equal(dp_scan(&m, &p, &pts, NULL, &err), DP_ERR_ARG);
	dp_scan_params_default(&p);
	p.noise = -0.1;
	assert_int_equal(dp_scan(&m, &p, &pts, NULL, &err), DP_ERR_ARG);
	dp_scan_params_default(&p);
	p.distance = 0.3; /* inside the bounding sphere */
	assert_int_equal(dp_scan(&m, &p, &pts, NULL, &err), DP_ERR_ARG);
	dp_scan_params_default(&p);
	p.up_axis = 3;
	assert_int_equal(dp_scan(&m, &p, &pts, NULL, &err), DP_ERR_ARG);
	dp_scan_params_default(&p);
	p.res = 100000;
	assert_int_equal(dp_scan(&m, &p, &pts, NULL, &err), DP_ERR_ARG);
	dp_scan_params_default(&p);
	dp_cloud points_only = m;
	points_only.faces = NULL;
	points_only.nfaces = 0;
	assert_int_equal(dp_scan(&points_only, &p, &pts, NULL, &err), DP_ERR_ARG);
	m.x[3] = NAN;
	assert_int_equal(dp_scan(&m, &p, &pts, NULL, &err), DP_ERR_FORMAT);
	assert_non_null(strstr(err.message, "scan"));
	dp_cloud_free(&m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_primitives),
		cmocka_unit_test(test_bvh_matches_brute_force),
		cmocka_unit_test(test_complete_scan_covers_sphere),
		cmocka_unit_test(test_one_view_covers_half),
		cmocka_unit_test(test_rays_in_mesh_planes),
		cmocka_unit_test(test_noise_level),
		cmocka_unit_test(test_views_normals_and_seed),
		cmocka_unit_test(test_up_axis),
		cmocka_unit_test(test_large_mesh_speed),
		cmocka_unit_test(test_bad_input),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
