/* dp_estimate_normals: PCA accuracy and consistent outward orientation on noisy
 * analytic shapes (closed, non-convex, open, several components), viewpoint
 * orientation, and tiny or degenerate inputs. */
#include "testkit.h"

#include "stages/orient.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Noise of the generated shapes: Gaussian per coordinate, this fraction of the
 * tube radius (or of the radius of spheres), as the brief asks (1–2%). */
#define NOISE_FRACTION 0.015
/* Acceptance thresholds from issue 2. */
#define MIN_OUTWARD 0.99
#define MAX_MEAN_ANGLE_DEG 10.0

/* A generated cloud with the exact outward normal of each point's noise-free
 * position. */
typedef struct sample {
	dp_cloud cloud;
	float *tx, *ty, *tz;
} sample;

static void sample_alloc(sample *s, size_t n)
{
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(&s->cloud, n, 0, &err), DP_OK);
	s->tx = malloc(n * sizeof *s->tx);
	s->ty = malloc(n * sizeof *s->ty);
	s->tz = malloc(n * sizeof *s->tz);
	assert_non_null(s->tx);
	assert_non_null(s->ty);
	assert_non_null(s->tz);
}

static void sample_free(sample *s)
{
	dp_cloud_free(&s->cloud);
	free(s->tx);
	free(s->ty);
	free(s->tz);
}

static void put(sample *s, size_t i, const double p[3], const double nrm[3], double sigma, dp_rng *rng)
{
	s->cloud.x[i] = (float)(p[0] + sigma * dp_rng_normal(rng));
	s->cloud.y[i] = (float)(p[1] + sigma * dp_rng_normal(rng));
	s->cloud.z[i] = (float)(p[2] + sigma * dp_rng_normal(rng));
	s->tx[i] = (float)nrm[0];
	s->ty[i] = (float)nrm[1];
	s->tz[i] = (float)nrm[2];
}

/* Uniform on the sphere of radius r about c, points with z below zmin
 * (relative to c, in units of r) rejected: zmin = -1 gives the whole sphere. */
static void make_sphere(sample *s, size_t first, size_t n, const double c[3], double r, double zmin,
			double sigma, dp_rng *rng)
{
	for (size_t i = first; i < first + n;) {
		double u = 2.0 * dp_rng_uniform(rng) - 1.0, a = 2.0 * M_PI * dp_rng_uniform(rng);
		double rho = sqrt(1.0 - u * u);
		double nrm[3] = {rho * cos(a), rho * sin(a), u};
		if (u < zmin)
			continue;
		double p[3] = {c[0] + r * nrm[0], c[1] + r * nrm[1], c[2] + r * nrm[2]};
		put(s, i++, p, nrm, sigma, rng);
	}
}

/* Torus about z: core radius R, tube radius rho; area-uniform by rejection. */
static void make_torus(sample *s, size_t n, double R, double rho, dp_rng *rng)
{
	sample_alloc(s, n);
	for (size_t i = 0; i < n;) {
		double th = 2.0 * M_PI * dp_rng_uniform(rng), ph = 2.0 * M_PI * dp_rng_uniform(rng);
		if (dp_rng_uniform(rng) * (R + rho) > R + rho * cos(ph))
			continue;
		double nrm[3] = {cos(ph) * cos(th), cos(ph) * sin(th), sin(ph)};
		double p[3] = {(R + rho * cos(ph)) * cos(th), (R + rho * cos(ph)) * sin(th), rho * sin(ph)};
		put(s, i++, p, nrm, NOISE_FRACTION * rho, rng);
	}
}

static void cross(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm3(const double a[3])
{
	return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* Trefoil core curve s (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t), its first
 * two derivatives, and the tube's area element |c'| (1 - kappa rho cos phi) in
 * the Frenet frame (T, N, B) at angle phi from N. */
typedef struct knot_frame {
	double c[3], nvec[3], bvec[3], speed, kappa;
} knot_frame;

static void knot_at(double t, double sc, knot_frame *f)
{
	double d1[3] = {sc * (cos(t) + 4 * cos(2 * t)), sc * (-sin(t) + 4 * sin(2 * t)), sc * (-3 * cos(3 * t))};
	double d2[3] = {sc * (-sin(t) - 8 * sin(2 * t)), sc * (-cos(t) + 8 * cos(2 * t)), sc * (9 * sin(3 * t))};
	f->c[0] = sc * (sin(t) + 2 * sin(2 * t));
	f->c[1] = sc * (cos(t) - 2 * cos(2 * t));
	f->c[2] = sc * (-sin(3 * t));
	double b[3], tv[3];
	cross(d1, d2, b);
	f->speed = norm3(d1);
	double bl = norm3(b);
	f->kappa = bl / (f->speed * f->speed * f->speed);
	for (int k = 0; k < 3; k++) {
		f->bvec[k] = b[k] / bl;
		tv[k] = d1[k] / f->speed;
	}
	cross(f->bvec, tv, f->nvec);
}

static void make_knot(sample *s, size_t n, double sc, double rho, dp_rng *rng)
{
	sample_alloc(s, n);
	const int scan = 20000;
	double bound = 0.0;
	for (int j = 0; j < scan; j++) {
		knot_frame f;
		knot_at(2.0 * M_PI * j / scan, sc, &f);
		double a = f.speed * (1.0 + f.kappa * rho);
		bound = a > bound ? a : bound;
	}
	for (size_t i = 0; i < n;) {
		double t = 2.0 * M_PI * dp_rng_uniform(rng), ph = 2.0 * M_PI * dp_rng_uniform(rng);
		knot_frame f;
		knot_at(t, sc, &f);
		assert_true(f.kappa * rho < 1.0); /* the tube does not fold onto itself */
		if (dp_rng_uniform(rng) * bound * 1.01 > f.speed * (1.0 - f.kappa * rho * cos(ph)))
			continue;
		double nrm[3], p[3];
		for (int k = 0; k < 3; k++) {
			nrm[k] = cos(ph) * f.nvec[k] + sin(ph) * f.bvec[k];
			p[k] = f.c[k] + rho * nrm[k];
		}
		put(s, i++, p, nrm, NOISE_FRACTION * rho, rng);
	}
}

typedef struct quality {
	double outward;    /* fraction with n·n_true > 0 */
	double mean_angle; /* mean angle to n_true in degrees, sign included */
	double max_len_err;
} quality;

static quality measure(const sample *s)
{
	const dp_cloud *c = &s->cloud;
	quality q = {0, 0, 0};
	for (size_t i = 0; i < c->n; i++) {
		double len = sqrt((double)c->nx[i] * c->nx[i] + (double)c->ny[i] * c->ny[i] +
				  (double)c->nz[i] * c->nz[i]);
		assert_true(isfinite(len));
		q.max_len_err = fmax(q.max_len_err, fabs(len - 1.0));
		double d = ((double)c->nx[i] * s->tx[i] + (double)c->ny[i] * s->ty[i] + (double)c->nz[i] * s->tz[i]) /
			   len;
		q.outward += d > 0.0;
		q.mean_angle += acos(fmax(-1.0, fmin(1.0, d))) * 180.0 / M_PI;
	}
	q.outward /= (double)c->n;
	q.mean_angle /= (double)c->n;
	return q;
}

static quality estimate_and_measure(sample *s, const dp_normal_params *p, const char *name)
{
	dp_error err = {0};
	double t0 = dp_seconds();
	dp_status st = dp_estimate_normals(&s->cloud, p, &err);
	double secs = dp_seconds() - t0;
	if (st != DP_OK)
		fail_msg("%s: %s", name, err.message);
	quality q = measure(s);
	print_message("%s: %zu points, outward %.4f, mean angle error %.2f deg, %.3f s\n", name, s->cloud.n,
		      q.outward, q.mean_angle, secs);
	assert_true(q.max_len_err < 1e-5);
	return q;
}

static void assert_outward(const quality *q)
{
	assert_true(q->outward >= MIN_OUTWARD);
	assert_true(q->mean_angle < MAX_MEAN_ANGLE_DEG);
}

static void test_torus(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 11);
	sample s = {0};
	make_torus(&s, 4000, 1.0, 0.3, &rng);
	quality q = estimate_and_measure(&s, NULL, "torus");
	assert_outward(&q);
	sample_free(&s);
}

static void test_knot(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 12);
	sample s = {0};
	make_knot(&s, 5000, 0.35, 0.12, &rng);
	quality q = estimate_and_measure(&s, NULL, "trefoil knot");
	assert_outward(&q);
	sample_free(&s);
}

static void test_sphere(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 13);
	sample s = {0};
	const double c[3] = {0.2, -0.4, 0.1};
	sample_alloc(&s, 3000);
	make_sphere(&s, 0, 3000, c, 1.0, -1.0, NOISE_FRACTION, &rng);
	quality q = estimate_and_measure(&s, NULL, "sphere");
	assert_outward(&q);
	sample_free(&s);
}

/* Every point stored three times: PCA and the graph see exact duplicates. */
static void test_sphere_duplicates(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 14);
	sample s = {0};
	const double c[3] = {0, 0, 0};
	const size_t m = 1000, copies = 3;
	sample_alloc(&s, m * copies);
	make_sphere(&s, 0, m, c, 1.0, -1.0, NOISE_FRACTION, &rng);
	for (size_t i = m; i < m * copies; i++) {
		s.cloud.x[i] = s.cloud.x[i % m];
		s.cloud.y[i] = s.cloud.y[i % m];
		s.cloud.z[i] = s.cloud.z[i % m];
		s.tx[i] = s.tx[i % m];
		s.ty[i] = s.ty[i % m];
		s.tz[i] = s.tz[i % m];
	}
	quality q = estimate_and_measure(&s, NULL, "sphere, every point three times");
	assert_outward(&q);
	sample_free(&s);
}

/* A one-sided scan: the cap z > 0.2 of a sphere, as seen from above. */
static void make_cap(sample *s, dp_rng *rng)
{
	const double c[3] = {0, 0, 0};
	sample_alloc(s, 2500);
	make_sphere(s, 0, 2500, c, 1.0, 0.2, NOISE_FRACTION, rng);
}

static void test_cap_viewpoint(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 15);
	sample s = {0};
	make_cap(&s, &rng);
	dp_normal_params p;
	dp_normal_params_default(&p);
	p.use_viewpoint = 1;
	p.viewpoint[0] = 0.5;
	p.viewpoint[1] = -0.5;
	p.viewpoint[2] = 10.0;
	quality q = estimate_and_measure(&s, &p, "cap with viewpoint");
	const dp_cloud *c = &s.cloud;
	for (size_t i = 0; i < c->n; i++) {
		double d = (p.viewpoint[0] - c->x[i]) * c->nx[i] + (p.viewpoint[1] - c->y[i]) * c->ny[i] +
			   (p.viewpoint[2] - c->z[i]) * c->nz[i];
		assert_true(d > 0.0);
	}
	/* Every point of the cap is visible from there, so facing the viewpoint
	 * is also outward. */
	assert_outward(&q);
	sample_free(&s);
}

static void test_cap_open_scan(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 16);
	sample s = {0};
	make_cap(&s, &rng);
	quality q = estimate_and_measure(&s, NULL, "open cap, no viewpoint");
	assert_outward(&q);
	sample_free(&s);
}

/* Two spheres far apart: two graph components, each oriented on its own. */
static void test_two_spheres(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 17);
	sample s = {0};
	const double a[3] = {-3, 0, 0.5}, b[3] = {3, 1, 0};
	sample_alloc(&s, 3000);
	make_sphere(&s, 0, 1800, a, 1.0, -1.0, NOISE_FRACTION, &rng);
	make_sphere(&s, 1800, 1200, b, 0.6, -1.0, NOISE_FRACTION * 0.6, &rng);
	quality q = estimate_and_measure(&s, NULL, "two spheres");
	assert_outward(&q);
	sample_free(&s);
}

/* Points of a Fibonacci sphere of `total` points, radius r about the
 * origin, with z at most zmax (in units of r), from row `first`; normals
 * outward (sign +1) or towards the centre (-1). Even spacing, so that a gap
 * of a few spacings splits the kNN graph, as it does on WLOP's output.
 * Returns the rows written. */
static size_t make_fibonacci(sample *s, size_t first, size_t total, double r, double zmax, double sign,
			     dp_rng *rng)
{
	size_t row = first;
	for (size_t i = 0; i < total; i++) {
		double u = 1.0 - (2.0 * (double)i + 1.0) / (double)total, a = (double)i * M_PI * (3.0 - sqrt(5.0));
		if (u > zmax)
			continue;
		double rho = sqrt(1.0 - u * u);
		double out[3] = {rho * cos(a), rho * sin(a), u}, nrm[3] = {sign * out[0], sign * out[1], sign * out[2]};
		double p[3] = {r * out[0], r * out[1], r * out[2]};
		put(s, row++, p, nrm, NOISE_FRACTION * r, rng);
	}
	return row - first;
}

/* The scene of test_fragment_under_body: rows [0, *n) the ball, then the
 * hollow's *hollow rows. */
static void make_ball_over_hollow(sample *s, uint64_t seed, size_t *n, size_t *hollow)
{
	dp_rng rng;
	dp_rng_seed(&rng, seed);
	const double radius = 1.25, zmax = -cos(35.0 * M_PI / 180.0);
	const size_t body = 3000, shell = (size_t)(body * radius * radius);
	sample_alloc(s, body + shell);
	*n = make_fibonacci(s, 0, body, 1.0, 1.0, 1.0, &rng);
	*hollow = make_fibonacci(s, *n, shell, radius, zmax, -1.0, &rng);
	s->cloud.n = *n + *hollow;
}

/* A ball resting over a bowl-shaped hollow in the solid below it, scanned
 * without the solid's sides: the hollow's points are a graph component of
 * their own 0.25 under the ball (about five mean spacings), facing it (the
 * one-view bunny's foot top under its belly). Concave, it voted itself
 * inwards; it takes its sign from the ball across the gap. The geometry
 * has a window: below a radius of about 1.2 the kNN graph joins the two
 * (and the propagation, not this step, decides), above about 1.6 the hollow
 * lies beyond the link range (both with 8 graph neighbours). */
static void test_fragment_under_body(void **state)
{
	(void)state;
	sample s = {0};
	size_t n, hollow;
	make_ball_over_hollow(&s, 23, &n, &hollow);
	/* the window above is measured at 8 graph neighbours: pinned, so that a
	 * new default cannot move the scene out of it unnoticed */
	dp_normal_params p;
	dp_normal_params_default(&p);
	p.k_graph = 8;
	quality q = estimate_and_measure(&s, &p, "ball over a hollow");
	size_t wrong = 0;
	for (size_t i = n; i < n + hollow; i++)
		wrong += s.cloud.nx[i] * s.tx[i] + s.cloud.ny[i] * s.ty[i] + s.cloud.nz[i] * s.tz[i] < 0.0f;
	print_message("hollow: %zu of %zu normals facing away from the ball\n", wrong, hollow);
	/* a wrong sign turns the whole component; noise a few points */
	assert_true(wrong <= hollow * 3 / 100);
	assert_outward(&q);
	sample_free(&s);
}

/* The outward check alone, with links: the ball and the hollow of
 * test_fragment_under_body with their exact normals, as two components.
 * The body decides by its vote, first, and the hollow is read against the
 * body's corrected normals; each is flipped when it comes in wrong. */
static void test_outward_links(void **state)
{
	(void)state;
	for (int wrong = 0; wrong < 2; wrong++) {
		sample s = {0};
		size_t n, hollow;
		make_ball_over_hollow(&s, 29, &n, &hollow);
		dp_error err = {0};
		assert_int_equal(dp_cloud_add_normals(&s.cloud, &err), DP_OK);
		uint32_t *comp = malloc(s.cloud.n * sizeof *comp);
		double *area = malloc(s.cloud.n * sizeof *area);
		assert_non_null(comp);
		assert_non_null(area);
		for (size_t i = 0; i < s.cloud.n; i++) {
			comp[i] = i >= n;
			/* wrong = 0: the body comes in inwards; 1: the hollow does */
			double sgn = (size_t)wrong == comp[i] ? -1.0 : 1.0;
			s.cloud.nx[i] = (float)(sgn * s.tx[i]);
			s.cloud.ny[i] = (float)(sgn * s.ty[i]);
			s.cloud.nz[i] = (float)(sgn * s.tz[i]);
			area[i] = 1.0;
		}
		size_t flipped = 0;
		assert_int_equal(dp_orient_outward(s.cloud.n, s.cloud.x, s.cloud.y, s.cloud.z, s.cloud.nx,
						   s.cloud.ny, s.cloud.nz, area, comp, 2, 0.5, &flipped, &err),
				 DP_OK);
		assert_int_equal(flipped, 1);
		assert_true(measure(&s).outward == 1.0);
		free(comp);
		free(area);
		sample_free(&s);
	}
}

/* An open sheet has no outside: all normals must merely agree. */
static void test_plane_sheet(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 18);
	const size_t n = 2500;
	dp_cloud c = {0};
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(&c, n, 0, &err), DP_OK);
	const double sigma = 0.002; /* 5% of the sample spacing */
	for (size_t i = 0; i < n; i++) {
		/* tilted, so no axis is special */
		double u = 2.0 * dp_rng_uniform(&rng) - 1.0, v = 2.0 * dp_rng_uniform(&rng) - 1.0;
		c.x[i] = (float)(u + sigma * dp_rng_normal(&rng));
		c.y[i] = (float)(0.6 * v + sigma * dp_rng_normal(&rng));
		c.z[i] = (float)(0.8 * v + sigma * dp_rng_normal(&rng));
	}
	assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_OK);
	size_t up = 0;
	double angle = 0.0;
	for (size_t i = 0; i < n; i++) {
		double d = -0.8 * c.ny[i] + 0.6 * c.nz[i]; /* the plane's normal (0, -0.8, 0.6) */
		up += d > 0.0;
		angle += acos(fmin(1.0, fabs(d))) * 180.0 / M_PI;
	}
	print_message("plane sheet: %zu of %zu on one side, mean unsigned angle error %.2f deg\n",
		      up > n - up ? up : n - up, n, angle / (double)n);
	assert_true(up == 0 || up == n);
	assert_true(angle / (double)n < MAX_MEAN_ANGLE_DEG);
	dp_cloud_free(&c);
}

/* The outward check alone: a component handed in with inward normals is
 * flipped, an outward one is not. */
static void test_outward_check(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 19);
	sample s = {0};
	make_knot(&s, 2000, 0.35, 0.12, &rng);
	const size_t n = s.cloud.n;
	dp_error err = {0};
	assert_int_equal(dp_cloud_add_normals(&s.cloud, &err), DP_OK);
	uint32_t *comp = malloc(n * sizeof *comp);
	double *area = malloc(n * sizeof *area);
	assert_non_null(comp);
	assert_non_null(area);
	for (size_t i = 0; i < n; i++) {
		/* component 1 (the points with x < 0) comes in with inward normals */
		comp[i] = s.cloud.x[i] < 0.0f;
		double sgn = comp[i] ? -1.0 : 1.0;
		s.cloud.nx[i] = (float)(sgn * s.tx[i]);
		s.cloud.ny[i] = (float)(sgn * s.ty[i]);
		s.cloud.nz[i] = (float)(sgn * s.tz[i]);
		area[i] = 1.0;
	}
	size_t flipped = 0;
	assert_int_equal(dp_orient_outward(n, s.cloud.x, s.cloud.y, s.cloud.z, s.cloud.nx, s.cloud.ny,
					   s.cloud.nz, area, comp, 2, 0.0, &flipped, &err),
			 DP_OK);
	assert_int_equal(flipped, 1);
	quality q = measure(&s);
	assert_true(q.outward == 1.0);
	free(comp);
	free(area);
	sample_free(&s);
}

static void check_finite_unit(const dp_cloud *c)
{
	for (size_t i = 0; i < c->n; i++) {
		double len = sqrt((double)c->nx[i] * c->nx[i] + (double)c->ny[i] * c->ny[i] +
				  (double)c->nz[i] * c->nz[i]);
		assert_true(isfinite(len));
		assert_true(fabs(len - 1.0) < 1e-5);
	}
}

/* Fewer points than a neighbourhood, a line, one repeated point, with and
 * without viewpoint: unit normals, never NaN. */
static void test_tiny_and_degenerate(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_normal_params view;
	dp_normal_params_default(&view);
	view.use_viewpoint = 1;
	view.viewpoint[2] = 5.0;
	for (size_t n = 1; n <= 17; n++) {
		for (int kind = 0; kind < 3; kind++) {
			dp_cloud c = {0};
			assert_int_equal(dp_cloud_alloc(&c, n, 0, &err), DP_OK);
			for (size_t i = 0; i < n; i++) {
				double t = (double)i;
				/* 0: scattered, 1: collinear, 2: all at one spot */
				c.x[i] = kind == 2 ? 1.0f : (float)t;
				c.y[i] = kind == 0 ? (float)(t * t * 0.1) : kind == 1 ? (float)(2 * t) : 1.0f;
				c.z[i] = kind == 0 ? (float)sin(t) : kind == 1 ? (float)(-t) : 1.0f;
			}
			assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_OK);
			check_finite_unit(&c);
			assert_int_equal(dp_estimate_normals(&c, &view, &err), DP_OK);
			check_finite_unit(&c);
			dp_cloud_free(&c);
		}
	}
}

/* A plane with 20 copies of one of its points: the copies see only each other
 * (an undefined normal) and must not disturb the plane's orientation. */
static void test_plane_with_stack(void **state)
{
	(void)state;
	dp_error err = {0};
	const size_t side = 30, copies = 20, plane = side * side, n = plane + copies;
	dp_cloud c = {0};
	assert_int_equal(dp_cloud_alloc(&c, n, 0, &err), DP_OK);
	for (size_t i = 0; i < n; i++) {
		size_t g = i < plane ? i : plane / 2 + side / 2;
		c.x[i] = (float)(g % side) * 0.1f;
		c.y[i] = (float)(g / side) * 0.1f;
		c.z[i] = 0.0f;
	}
	assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_OK);
	check_finite_unit(&c);
	size_t up = 0;
	for (size_t i = 0; i < plane; i++) {
		assert_true(fabsf(c.nz[i]) > 0.999f);
		up += c.nz[i] > 0.0f;
	}
	assert_true(up == 0 || up == plane);
	dp_cloud_free(&c);
}

static void test_bad_input(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud c = {0};
	assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_ERR_EMPTY);
	assert_non_null(strstr(err.message, "normals"));
	assert_int_equal(dp_estimate_normals(NULL, NULL, &err), DP_ERR_ARG);
	assert_int_equal(dp_cloud_alloc(&c, 20, 0, &err), DP_OK);
	for (size_t i = 0; i < 20; i++) {
		c.x[i] = (float)i;
		c.y[i] = (float)(i * i);
		c.z[i] = 0.0f;
	}
	dp_normal_params p;
	dp_normal_params_default(&p);
	p.k = 1;
	assert_int_equal(dp_estimate_normals(&c, &p, &err), DP_ERR_ARG);
	dp_normal_params_default(&p);
	p.k_graph = 0;
	assert_int_equal(dp_estimate_normals(&c, &p, &err), DP_ERR_ARG);
	dp_normal_params_default(&p);
	p.use_viewpoint = 1;
	p.viewpoint[1] = NAN;
	assert_int_equal(dp_estimate_normals(&c, &p, &err), DP_ERR_ARG);
	c.y[7] = INFINITY;
	assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "point 7"));
	dp_cloud_free(&c);
}

/* The fraction of a thin closed slab's face samples (width 1, `thickness`
 * thick, 3000 samples: spacing about 0.026) whose estimated normal points
 * outward. The kNN graph links the two faces, whose normals are antiparallel:
 * Hoppe's weight and agreement test alone pass the orientation across and
 * turn one face inwards. Samples of the built-in slab mesh carry its exact
 * outward normals. */
static double thin_plate_outward(double thickness)
{
	dp_error err = {0};
	dp_shape shape;
	dp_cloud mesh = {0}, truth = {0};
	assert_int_equal(dp_shape_default("slab", &shape, &err), DP_OK);
	shape.width = 1.0;
	shape.thickness = thickness;
	assert_int_equal(dp_shape_mesh(&shape, &mesh, &err), DP_OK);
	assert_int_equal(dp_mesh_sample(&mesh, 3000, 0.0, 3, &truth, &err), DP_OK);
	dp_cloud c;
	assert_int_equal(dp_cloud_copy(&c, &truth, &err), DP_OK);
	assert_int_equal(dp_estimate_normals(&c, NULL, &err), DP_OK);
	/* The rim is as thin as two spacings: PCA there sees the plate, and its
	 * sideways normal has no outward side to find; count the two faces. */
	size_t outward = 0, faces = 0;
	for (size_t i = 0; i < c.n; i++) {
		if (fabsf(truth.nz[i]) < 0.9f)
			continue;
		faces++;
		outward += c.nx[i] * truth.nx[i] + c.ny[i] * truth.ny[i] + c.nz[i] * truth.nz[i] > 0.0f;
	}
	printf("thin plate %.2f thick: %zu points on the faces, outward %.4f\n", thickness, faces,
	       (double)outward / (double)faces);
	assert_true(faces > c.n / 2);
	dp_cloud_free(&c);
	dp_cloud_free(&truth);
	dp_cloud_free(&mesh);
	return (double)outward / (double)faces;
}

/* 2.3 spacings thick: 0.516 outward with Hoppe's weight alone, 0.989 with
 * the cost of running along the normals (from 2.7 spacings on, all). 1.5
 * spacings: 0.51 even so, since a step across is then the only way to the far
 * face; 0.88 with the mirrored agreement test (orient.c). */
static void test_thin_plate(void **state)
{
	(void)state;
	assert_true(thin_plate_outward(0.06) >= 0.98);
	assert_true(thin_plate_outward(0.04) >= 0.85);
}

/* Sparse WLOP samples of the demo chair (two views of 128 x 128 rays, 4452
 * points, 1000 samples): oriented on their own 98% pointed inwards, the legs
 * and the back rest a sample or two thick; with signs from 4000 denser
 * samples (dp_orient_from_denser) 0.6%. Enough samples, or a viewpoint,
 * leave the normals alone. */
static void test_sparse_from_denser(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud mesh = {0}, scan = {0}, samples = {0};
	tk_scan_shape("chair", 2, 128, 0.003, 1, NULL, &mesh, &scan);
	dp_wlop_params wp;
	dp_wlop_params_default(&wp);
	wp.samples = 1000;
	assert_int_equal(dp_wlop(tk_cl_context(), &scan, &wp, &samples, NULL, &err), DP_OK);
	assert_int_equal(dp_estimate_normals(&samples, NULL, &err), DP_OK);
	dp_eval_result own, guided;
	assert_int_equal(dp_eval(&mesh, &samples, NULL, &own, &err), DP_OK);
	size_t dense = 0, turned = 0;
	assert_int_equal(dp_orient_from_denser(tk_cl_context(), &scan, &wp, NULL, DP_ORIENT_DENSE_SAMPLES, &samples,
					       &dense, &turned, &err),
			 DP_OK);
	assert_int_equal(dp_eval(&mesh, &samples, NULL, &guided, &err), DP_OK);
	printf("chair, 1000 WLOP samples of %zu points: %.4f flipped on their own, %.4f with signs from %zu (%zu "
	       "turned)\n", scan.n, own.normal_flipped, guided.normal_flipped, dense, turned);
	assert_int_equal(dense, DP_ORIENT_DENSE_SAMPLES);
	assert_true(guided.normal_flipped < 0.05);
	/* as many samples as the dense count, or a viewpoint: nothing to do */
	float nx0 = samples.nx[0];
	assert_int_equal(dp_orient_from_denser(tk_cl_context(), &scan, &wp, NULL, samples.n, &samples, &dense, &turned,
					       &err),
			 DP_OK);
	assert_int_equal(dense, 0);
	assert_int_equal(turned, 0);
	dp_normal_params np;
	dp_normal_params_default(&np);
	np.use_viewpoint = 1;
	assert_int_equal(dp_orient_from_denser(tk_cl_context(), &scan, &wp, &np, DP_ORIENT_DENSE_SAMPLES, &samples,
					       &dense, &turned, &err),
			 DP_OK);
	assert_int_equal(dense, 0);
	assert_true(samples.nx[0] == nx0);
	dp_cloud bare = {0};
	assert_int_equal(dp_cloud_alloc(&bare, 10, 0, &err), DP_OK);
	assert_int_equal(dp_orient_from_denser(tk_cl_context(), &scan, &wp, NULL, DP_ORIENT_DENSE_SAMPLES, &bare, NULL,
					       NULL, &err),
			 DP_ERR_ARG);
	dp_cloud_free(&bare);
	dp_cloud_free(&samples);
	dp_cloud_free(&scan);
	dp_cloud_free(&mesh);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_torus),
		cmocka_unit_test(test_knot),
		cmocka_unit_test(test_sphere),
		cmocka_unit_test(test_sphere_duplicates),
		cmocka_unit_test(test_cap_viewpoint),
		cmocka_unit_test(test_cap_open_scan),
		cmocka_unit_test(test_two_spheres),
		cmocka_unit_test(test_fragment_under_body),
		cmocka_unit_test(test_plane_sheet),
		cmocka_unit_test(test_thin_plate),
		cmocka_unit_test(test_outward_check),
		cmocka_unit_test(test_outward_links),
		cmocka_unit_test(test_tiny_and_degenerate),
		cmocka_unit_test(test_plane_with_stack),
		cmocka_unit_test(test_bad_input),
		cmocka_unit_test(test_sparse_from_denser),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
