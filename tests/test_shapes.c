/* Built-in shapes: closed, outward-wound meshes whose volume and vertices
 * match the analytic definitions, and distance functions with known answers. */
#include "testkit.h"

#include "tools/mesh.h"
#include "tools/shapes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *names[] = {"sphere", "cylinder", "slab", "torus", "knot", "chair", "rods"};
#define NNAMES (sizeof names / sizeof names[0])

static dp_shape shape_named(const char *name)
{
	dp_shape s;
	dp_error err = {0};
	if (dp_shape_default(name, &s, &err) != DP_OK)
		fail_msg("%s", err.message);
	return s;
}

static void make_mesh(const dp_shape *s, dp_cloud *m)
{
	dp_error err = {0};
	if (dp_shape_mesh(s, m, &err) != DP_OK)
		fail_msg("%s: %s", dp_shape_name(s->kind), err.message);
}

/* Smallest radius of curvature the triangulation has to follow (0: flat). */
static double curvature_radius(const dp_shape *s)
{
	switch (s->kind) {
	case DP_SHAPE_SPHERE:
	case DP_SHAPE_CYLINDER:
	case DP_SHAPE_CHAIR:
	case DP_SHAPE_RODS: return s->radius;
	case DP_SHAPE_TORUS:
	case DP_SHAPE_KNOT: return s->tube;
	case DP_SHAPE_SLAB: return 0;
	}
	return 0;
}

static int cmp_u64(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return (x > y) - (x < y);
}

static double edge_coord(const dp_cloud *m, uint32_t v, int k)
{
	return k == 0 ? m->x[v] : (k == 1 ? m->y[v] : m->z[v]);
}

/* How much of the edge a->b the edge c->d covers running the other way:
 * the length of their overlap when d->c lies on a->b's line (within `eps`),
 * else 0. */
static double reverse_overlap(const dp_cloud *m, uint32_t a, uint32_t b, uint32_t c, uint32_t d, double eps)
{
	double e[3], len2 = 0, t[2], off2[2] = {0, 0};
	for (int k = 0; k < 3; k++) {
		e[k] = edge_coord(m, b, k) - edge_coord(m, a, k);
		len2 += e[k] * e[k];
	}
	uint32_t ends[2] = {d, c};
	for (int q = 0; q < 2; q++) {
		double dot = 0;
		for (int k = 0; k < 3; k++)
			dot += (edge_coord(m, ends[q], k) - edge_coord(m, a, k)) * e[k];
		t[q] = dot / len2;
		for (int k = 0; k < 3; k++) {
			double off = edge_coord(m, ends[q], k) - edge_coord(m, a, k) - t[q] * e[k];
			off2[q] += off * off;
		}
	}
	if (off2[0] > eps * eps || off2[1] > eps * eps || t[1] <= t[0])
		return 0;
	return fmax(fmin(t[1], 1.0) - fmax(t[0], 0.0), 0.0) * sqrt(len2);
}

/* Closed and consistently oriented: every directed edge occurs once, and
 * its reverse occurs too (each edge borders exactly two faces that traverse
 * it in opposite directions), or, where pieces meet without sharing vertices
 * (the chair's), edges running the other way along its line cover it whole. */
static void assert_closed(const dp_cloud *m, const char *what)
{
	size_t ne = 3 * m->nfaces, open = 0;
	uint64_t *e = malloc(ne * sizeof *e), *loose = malloc(ne * sizeof *loose);
	assert_non_null(e);
	assert_non_null(loose);
	for (size_t f = 0; f < m->nfaces; f++)
		for (int k = 0; k < 3; k++) {
			uint64_t a = m->faces[3 * f + k], b = m->faces[3 * f + (k + 1) % 3];
			if (a == b)
				fail_msg("%s: face %zu repeats vertex %llu", what, f, (unsigned long long)a);
			e[3 * f + k] = a << 32 | b;
		}
	qsort(e, ne, sizeof *e, cmp_u64);
	for (size_t i = 0; i < ne; i++) {
		if (i + 1 < ne && e[i] == e[i + 1])
			fail_msg("%s: directed edge %llu->%llu used twice (inconsistent winding)", what,
				 (unsigned long long)(e[i] >> 32), (unsigned long long)(e[i] & 0xffffffffu));
		uint64_t rev = (e[i] & 0xffffffffu) << 32 | e[i] >> 32;
		if (!bsearch(&rev, e, ne, sizeof *e, cmp_u64))
			loose[open++] = e[i];
	}
	double lo[3], hi[3];
	dp_mesh_bbox(m, lo, hi);
	double eps = 1e-6 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
				 (hi[2] - lo[2]) * (hi[2] - lo[2]));
	for (size_t i = 0; i < open; i++) {
		uint32_t a = (uint32_t)(loose[i] >> 32), b = (uint32_t)loose[i];
		double covered = 0, len = 0;
		for (int k = 0; k < 3; k++)
			len += (edge_coord(m, b, k) - edge_coord(m, a, k)) * (edge_coord(m, b, k) - edge_coord(m, a, k));
		len = sqrt(len);
		for (size_t j = 0; j < open; j++)
			covered += reverse_overlap(m, a, b, (uint32_t)(loose[j] >> 32), (uint32_t)loose[j], eps);
		if (fabs(covered - len) > eps)
			fail_msg("%s: edge %u->%u (length %.6g) has %.6g of opposite edges along it (hole)", what, a, b,
				 len, covered);
	}
	free(loose);
	free(e);
}

static void test_meshes_closed_and_outward(void **state)
{
	(void)state;
	for (size_t i = 0; i < NNAMES; i++) {
		dp_shape s = shape_named(names[i]);
		dp_cloud m;
		make_mesh(&s, &m);
		assert_closed(&m, names[i]);
		for (size_t f = 0; f < m.nfaces; f++) {
			double n[3];
			if (!(dp_mesh_triangle_normal(&m, f, n) > 0))
				fail_msg("%s: face %zu is degenerate", names[i], f);
		}
		double v = dp_mesh_signed_volume(&m), exact = dp_shape_volume(&s);
		/* An inscribed polygon of n sides misses (2 pi/n)^2/6 of a disc's
		 * area; a surface curved in two directions misses about twice that.
		 * Allow three times it. */
		double step = 2.0 * M_PI / s.resolution;
		double tol = curvature_radius(&s) > 0 ? 0.5 * step * step : 1e-6;
		double rel = fabs(v - exact) / exact;
		printf("%-8s res %d: %zu vertices, %zu faces, volume %.6f (exact %.6f, rel. error %.2e)\n", names[i],
		       s.resolution, m.n, m.nfaces, v, exact, rel);
		assert_true(v > 0);
		if (rel > tol)
			fail_msg("%s: volume %.6f vs exact %.6f (rel %.3g > %.3g)", names[i], v, exact, rel, tol);
		dp_cloud_free(&m);
	}
	/* The chair's leg squares get corners of their own when no ray of the
	 * legs' angles meets them (a resolution not a multiple of 8). */
	dp_shape s = shape_named("chair");
	s.resolution = 13;
	dp_cloud m;
	make_mesh(&s, &m);
	assert_closed(&m, "chair at resolution 13");
	double rel = fabs(dp_mesh_signed_volume(&m) - dp_shape_volume(&s)) / dp_shape_volume(&s);
	double step = 2.0 * M_PI / s.resolution;
	printf("chair    res 13: volume rel. error %.2e\n", rel);
	assert_true(rel < 0.5 * step * step);
	dp_cloud_free(&m);
}

static void test_volume_converges(void **state)
{
	(void)state;
	for (size_t i = 0; i < NNAMES; i++) {
		dp_shape s = shape_named(names[i]);
		if (curvature_radius(&s) == 0)
			continue;
		double rel[2];
		for (int k = 0; k < 2; k++) {
			s.resolution = k ? 64 : 16;
			dp_cloud m;
			make_mesh(&s, &m);
			rel[k] = fabs(dp_mesh_signed_volume(&m) - dp_shape_volume(&s)) / dp_shape_volume(&s);
			dp_cloud_free(&m);
		}
		/* Second order: 4x the resolution should cut the error about 16x. */
		printf("%-8s volume error res 16 %.2e, res 64 %.2e\n", names[i], rel[0], rel[1]);
		if (!(rel[1] < rel[0] / 8))
			fail_msg("%s: volume error %.3g -> %.3g does not converge", names[i], rel[0], rel[1]);
	}
}

static void test_vertices_on_surface(void **state)
{
	(void)state;
	for (size_t i = 0; i < NNAMES; i++) {
		dp_shape s = shape_named(names[i]);
		dp_cloud m;
		make_mesh(&s, &m);
		double worst = 0;
		for (size_t v = 0; v < m.n; v++) {
			double p[3] = {m.x[v], m.y[v], m.z[v]};
			worst = fmax(worst, dp_shape_surface_distance(&s, p));
		}
		/* Vertices are exact up to float rounding of coordinates of order 1. */
		if (worst > 1e-6)
			fail_msg("%s: a vertex lies %.3g off the analytic surface", names[i], worst);
		dp_cloud_free(&m);
	}
}

/* Where the chair's parts touch: the leg tops against the seat's underside
 * and the back's underside against the seat's top. Those places are inside
 * the solid, so no face of its boundary lies there. */
static int chair_contact(const dp_shape *s, const double p[3])
{
	const double eps = 1e-6;
	double leg = 0.5 * s->width - DP_CHAIR_LEG_INSET * s->radius;
	if (fabs(p[2] - s->length) < eps)
		/* the legs' polygons lie inside their circles: inside the polygon's
		 * inner radius, whatever the angle */
		return hypot(fabs(p[0]) - leg, fabs(p[1]) - leg) < s->radius * cos(M_PI / s->resolution) - eps;
	if (fabs(p[2] - (s->length + s->thickness)) < eps)
		return p[1] > 0.5 * s->width - s->thickness + eps;
	return 0;
}

/* The area of the chair's boundary: both parts' boxes and the legs, less
 * both faces of each contact (the strip under the back, the legs' discs). */
static double chair_area(const dp_shape *s)
{
	double w = s->width, t = s->thickness, h = s->height, r = s->radius;
	double seat = 2 * w * w + 4 * w * t, back = 2 * w * h + 2 * t * h + 2 * w * t;
	double legs = 4 * (2 * M_PI * r * s->length + 2 * M_PI * r * r);
	return seat + back + legs - 2 * w * t - 8 * M_PI * r * r;
}

/* Samples of the faces stay within the chord sag of the analytic surface
 * and their normals point outwards (never towards the skeleton). */
static void test_samples_near_surface_and_outward(void **state)
{
	(void)state;
	for (size_t i = 0; i < NNAMES; i++) {
		dp_shape s = shape_named(names[i]);
		dp_cloud m, pts;
		dp_error err = {0};
		make_mesh(&s, &m);
		assert_int_equal(dp_mesh_sample(&m, 5000, 0.0, 7, &pts, &err), DP_OK);
		double r = curvature_radius(&s);
		/* A flat triangle inscribed in a sphere of radius r with angular
		 * circumradius a is at most r (1 - cos a) ~ r a^2 / 2 from it; the
		 * faces here have a <= (sqrt 2 / 2) 2 pi / res. */
		double sag = r * M_PI * M_PI / (s.resolution * s.resolution) + 1e-6;
		double worst = 0, delta = 1e-3 * (r > 0 ? r : s.thickness);
		size_t inward = 0, contact = 0;
		for (size_t k = 0; k < pts.n; k++) {
			double p[3] = {pts.x[k], pts.y[k], pts.z[k]};
			worst = fmax(worst, dp_shape_surface_distance(&s, p));
			if (s.kind == DP_SHAPE_CHAIR && chair_contact(&s, p)) {
				contact++;
				continue;
			}
			double q[3] = {p[0] + delta * pts.nx[k], p[1] + delta * pts.ny[k], p[2] + delta * pts.nz[k]};
			inward += dp_shape_skeleton_distance(&s, q) < dp_shape_skeleton_distance(&s, p);
		}
		printf("%-8s samples: max distance to surface %.3g (bound %.3g), %zu of %zu move towards the "
		       "skeleton along the normal, %zu on contact faces\n", names[i], worst, sag, inward, pts.n,
		       contact);
		if (worst > sag)
			fail_msg("%s: a sample lies %.3g off the surface (bound %.3g)", names[i], worst, sag);
		assert_int_equal(inward, 0);
		if (s.kind == DP_SHAPE_CHAIR) {
			/* The contacts' faces would add 2 W T + 8 pi r^2, 4% of the
			 * area; the legs' polygons miss (2 pi / res)^2 / 6 of their
			 * discs and sides. */
			double area = dp_mesh_area(&m), exact = chair_area(&s);
			double step = 2.0 * M_PI / s.resolution;
			printf("chair area %.6f (boundary %.6f)\n", area, exact);
			assert_true(fabs(area - exact) / exact < step * step / 6);
			assert_int_equal(contact, 0);
		}
		dp_cloud_free(&pts);
		dp_cloud_free(&m);
	}
}

static void test_sampling_by_area_and_seeded(void **state)
{
	(void)state;
	dp_shape s = shape_named("slab");
	dp_cloud m, a, b;
	dp_error err = {0};
	make_mesh(&s, &m);
	const size_t n = 20000;
	assert_int_equal(dp_mesh_sample(&m, n, 0.0, 3, &a, &err), DP_OK);
	assert_int_equal(dp_mesh_sample(&m, n, 0.0, 3, &b, &err), DP_OK);
	assert_memory_equal(a.x, b.x, n * sizeof(float));
	assert_memory_equal(a.nz, b.nz, n * sizeof(float));
	size_t top = 0;
	for (size_t i = 0; i < n; i++) {
		double len = sqrt(a.nx[i] * a.nx[i] + a.ny[i] * a.ny[i] + a.nz[i] * a.nz[i]);
		assert_true(fabs(len - 1.0) < 1e-5);
		top += a.nz[i] > 0.5f;
	}
	double w = s.width, t = s.thickness, p = w * w / (2 * w * w + 4 * w * t);
	double se = sqrt(p * (1 - p) / n), frac = (double)top / n;
	printf("slab top-face fraction %.4f, area fraction %.4f (sd %.4f)\n", frac, p, se);
	assert_true(fabs(frac - p) < 4 * se);
	dp_cloud_free(&a);
	dp_cloud_free(&b);
	dp_cloud_free(&m);

	/* Noise is a fraction of the bbox diagonal per coordinate: on a sphere
	 * its normal component is the distance to the surface. */
	dp_shape sp = shape_named("sphere");
	make_mesh(&sp, &m);
	double sigma = 0.01, diag = dp_mesh_diagonal(&m), sum2 = 0;
	assert_int_equal(dp_mesh_sample(&m, n, sigma, 3, &a, &err), DP_OK);
	for (size_t i = 0; i < n; i++) {
		double q[3] = {a.x[i], a.y[i], a.z[i]}, d = dp_shape_surface_distance(&sp, q);
		sum2 += d * d;
	}
	double measured = sqrt(sum2 / n) / diag;
	printf("sample noise: requested %.4f, measured %.4f diagonals\n", sigma, measured);
	assert_true(fabs(measured - sigma) < 0.03 * sigma);
	dp_cloud_free(&a);
	dp_cloud_free(&m);
}

static void test_distance_known_answers(void **state)
{
	(void)state;
	dp_shape sp = shape_named("sphere"), cy = shape_named("cylinder"), sl = shape_named("slab");
	dp_shape to = shape_named("torus"), ch = shape_named("chair");
	const double tol = 1e-12;
	double p1[3] = {2, 0, 0}, p2[3] = {0.5, 0, 0};
	assert_true(fabs(dp_shape_surface_distance(&sp, p1) - 1.0) < tol);
	assert_true(fabs(dp_shape_surface_distance(&sp, p2) - 0.5) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&sp, p2) - 0.5) < tol);
	/* Cylinder R 0.25, L 2: beyond the cap, beside the side, inside. */
	double c1[3] = {0, 0, 2}, c2[3] = {1, 0, 0}, c3[3] = {0.1, 0, 0}, c4[3] = {0.1, 0, 1.5}, c5[3] = {0.75, 0, 1.5};
	assert_true(fabs(dp_shape_surface_distance(&cy, c1) - 1.0) < tol);
	assert_true(fabs(dp_shape_surface_distance(&cy, c2) - 0.75) < tol);
	assert_true(fabs(dp_shape_surface_distance(&cy, c3) - 0.15) < tol);
	assert_true(fabs(dp_shape_surface_distance(&cy, c5) - hypot(0.5, 0.5)) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&cy, c3) - 0.1) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&cy, c4) - hypot(0.1, 0.5)) < tol);
	/* Slab W 2, T 0.2. */
	double s1[3] = {0, 0, 1}, s2[3] = {0.5, 0.5, 0.05}, s3[3] = {1.5, 0, 0};
	assert_true(fabs(dp_shape_surface_distance(&sl, s1) - 0.9) < tol);
	assert_true(fabs(dp_shape_surface_distance(&sl, s2) - 0.05) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&sl, s2) - 0.05) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&sl, s3) - 0.5) < tol);
	/* Torus R 1, rho 0.3. */
	double t1[3] = {0, 0, 0}, t2[3] = {1, 0, 0}, t3[3] = {0, 1, 0.2};
	assert_true(fabs(dp_shape_surface_distance(&to, t1) - 0.7) < tol);
	assert_true(fabs(dp_shape_surface_distance(&to, t2) - 0.3) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&to, t3) - 0.2) < tol);
	assert_true(fabs(dp_shape_skeleton_distance(&to, t1) - 1.0) < tol);
	/* Chair: under the seat's centre the seat's mid-plane is nearer than
	 * any leg axis; on a leg axis the skeleton distance is 0. */
	double seat_mid = ch.length + 0.5 * ch.thickness, leg = 0.5 * ch.width - 1.5 * ch.radius;
	double h1[3] = {0, 0, 0.5}, h2[3] = {leg, leg, 0.3}, h3[3] = {leg + 2 * ch.radius, leg, 0.3};
	assert_true(fabs(dp_shape_skeleton_distance(&ch, h1) - (seat_mid - 0.5)) < tol);
	assert_true(dp_shape_skeleton_distance(&ch, h2) < tol);
	assert_true(fabs(dp_shape_surface_distance(&ch, h3) - ch.radius) < tol);
	assert_true(fabs(dp_shape_surface_distance(&ch, h1) - (ch.length - 0.5)) < tol);
	/* Where the parts touch, inside the solid: on the seat's top under the
	 * middle of the back (half the back's thickness from its front and
	 * rear), and at a leg's top (a radius from its side and the rim of its
	 * disc on the seat's underside). */
	double top = ch.length + ch.thickness;
	double h4[3] = {0, 0.5 * ch.width - 0.5 * ch.thickness, top}, h5[3] = {leg, leg, ch.length};
	assert_true(fabs(dp_shape_surface_distance(&ch, h4) - 0.5 * ch.thickness) < tol);
	assert_true(fabs(dp_shape_surface_distance(&ch, h5) - ch.radius) < tol);
}

/* Offsets from the knot's core along a normal direction are measured exactly
 * by the skeleton distance, for offsets below the tube radius. */
static void test_knot_core(void **state)
{
	(void)state;
	dp_shape k = shape_named("knot");
	dp_cloud core;
	dp_error err = {0};
	assert_int_equal(dp_shape_core_curve(&k, 300, &core, &err), DP_OK);
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	double worst_on = 0, worst_off = 0;
	for (size_t i = 0; i < core.n; i++) {
		size_t j = (i + 1) % core.n, h = (i + core.n - 1) % core.n;
		double p[3] = {core.x[i], core.y[i], core.z[i]};
		double t[3] = {core.x[j] - core.x[h], core.y[j] - core.y[h], core.z[j] - core.z[h]};
		worst_on = fmax(worst_on, dp_shape_skeleton_distance(&k, p));
		/* A direction across the (central-difference) tangent. */
		double r[3] = {dp_rng_normal(&rng), dp_rng_normal(&rng), dp_rng_normal(&rng)};
		double tt = t[0] * t[0] + t[1] * t[1] + t[2] * t[2], rt = r[0] * t[0] + r[1] * t[1] + r[2] * t[2];
		for (int d = 0; d < 3; d++)
			r[d] -= rt / tt * t[d];
		double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]), off = 0.5 * k.tube;
		double q[3] = {p[0] + off * r[0] / rl, p[1] + off * r[1] / rl, p[2] + off * r[2] / rl};
		worst_off = fmax(worst_off, fabs(dp_shape_skeleton_distance(&k, q) - off));
		worst_off = fmax(worst_off, fabs(dp_shape_surface_distance(&k, q) - (k.tube - off)));
	}
	printf("knot: core samples %.3g from the core, offsets measured to %.3g\n", worst_on, worst_off);
	/* Float sample coordinates; the central-difference tangent is off by
	 * (h^2 kappa^2 / 6), which tilts the offset direction slightly. */
	assert_true(worst_on < 1e-6);
	assert_true(worst_off < 1e-4 * k.tube);
	dp_cloud_free(&core);

	dp_shape cy = shape_named("cylinder"), to = shape_named("torus");
	assert_int_equal(dp_shape_core_curve(&cy, 11, &core, &err), DP_OK);
	assert_true(fabs(core.z[0] + 0.5 * cy.length) < 1e-6 && fabs(core.z[10] - 0.5 * cy.length) < 1e-6);
	dp_cloud_free(&core);
	assert_int_equal(dp_shape_core_curve(&to, 64, &core, &err), DP_OK);
	for (size_t i = 0; i < core.n; i++) {
		double p[3] = {core.x[i], core.y[i], core.z[i]};
		assert_true(dp_shape_skeleton_distance(&to, p) < 1e-6);
	}
	dp_cloud_free(&core);
}

static void test_bad_input(void **state)
{
	(void)state;
	dp_shape s;
	dp_cloud m;
	dp_error err = {0};
	assert_int_equal(dp_shape_default("teapot", &s, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "teapot"));
	s = shape_named("torus");
	s.tube = 1.5; /* thicker than the core radius */
	assert_int_equal(dp_shape_mesh(&s, &m, &err), DP_ERR_ARG);
	assert_true(isnan(dp_shape_volume(&s)));
	s = shape_named("sphere");
	s.resolution = 2;
	assert_int_equal(dp_shape_mesh(&s, &m, &err), DP_ERR_ARG);
	s.resolution = 48;
	s.radius = NAN;
	assert_int_equal(dp_shape_mesh(&s, &m, &err), DP_ERR_ARG);
	s = shape_named("knot");
	s.tube = s.radius; /* would intersect itself */
	assert_int_equal(dp_shape_mesh(&s, &m, &err), DP_ERR_ARG);
	s = shape_named("sphere");
	assert_int_equal(dp_shape_core_curve(&s, 10, &m, &err), DP_ERR_ARG);
	s = shape_named("sphere");
	make_mesh(&s, &m);
	dp_cloud pts;
	assert_int_equal(dp_mesh_sample(&m, 0, 0.0, 1, &pts, &err), DP_ERR_ARG);
	assert_int_equal(dp_mesh_sample(&m, 10, -1.0, 1, &pts, &err), DP_ERR_ARG);
	m.faces[4] = (uint32_t)m.n; /* out of range */
	assert_int_equal(dp_mesh_sample(&m, 10, 0.0, 1, &pts, &err), DP_ERR_FORMAT);
	dp_cloud_free(&m);
	for (size_t i = 0; i < NNAMES; i++) {
		assert_int_equal(dp_shape_default(names[i], &s, &err), DP_OK);
		assert_string_equal(dp_shape_name(s.kind), names[i]);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_meshes_closed_and_outward),
		cmocka_unit_test(test_volume_converges),
		cmocka_unit_test(test_vertices_on_surface),
		cmocka_unit_test(test_samples_near_surface_and_outward),
		cmocka_unit_test(test_sampling_by_area_and_seeded),
		cmocka_unit_test(test_distance_known_answers),
		cmocka_unit_test(test_knot_core),
		cmocka_unit_test(test_bad_input),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
