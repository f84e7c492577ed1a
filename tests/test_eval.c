/* Evaluation metrics against ground truth, on inputs with known answers. */
#include "testkit.h"

#include "tools/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void sphere_mesh(dp_shape *s, dp_cloud *m)
{
	dp_error err = {0};
	assert_int_equal(dp_shape_default("sphere", s, &err), DP_OK);
	if (dp_shape_mesh(s, m, &err) != DP_OK)
		fail_msg("%s", err.message);
}

static void sample(const dp_cloud *m, size_t n, dp_cloud *out)
{
	dp_error err = {0};
	if (dp_mesh_sample(m, n, 0.0, 42, out, &err) != DP_OK)
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

/* A square [-1, 1]^2 in the plane z = 0, as two triangles. */
static void square_mesh(dp_cloud *m)
{
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(m, 4, 0, &err), DP_OK);
	const float x[4] = {-1, 1, 1, -1}, y[4] = {-1, -1, 1, 1};
	for (int i = 0; i < 4; i++) {
		m->x[i] = x[i];
		m->y[i] = y[i];
		m->z[i] = 0;
	}
	m->faces = malloc(6 * sizeof(uint32_t));
	assert_non_null(m->faces);
	const uint32_t f[6] = {0, 1, 2, 0, 2, 3};
	memcpy(m->faces, f, sizeof f);
	m->nfaces = 2;
}

static void test_exact_samples(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	sphere_mesh(&s, &m);
	sample(&m, 30000, &pts);
	dp_eval_result r = evaluate(&m, &pts);
	printf("exact samples: accuracy max %.3g, coverage %.4f, completeness %.3g, spacing cv %.3f\n",
	       r.accuracy_max, r.coverage, r.completeness_mean, r.spacing_cv);
	assert_true(r.accuracy_max < 1e-6);
	/* Random points form a Poisson process of density L: the nearest point
	 * is beyond r with probability exp(-L pi r^2), and the mean spacing is
	 * 1/(2 sqrt L); with r = 1.5 spacing, exp(-pi 1.5^2 / 4) is uncovered. */
	double expect = 1.0 - exp(-M_PI * 1.5 * 1.5 / 4.0);
	printf("Poisson coverage expected %.4f\n", expect);
	assert_true(fabs(r.coverage - expect) < 0.01);
	assert_true(fabs(r.spacing_cv - sqrt(4.0 / M_PI - 1.0)) < 0.02);
	assert_true(r.normal_angle_deg < 1e-3 && r.normal_flipped == 0 && r.normal_flipped_clear == 0);
	assert_int_equal(r.normals_used, pts.n);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

/* Outward offsets d along the face normal of a convex mesh are exactly d
 * from it: the face stays the nearest. */
static void test_shifted_points(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	sphere_mesh(&s, &m);
	sample(&m, 5000, &pts);
	double diag = dp_mesh_diagonal(&m);
	const double shifts[2] = {0.01, 0.002};
	for (int k = 0; k < 2; k++) {
		double d = shifts[k] * diag;
		dp_cloud moved;
		dp_error err = {0};
		assert_int_equal(dp_cloud_copy(&moved, &pts, &err), DP_OK);
		for (size_t i = 0; i < moved.n; i++) {
			moved.x[i] += (float)(d * moved.nx[i]);
			moved.y[i] += (float)(d * moved.ny[i]);
			moved.z[i] += (float)(d * moved.nz[i]);
		}
		dp_eval_result r = evaluate(&m, &moved);
		printf("shift %.4f: accuracy mean %.6f p95 %.6f max %.6f\n", shifts[k], r.accuracy_mean, r.accuracy_p95,
		       r.accuracy_max);
		/* float coordinates of order 1 round at 1e-7. */
		assert_true(fabs(r.accuracy_mean - shifts[k]) < 1e-6);
		assert_true(fabs(r.accuracy_p95 - shifts[k]) < 1e-6);
		assert_true(fabs(r.accuracy_max - shifts[k]) < 1e-6);
		assert_true(fabs(r.accuracy_rms - shifts[k]) < 1e-6);
		dp_cloud_free(&moved);
	}
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

/* Evenly spread points (a Fibonacci lattice on the sphere), like a
 * consolidated surface: nearest-neighbour spacing nearly constant. */
static void test_half_sphere(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, half;
	dp_error err = {0};
	sphere_mesh(&s, &m);
	const size_t total = 24000;
	assert_int_equal(dp_cloud_alloc(&half, total / 2, 0, &err), DP_OK);
	for (size_t i = 0; i < total / 2; i++) {
		double z = 1.0 - (2.0 * i + 1.0) / total, rho = sqrt(1.0 - z * z), a = i * M_PI * (3.0 - sqrt(5.0));
		half.x[i] = (float)(s.radius * rho * cos(a));
		half.y[i] = (float)(s.radius * rho * sin(a));
		half.z[i] = (float)(s.radius * z);
	}
	dp_eval_result r = evaluate(&m, &half);
	/* A south-hemisphere sample at angle a below the equator is the chord
	 * 2R sin(a/2) from the nearest north point; averaged over the south
	 * half's area (weight cos a) that is R [2 cos(a/2) - 2/3 cos(3a/2)]
	 * from 0 to pi/2 = 0.5523 R. The lattice's own spacing adds a few
	 * percent (samples between points, and beside the equator row). */
	double south = (2.0 / 3.0 * cos(3.0 * M_PI / 4.0) * -1.0 + 2.0 * cos(M_PI / 4.0)) - (2.0 - 2.0 / 3.0);
	double expect = 0.5 * south * s.radius / dp_mesh_diagonal(&m);
	printf("half sphere: %zu points, coverage %.4f, completeness %.5f (expect %.5f), normals %s\n", half.n,
	       r.coverage, r.completeness_mean, expect, r.has_normals ? "yes" : "no");
	/* Half, plus a band one coverage radius wide past the equator. */
	assert_true(r.spacing_cv < 0.2);
	assert_true(r.coverage > 0.5 && r.coverage < 0.5 + r.coverage_radius * dp_mesh_diagonal(&m) / s.radius);
	assert_true(fabs(r.completeness_mean - expect) < 0.05 * expect);
	assert_int_equal(r.has_normals, 0);
	FILE *f = tmpfile();
	assert_non_null(f);
	dp_eval_json(&r, f);
	char line[2048] = {0};
	rewind(f);
	assert_non_null(fgets(line, sizeof line, f));
	fclose(f);
	assert_true(line[0] == '{' && strcmp(line + strlen(line) - 2, "}\n") == 0);
	assert_non_null(strstr(line, "\"normal_angle_deg\": null"));
	const char *cov = strstr(line, "\"coverage\": ");
	assert_non_null(cov);
	assert_true(fabs(strtod(cov + strlen("\"coverage\": "), NULL) - r.coverage) < 1e-8);
	dp_cloud_free(&half);
	dp_cloud_free(&m);
}

/* Rotates every normal by `deg` about an axis across it. */
static void rotate_normals(dp_cloud *c, double deg)
{
	double a = deg * M_PI / 180.0, ca = cos(a), sa = sin(a);
	for (size_t i = 0; i < c->n; i++) {
		double n[3] = {c->nx[i], c->ny[i], c->nz[i]};
		/* A unit tangent: n x (the axis n leans least on). */
		double e[3] = {0, 0, 0};
		int k = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2) : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
		e[k] = 1;
		double t[3] = {n[1] * e[2] - n[2] * e[1], n[2] * e[0] - n[0] * e[2], n[0] * e[1] - n[1] * e[0]};
		double tl = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
		c->nx[i] = (float)(ca * n[0] + sa * t[0] / tl);
		c->ny[i] = (float)(ca * n[1] + sa * t[1] / tl);
		c->nz[i] = (float)(ca * n[2] + sa * t[2] / tl);
	}
}

static void test_normals(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts, work;
	dp_error err = {0};
	sphere_mesh(&s, &m);
	sample(&m, 8000, &pts);
	/* Every 4th flipped: a quarter flipped, no angle error ignoring sign. */
	assert_int_equal(dp_cloud_copy(&work, &pts, &err), DP_OK);
	for (size_t i = 0; i < work.n; i += 4) {
		work.nx[i] = -work.nx[i];
		work.ny[i] = -work.ny[i];
		work.nz[i] = -work.nz[i];
	}
	dp_eval_result r = evaluate(&m, &work);
	printf("quarter flipped: flipped %.4f, angle %.4f deg\n", r.normal_flipped, r.normal_angle_deg);
	assert_true(fabs(r.normal_flipped - 0.25) < 1e-9);
	/* nothing on a sphere faces inwards: every flip is clear */
	assert_true(fabs(r.normal_flipped_clear - 0.25) < 1e-9);
	assert_true(r.normal_angle_deg < 1e-3);
	dp_cloud_free(&work);
	/* Tilted by 10 degrees, and by 120 (= 60 ignoring sign, all flipped). */
	const double tilt[2] = {10, 120}, unsigned_angle[2] = {10, 60}, flipped[2] = {0, 1};
	for (int k = 0; k < 2; k++) {
		assert_int_equal(dp_cloud_copy(&work, &pts, &err), DP_OK);
		rotate_normals(&work, tilt[k]);
		r = evaluate(&m, &work);
		printf("tilted %.0f deg: angle %.4f, flipped %.4f\n", tilt[k], r.normal_angle_deg, r.normal_flipped);
		assert_true(fabs(r.normal_angle_deg - unsigned_angle[k]) < 1e-3);
		assert_true(fabs(r.normal_flipped - flipped[k]) < 1e-9);
		assert_true(fabs(r.normal_flipped_clear - flipped[k]) < 1e-9);
		dp_cloud_free(&work);
	}
	/* Zero normals are left out of the normal metrics. */
	assert_int_equal(dp_cloud_copy(&work, &pts, &err), DP_OK);
	work.nx[0] = work.ny[0] = work.nz[0] = 0;
	r = evaluate(&m, &work);
	assert_int_equal(r.normals_used, work.n - 1);
	dp_cloud_free(&work);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

/* A grid of points spacing g apart a quarter of the way through a slab of
 * thickness T, normals up: the bottom face is nearest (T/4 below), so every
 * normal is flipped, while the top face lies 3T/4 above. Within the nearest
 * distance plus g/2 it is reached when g > T: the grid is too coarse to tell
 * the faces apart and no flip is clear; at g < T every one is. At 1.25 T and
 * 0.75 T the answers turn if the reach leaves out the distance (0.625 T) or
 * takes the whole spacing (T). */
static void test_flipped_clear(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	dp_error err = {0};
	assert_int_equal(dp_shape_default("slab", &s, &err), DP_OK);
	s.width = 2.0;
	s.thickness = 0.05;
	if (dp_shape_mesh(&s, &m, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double spacing[2] = {1.25 * s.thickness, 0.75 * s.thickness}, clear[2] = {0.0, 1.0};
	for (int k = 0; k < 2; k++) {
		int g = (int)lround(1.2 / spacing[k]) + 1;
		assert_int_equal(dp_cloud_alloc(&pts, (size_t)g * (size_t)g, 1, &err), DP_OK);
		for (int i = 0; i < g; i++)
			for (int j = 0; j < g; j++) {
				size_t p = (size_t)i * (size_t)g + (size_t)j;
				pts.x[p] = (float)(-0.6 + i * spacing[k]);
				pts.y[p] = (float)(-0.6 + j * spacing[k]);
				pts.z[p] = (float)(-0.25 * s.thickness);
				pts.nx[p] = pts.ny[p] = 0.0f;
				pts.nz[p] = 1.0f;
			}
		dp_eval_result r = evaluate(&m, &pts);
		printf("slab %.3f thick, points %.4f apart: flipped %.4f, clear %.4f\n", s.thickness, spacing[k],
		       r.normal_flipped, r.normal_flipped_clear);
		assert_true(r.normal_flipped == 1.0);
		assert_true(r.normal_flipped_clear == clear[k]);
		dp_cloud_free(&pts);
	}
	dp_cloud_free(&m);
}

/* A g x g grid over [-1, 1]^2 in the plane z = 0, spacing 2 / (g - 1), with
 * Gaussian noise of `noise` spacings across it (none: 0, and rng unused). */
static void plane_grid(int g, double noise, dp_rng *rng, dp_cloud *pts)
{
	dp_error err = {0};
	double h = 2.0 / (g - 1);
	assert_int_equal(dp_cloud_alloc(pts, (size_t)g * g, 0, &err), DP_OK);
	for (int i = 0; i < g; i++)
		for (int j = 0; j < g; j++) {
			pts->x[i * g + j] = (float)(-1 + i * h);
			pts->y[i * g + j] = (float)(-1 + j * h);
			pts->z[i * g + j] = noise > 0.0 ? (float)(noise * h * dp_rng_normal(rng)) : 0.0f;
		}
}

static void test_spacing(void **state)
{
	(void)state;
	dp_cloud m, pts;
	dp_error err = {0};
	square_mesh(&m);
	double diag = dp_mesh_diagonal(&m);
	/* A regular grid: every nearest neighbour is h away, every sample of the
	 * square lies in a cell, 0.3826 h from its nearest corner on average
	 * ((sqrt 2 + ln(1 + sqrt 2)) / 6 h). */
	const int g = 101;
	double h = 2.0 / (g - 1);
	plane_grid(g, 0.0, NULL, &pts);
	dp_eval_result r = evaluate(&m, &pts);
	double corner = (sqrt(2.0) + log(1.0 + sqrt(2.0))) / 6.0;
	printf("grid: spacing %.6f (h %.6f), cv %.2e, coverage %.4f, completeness %.6f (expect %.6f)\n",
	       r.spacing_mean, h / diag, r.spacing_cv, r.coverage, r.completeness_mean, corner * h / diag);
	assert_true(fabs(r.spacing_mean - h / diag) < 1e-5 * h / diag);
	assert_true(r.spacing_cv < 1e-4);
	assert_true(r.coverage == 1.0);
	assert_true(fabs(r.completeness_mean - corner * h / diag) < 0.02 * corner * h / diag);
	dp_cloud_free(&pts);
	/* Uniform random points: nearest-neighbour distances of a Poisson
	 * process are Rayleigh, mean 1/(2 sqrt(density)), CV sqrt(4/pi - 1). */
	const size_t n = 20000;
	assert_int_equal(dp_cloud_alloc(&pts, n, 0, &err), DP_OK);
	dp_rng rng;
	dp_rng_seed(&rng, 9);
	for (size_t i = 0; i < n; i++) {
		pts.x[i] = (float)(2 * dp_rng_uniform(&rng) - 1);
		pts.y[i] = (float)(2 * dp_rng_uniform(&rng) - 1);
		pts.z[i] = 0;
	}
	r = evaluate(&m, &pts);
	double mean = 0.5 / sqrt(n / 4.0) / diag, cv = sqrt(4.0 / M_PI - 1.0);
	printf("random: spacing %.6f (expect %.6f), cv %.4f (expect %.4f)\n", r.spacing_mean, mean, r.spacing_cv, cv);
	/* Points near the border lack neighbours on one side: a few percent. */
	assert_true(fabs(r.spacing_mean - mean) < 0.03 * mean);
	assert_true(fabs(r.spacing_cv - cv) < 0.03);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

/* The scatter of a point set off a surface. By hand first: a 4 x 4 grid of
 * unit spacing whose heights alternate +-t like a chessboard has covariance
 * diag(1.25, 1.25, t^2), and with one more point far away every grid point's
 * 15 nearest are the rest of the grid, so 16 of the 17 read t / sqrt(1.25)
 * (17 points or 15 would not, nor would a mean with the far point's own).
 * Then none on a plane, in proportion to the noise on a noisy plane (the 15
 * nearest of a grid point spread about 1.5 h along it), little on samples of
 * the built-in sphere's mesh (its facets and its curvature), and a random
 * cloud filling a cube near 0.590 (measured independently over 20000
 * points; 0.589 with the point left out, 0.603 with 16 neighbours). */
static void test_scatter(void **state)
{
	(void)state;
	dp_cloud m, pts;
	dp_error err = {0};
	square_mesh(&m);
	const double t = 0.5;
	assert_int_equal(dp_cloud_alloc(&pts, 17, 0, &err), DP_OK);
	for (int i = 0; i < 16; i++) {
		pts.x[i] = (float)(i % 4);
		pts.y[i] = (float)(i / 4);
		pts.z[i] = (float)((i % 4 + i / 4) % 2 ? -t : t);
	}
	pts.x[16] = pts.y[16] = 0.0f, pts.z[16] = 100.0f;
	double chess = evaluate(&m, &pts).scatter_median;
	printf("chessboard: scatter %.6f (expect %.6f)\n", chess, t / sqrt(1.25));
	assert_true(fabs(chess - t / sqrt(1.25)) < 1e-5);
	dp_cloud_free(&pts);
	double got[3];
	const double noise[3] = {0.0, 0.1, 0.2};
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	for (int k = 0; k < 3; k++) {
		plane_grid(101, noise[k], &rng, &pts);
		got[k] = evaluate(&m, &pts).scatter_median;
		printf("plane with noise %.1f h: scatter %.4f\n", noise[k], got[k]);
		dp_cloud_free(&pts);
	}
	assert_true(got[0] < 1e-6);
	assert_true(got[1] > 0.05 && got[1] < 0.09);
	assert_true(fabs(got[2] / got[1] - 2.0) < 0.2);
	/* More points than the median is read at: the same noise reads the
	 * same from the points chosen */
	const int big = 401;
	plane_grid(big, noise[1], &rng, &pts);
	double chosen = evaluate(&m, &pts).scatter_median;
	printf("plane of %d points with noise %.1f h: scatter %.4f\n", big * big, noise[1], chosen);
	assert_true(fabs(chosen - got[1]) < 0.003);
	dp_cloud_free(&pts);
	const size_t n = 20000;
	assert_int_equal(dp_cloud_alloc(&pts, n, 0, &err), DP_OK);
	for (size_t i = 0; i < n; i++) {
		pts.x[i] = (float)(2 * dp_rng_uniform(&rng) - 1);
		pts.y[i] = (float)(2 * dp_rng_uniform(&rng) - 1);
		pts.z[i] = (float)(2 * dp_rng_uniform(&rng) - 1);
	}
	double cloud = evaluate(&m, &pts).scatter_median;
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
	dp_shape s;
	sphere_mesh(&s, &m);
	sample(&m, n, &pts);
	double sphere = evaluate(&m, &pts).scatter_median;
	printf("random cube: scatter %.4f; sphere samples: %.4f\n", cloud, sphere);
	assert_true(fabs(cloud - 0.590) < 0.008);
	assert_true(sphere < 0.03);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

static void test_bad_input(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m, pts;
	dp_error err = {0};
	dp_eval_result r;
	sphere_mesh(&s, &m);
	sample(&m, 100, &pts);
	dp_eval_params p;
	dp_eval_params_default(&p);
	p.samples = 0;
	assert_int_equal(dp_eval(&m, &pts, &p, &r, &err), DP_ERR_ARG);
	dp_eval_params_default(&p);
	p.coverage_factor = -1;
	assert_int_equal(dp_eval(&m, &pts, &p, &r, &err), DP_ERR_ARG);
	dp_cloud one = pts;
	one.n = 1;
	assert_int_equal(dp_eval(&m, &one, NULL, &r, &err), DP_ERR_EMPTY);
	pts.y[7] = INFINITY;
	assert_int_equal(dp_eval(&m, &pts, NULL, &r, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "eval"));
	pts.y[7] = 0;
	dp_cloud no_faces = m;
	no_faces.nfaces = 0;
	assert_int_equal(dp_eval(&no_faces, &pts, NULL, &r, &err), DP_ERR_ARG);
	m.faces[0] = 1u << 30;
	assert_int_equal(dp_eval(&m, &pts, NULL, &r, &err), DP_ERR_FORMAT);
	dp_cloud_free(&pts);
	dp_cloud_free(&m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_exact_samples),
		cmocka_unit_test(test_shifted_points),
		cmocka_unit_test(test_half_sphere),
		cmocka_unit_test(test_normals),
		cmocka_unit_test(test_flipped_clear),
		cmocka_unit_test(test_spacing),
		cmocka_unit_test(test_scatter),
		cmocka_unit_test(test_bad_input),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
