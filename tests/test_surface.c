/* Surface consolidation (dp_surface) on shapes with a known answer, with
 * noise (DESIGN 5, issue 3): a complete sphere lands on the sphere; one-sided
 * scans (the half facing +z) of a sphere and a torus are completed by the
 * volume prior; and the two backends agree on a small input. The skeletons
 * stand in for the earlier stages: points near the centre (sphere), points
 * near the core circle (torus). */
#include "testkit.h"

#include "knn/knn.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SPHERE_R 1.0
#define TORUS_R 1.0
#define TORUS_RHO 0.35
/* Coverage: a true-surface sample is covered within this many mean
 * nearest-neighbour spacings of the points (issue 3). */
#define COVER_FACTOR 1.5
#define TRUTH_SAMPLES 6000

typedef struct shape {
	int torus; /* else sphere */
} shape;

/* A uniform point of the surface with its outward normal. The torus is
 * sampled by rejection on the tube angle (area element ∝ R + ρ cos v). */
static void surface_point(const shape *s, dp_rng *rng, double p[3], double n[3])
{
	if (!s->torus) {
		double len;
		do {
			len = 0.0;
			for (int a = 0; a < 3; a++) {
				n[a] = dp_rng_normal(rng);
				len += n[a] * n[a];
			}
		} while (len < 1e-12);
		len = sqrt(len);
		for (int a = 0; a < 3; a++) {
			n[a] /= len;
			p[a] = SPHERE_R * n[a];
		}
		return;
	}
	double u = 2.0 * M_PI * dp_rng_uniform(rng), v;
	do
		v = 2.0 * M_PI * dp_rng_uniform(rng);
	while (dp_rng_uniform(rng) * (TORUS_R + TORUS_RHO) > TORUS_R + TORUS_RHO * cos(v));
	n[0] = cos(v) * cos(u);
	n[1] = cos(v) * sin(u);
	n[2] = sin(v);
	p[0] = (TORUS_R + TORUS_RHO * cos(v)) * cos(u);
	p[1] = (TORUS_R + TORUS_RHO * cos(v)) * sin(u);
	p[2] = TORUS_RHO * sin(v);
}

static double surface_distance(const shape *s, const float *p)
{
	double x = p[0], y = p[1], z = p[2];
	if (!s->torus)
		return fabs(sqrt(x * x + y * y + z * z) - SPHERE_R);
	double ring = sqrt(x * x + y * y) - TORUS_R;
	return fabs(sqrt(ring * ring + z * z) - TORUS_RHO);
}

/* The skeleton point an earlier stage would give for surface point p: the
 * centre, or the nearest core-circle point, plus isotropic noise. */
static void skeleton_point(const shape *s, dp_rng *rng, const double p[3], double noise, float q[3])
{
	double c[3] = {0.0, 0.0, 0.0};
	if (s->torus) {
		double rho = sqrt(p[0] * p[0] + p[1] * p[1]);
		c[0] = TORUS_R * p[0] / rho;
		c[1] = TORUS_R * p[1] / rho;
	}
	for (int a = 0; a < 3; a++)
		q[a] = (float)(c[a] + noise * dp_rng_normal(rng));
}

/* n points of the surface (only those with z > 0 when one_sided) with
 * Gaussian noise per coordinate and exact outward normals. */
static void make_cloud(const shape *s, dp_rng *rng, size_t n, int one_sided, double noise, dp_cloud *c)
{
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(c, n, 1, &err), DP_OK);
	for (size_t i = 0; i < n; i++) {
		double p[3], nrm[3];
		do
			surface_point(s, rng, p, nrm);
		while (one_sided && p[2] <= 0.0);
		c->x[i] = (float)(p[0] + noise * dp_rng_normal(rng));
		c->y[i] = (float)(p[1] + noise * dp_rng_normal(rng));
		c->z[i] = (float)(p[2] + noise * dp_rng_normal(rng));
		c->nx[i] = (float)nrm[0];
		c->ny[i] = (float)nrm[1];
		c->nz[i] = (float)nrm[2];
	}
}

static void make_skeleton(const shape *s, dp_rng *rng, const dp_cloud *samples, double noise, dp_cloud *q)
{
	dp_error err = {0};
	assert_int_equal(dp_cloud_alloc(q, samples->n, 1, &err), DP_OK);
	for (size_t i = 0; i < samples->n; i++) {
		double p[3] = {samples->x[i], samples->y[i], samples->z[i]};
		float v[3];
		skeleton_point(s, rng, p, noise, v);
		q->x[i] = v[0];
		q->y[i] = v[1];
		q->z[i] = v[2];
		q->nx[i] = samples->nx[i];
		q->ny[i] = samples->ny[i];
		q->nz[i] = samples->nz[i];
	}
}

static double mean_distance(const shape *s, const dp_cloud *c)
{
	double sum = 0.0;
	for (size_t i = 0; i < c->n; i++) {
		float p[3] = {c->x[i], c->y[i], c->z[i]};
		sum += surface_distance(s, p);
	}
	return sum / (double)c->n;
}

/* Fraction of TRUTH_SAMPLES uniform surface samples within COVER_FACTOR × the
 * mean nearest-neighbour spacing of c. */
static double coverage(const shape *s, const dp_cloud *c)
{
	dp_error err = {0};
	double spacing;
	assert_int_equal(dp_mean_spacing(c->n, c->x, c->y, c->z, &spacing, &err), DP_OK);
	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, c->n, c->x, c->y, c->z, &err), DP_OK);
	dp_rng rng;
	dp_rng_seed(&rng, 99);
	float *t = malloc(3 * TRUTH_SAMPLES * sizeof *t), *d2 = malloc(TRUTH_SAMPLES * sizeof *d2);
	int *idx = malloc(TRUTH_SAMPLES * sizeof *idx);
	assert_non_null(t);
	assert_non_null(d2);
	assert_non_null(idx);
	for (size_t i = 0; i < TRUTH_SAMPLES; i++) {
		double p[3], nrm[3];
		surface_point(s, &rng, p, nrm);
		for (int a = 0; a < 3; a++)
			t[a * TRUTH_SAMPLES + i] = (float)p[a];
	}
	assert_int_equal(dp_knn_query(&knn, TRUTH_SAMPLES, t, t + TRUTH_SAMPLES, t + 2 * TRUTH_SAMPLES, 1, idx, d2,
				      &err),
			 DP_OK);
	double lim = COVER_FACTOR * spacing;
	size_t covered = 0;
	for (size_t i = 0; i < TRUTH_SAMPLES; i++)
		covered += d2[i] <= lim * lim;
	free(t);
	free(d2);
	free(idx);
	dp_knn_free(&knn);
	return (double)covered / TRUTH_SAMPLES;
}

/* Mean angle (degrees) between output normals and the true outward normal
 * of the nearest surface point. */
static double normal_error_deg(const shape *s, const dp_cloud *c)
{
	double sum = 0.0;
	for (size_t i = 0; i < c->n; i++) {
		double x = c->x[i], y = c->y[i], z = c->z[i], t[3];
		if (!s->torus) {
			double len = sqrt(x * x + y * y + z * z);
			t[0] = x / len;
			t[1] = y / len;
			t[2] = z / len;
		} else {
			double rho = sqrt(x * x + y * y);
			double cx = TORUS_R * x / rho, cy = TORUS_R * y / rho;
			double len = sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + z * z);
			t[0] = (x - cx) / len;
			t[1] = (y - cy) / len;
			t[2] = z / len;
		}
		double dot = t[0] * c->nx[i] + t[1] * c->ny[i] + t[2] * c->nz[i];
		sum += acos(fmax(-1.0, fmin(1.0, dot))) * 180.0 / M_PI;
	}
	return sum / (double)c->n;
}

typedef struct scene {
	shape s;
	dp_cloud input, samples, skeleton;
	double r;
} scene;

static void make_scene(scene *sc, int torus, int one_sided, size_t n_input, size_t n_samples, double input_noise,
		       double sample_noise, double skeleton_noise, uint64_t seed)
{
	dp_rng rng;
	dp_rng_seed(&rng, seed);
	sc->s.torus = torus;
	make_cloud(&sc->s, &rng, n_input, one_sided, input_noise, &sc->input);
	make_cloud(&sc->s, &rng, n_samples, one_sided, sample_noise, &sc->samples);
	make_skeleton(&sc->s, &rng, &sc->samples, skeleton_noise, &sc->skeleton);
	dp_error err = {0};
	assert_int_equal(dp_mean_spacing(sc->samples.n, sc->samples.x, sc->samples.y, sc->samples.z, &sc->r, &err),
			 DP_OK);
}

static void free_scene(scene *sc)
{
	dp_cloud_free(&sc->input);
	dp_cloud_free(&sc->samples);
	dp_cloud_free(&sc->skeleton);
}

static void run_stage(dp_context *ctx, scene *sc, const dp_surface_params *p, dp_cloud *out, float *eta,
		      dp_surface_stats *st)
{
	dp_error err = {0};
	if (dp_surface(ctx, &sc->input, &sc->samples, &sc->skeleton, NULL, sc->r, p, out, eta, st, &err) != DP_OK)
		fail_msg("dp_surface: %s", err.message);
}

static void report(const char *name, const scene *sc, const dp_cloud *out, const dp_surface_stats *st, double unit)
{
	printf("%s: n=%zu r=%.4f iterations=%d converged=%d last_move=%.4f r spacing_growth=%.3f reattached=%zu "
	       "seconds=%.2f pairs=%.3g\n",
	       name, out->n, sc->r, st->iterations, st->converged, st->last_mean_move, st->spacing_growth,
	       st->reattached, st->seconds, st->pair_evaluations);
	printf("%s: mean distance to the surface input %.4f samples %.4f output %.4f (x %s); coverage input %.3f "
	       "samples %.3f output %.3f; output normal error %.2f deg\n",
	       name, mean_distance(&sc->s, &sc->input) / unit, mean_distance(&sc->s, &sc->samples) / unit,
	       mean_distance(&sc->s, out) / unit, sc->s.torus ? "rho" : "R", coverage(&sc->s, &sc->input),
	       coverage(&sc->s, &sc->samples), coverage(&sc->s, out), normal_error_deg(&sc->s, out));
}

/* Largest distance from an inner end to the nearest point of the skeleton
 * as it was given: re-attachment only ever picks skeleton points. */
static double off_skeleton(const dp_cloud *given, const dp_cloud *now)
{
	dp_error err = {0};
	dp_knn knn;
	assert_int_equal(dp_knn_build(&knn, given->n, given->x, given->y, given->z, &err), DP_OK);
	int *idx = malloc(now->n * sizeof *idx);
	float *d2 = malloc(now->n * sizeof *d2);
	assert_non_null(idx);
	assert_non_null(d2);
	assert_int_equal(dp_knn_query(&knn, now->n, now->x, now->y, now->z, 1, idx, d2, &err), DP_OK);
	double worst = 0.0;
	for (size_t i = 0; i < now->n; i++)
		worst = fmax(worst, sqrt(d2[i]));
	free(idx);
	free(d2);
	dp_knn_free(&knn);
	return worst;
}

/* Complete noisy sphere: the output lies within 0.01 R of the sphere on
 * average (issue 3), starting from samples noisier than that. */
static void test_sphere_complete(void **state)
{
	(void)state;
	scene sc;
	make_scene(&sc, 0, 0, 8000, 2000, 0.02 * SPHERE_R, 0.02 * SPHERE_R, 0.03 * SPHERE_R, 1);
	dp_surface_params p;
	dp_surface_params_default(&p);
	dp_cloud out = {0};
	float *eta = malloc(sc.samples.n * sizeof *eta);
	assert_non_null(eta);
	dp_surface_stats st;
	run_stage(tk_cl_context(), &sc, &p, &out, eta, &st);
	report("sphere complete", &sc, &out, &st, SPHERE_R);
	assert_true(mean_distance(&sc.s, &sc.samples) > 0.01 * SPHERE_R);
	assert_true(mean_distance(&sc.s, &out) < 0.01 * SPHERE_R);
	/* No point has left the data of a complete scan: every η shows input
	 * within about 1.5 r. */
	for (size_t i = 0; i < out.n; i++)
		assert_true(eta[i] > 1.1f);
	free(eta);
	dp_cloud_free(&out);
	free_scene(&sc);
}

/* Outward normals in a cap (z > 0.8 R) of the complete sphere scene, whose
 * inner ends there were moved 0.3 R outside the sphere, as where a thin
 * part's sinking points left it: each dpoint there points inwards. */
static double cap_outward(int orient_by_dpoint, size_t *in_cap)
{
	scene sc;
	make_scene(&sc, 0, 0, 8000, 2000, 0.01 * SPHERE_R, 0.01 * SPHERE_R, 0.03 * SPHERE_R, 3);
	*in_cap = 0;
	for (size_t i = 0; i < sc.samples.n; i++) {
		if (!(sc.samples.z[i] > 0.8 * SPHERE_R))
			continue;
		sc.skeleton.x[i] = 1.3f * sc.samples.x[i];
		sc.skeleton.y[i] = 1.3f * sc.samples.y[i];
		sc.skeleton.z[i] = 1.3f * sc.samples.z[i];
		(*in_cap)++;
	}
	dp_surface_params p;
	dp_surface_params_default(&p);
	p.orient_by_dpoint = orient_by_dpoint;
	p.max_iters = 3;
	p.reattach = 0;
	dp_cloud out = {0};
	dp_surface_stats st;
	run_stage(tk_cl_context(), &sc, &p, &out, NULL, &st);
	size_t outward = 0;
	for (size_t i = 0; i < out.n; i++)
		if (sc.samples.z[i] > 0.8 * SPHERE_R)
			outward += out.nx[i] * out.x[i] + out.ny[i] * out.y[i] + out.nz[i] * out.z[i] > 0.0f;
	printf("cap of %zu points with inner ends outside, orient_by_dpoint %d: %zu outward, %zu disagreeing\n",
	       *in_cap, orient_by_dpoint, outward, st.normals_disagreeing);
	dp_cloud_free(&out);
	free_scene(&sc);
	return (double)outward / (double)*in_cap;
}

/* A point the input holds keeps its data's orientation whatever its dpoint
 * says (orient_by_dpoint signs only the points no input holds): the cap's
 * normals stay outward, as they do when the old normal signs everything. */
static void test_held_orientation(void **state)
{
	(void)state;
	size_t in_cap = 0;
	assert_true(cap_outward(1, &in_cap) >= 0.95);
	assert_true(in_cap > 50);
	assert_true(cap_outward(0, &in_cap) >= 0.95);
}

/* One-sided scan: the output covers >= 90% of the true surface while the
 * input covers about half; mean distance to the surface < 0.05 R (issue 3). */
static void check_one_sided(int torus, const char *name, double unit)
{
	scene sc;
	make_scene(&sc, torus, 1, 6000, 1500, 0.01 * unit, 0.002 * unit, 0.03 * unit, torus ? 3 : 2);
	dp_cloud given = {0};
	dp_error err = {0};
	assert_int_equal(dp_cloud_copy(&given, &sc.skeleton, &err), DP_OK);
	dp_surface_params p;
	dp_surface_params_default(&p);
	dp_cloud out = {0};
	dp_surface_stats st;
	run_stage(tk_cl_context(), &sc, &p, &out, NULL, &st);
	report(name, &sc, &out, &st, unit);
	double cover_in = coverage(&sc.s, &sc.input);
	assert_true(cover_in > 0.4 && cover_in < 0.6);
	assert_true(coverage(&sc.s, &out) >= 0.9);
	assert_true(mean_distance(&sc.s, &out) < 0.05 * unit);
	assert_true(st.reattached > 0);
	assert_true(off_skeleton(&given, &sc.skeleton) == 0.0);
	/* Inner ends carry their surface point's final normal. */
	for (size_t i = 0; i < out.n; i++)
		assert_true(sc.skeleton.nx[i] == out.nx[i] && sc.skeleton.nz[i] == out.nz[i]);
	dp_cloud_free(&given);
	dp_cloud_free(&out);
	free_scene(&sc);
}

static void test_sphere_one_sided(void **state)
{
	(void)state;
	check_one_sided(0, "sphere one-sided", SPHERE_R);
}

static void test_torus_one_sided(void **state)
{
	(void)state;
	check_one_sided(1, "torus one-sided", TORUS_RHO);
}

/* The reference and OpenCL backends run the same stage: a few iterations on
 * a small one-sided sphere end at the same points. */
static void test_backends_agree(void **state)
{
	(void)state;
	scene sc[2];
	for (int b = 0; b < 2; b++)
		make_scene(&sc[b], 0, 1, 1200, 300, 0.01, 0.002, 0.03, 4);
	dp_surface_params p;
	dp_surface_params_default(&p);
	p.max_iters = 5;
	dp_cloud out[2] = {{0}, {0}};
	dp_surface_stats st[2];
	run_stage(tk_ref_context(), &sc[0], &p, &out[0], NULL, &st[0]);
	run_stage(tk_cl_context(), &sc[1], &p, &out[1], NULL, &st[1]);
	assert_int_equal(st[0].iterations, st[1].iterations);
	double worst = 0.0, moved = 0.0;
	for (size_t i = 0; i < out[0].n; i++) {
		double dx = out[0].x[i] - out[1].x[i], dy = out[0].y[i] - out[1].y[i], dz = out[0].z[i] - out[1].z[i];
		worst = fmax(worst, sqrt(dx * dx + dy * dy + dz * dz));
		double mx = out[0].x[i] - sc[0].samples.x[i], my = out[0].y[i] - sc[0].samples.y[i],
		       mz = out[0].z[i] - sc[0].samples.z[i];
		moved = fmax(moved, sqrt(mx * mx + my * my + mz * mz));
	}
	printf("backends: largest difference %.3g r after %d iterations (largest move %.3g r)\n", worst / sc[0].r,
	       st[0].iterations, moved / sc[0].r);
	assert_true(moved > 0.1 * sc[0].r);
	assert_true(worst < 1e-3 * sc[0].r);
	for (int b = 0; b < 2; b++) {
		dp_cloud_free(&out[b]);
		free_scene(&sc[b]);
	}
}

/* Where the output points are, in R, split by input support (η = 1 up to
 * float rounding: no input in reach): the mean depth below the equator of
 * the unsupported ones, their mean distance from the centre, and the mean
 * distance of the supported ones to the sphere. */
typedef struct prior_outcome {
	size_t unsupported;
	double depth, radius, supported_error;
} prior_outcome;

static prior_outcome measure_prior(const dp_cloud *out, const float *eta)
{
	prior_outcome o = {0};
	size_t supported = 0;
	for (size_t i = 0; i < out->n; i++) {
		double rad = sqrt((double)out->x[i] * out->x[i] + (double)out->y[i] * out->y[i] +
				  (double)out->z[i] * out->z[i]);
		if (eta[i] > 1.0f + 1e-6f) {
			o.supported_error += fabs(rad - SPHERE_R);
			supported++;
			continue;
		}
		o.depth += -out->z[i];
		o.radius += rad;
		o.unsupported++;
	}
	if (o.unsupported) {
		o.depth /= (double)o.unsupported * SPHERE_R;
		o.radius /= (double)o.unsupported * SPHERE_R;
	}
	if (supported)
		o.supported_error /= (double)supported * SPHERE_R;
	return o;
}

/* The two priors where there is no input: samples over the whole sphere,
 * input over the upper half only, the skeleton at the centre. The volume
 * prior keeps the lower half a hemisphere (at distance R from the centre);
 * the minimal prior closes it flatter (a flat disc would have depth 0)
 * without collapsing onto the skeleton; both keep the supported half on the
 * sphere. */
#define PRIOR_ITERS 40
static void test_priors(void **state)
{
	(void)state;
	dp_surface_params p;
	dp_surface_params_default(&p);
	p.max_iters = PRIOR_ITERS;
	prior_outcome o[2];
	for (int prior = 0; prior < 2; prior++) {
		dp_rng rng;
		dp_rng_seed(&rng, 6);
		scene sc;
		sc.s.torus = 0;
		make_cloud(&sc.s, &rng, 3000, 1, 0.005, &sc.input);
		make_cloud(&sc.s, &rng, 800, 0, 0.002, &sc.samples);
		make_skeleton(&sc.s, &rng, &sc.samples, 0.0, &sc.skeleton);
		dp_error err = {0};
		assert_int_equal(dp_mean_spacing(sc.samples.n, sc.samples.x, sc.samples.y, sc.samples.z, &sc.r, &err),
				 DP_OK);
		p.prior = prior ? DP_SURFACE_PRIOR_MINIMAL : DP_SURFACE_PRIOR_VOLUME;
		dp_cloud out = {0};
		float *eta = malloc(sc.samples.n * sizeof *eta);
		assert_non_null(eta);
		dp_surface_stats st;
		run_stage(tk_cl_context(), &sc, &p, &out, eta, &st);
		o[prior] = measure_prior(&out, eta);
		/* All 800 inner ends at one spot: re-attachment scans it once;
		 * scanning every copy would alone cost 800 pairs per point and
		 * iteration (skeleton_grid in surface.c). */
		double per_point = st.pair_evaluations / ((double)st.iterations * (double)sc.samples.n);
		printf("prior %s: %.0f candidate pairs per point and iteration\n", prior ? "minimal" : "volume",
		       per_point);
		assert_true(per_point < (double)sc.samples.n);
		printf("prior %s: %zu unsupported points at mean depth %.3f R below the equator, %.3f R from the "
		       "centre; supported points %.4f R off the sphere; %d iterations\n",
		       prior ? "minimal" : "volume", o[prior].unsupported, o[prior].depth, o[prior].radius,
		       o[prior].supported_error, st.iterations);
		assert_true(o[prior].unsupported > sc.samples.n / 4);
		free(eta);
		dp_cloud_free(&out);
		free_scene(&sc);
	}
	assert_true(fabs(o[0].radius - 1.0) < 0.02);
	assert_true(o[0].depth > 0.4);
	/* The membrane flattens slowly: its pull is the curvature offset of P_i,
	 * about r²/R a step (measured: depth 0.615 -> 0.592 R, distance from the
	 * centre 1.000 -> 0.959 R in ~30 iterations). It must remove volume and
	 * never collapse. */
	assert_true(o[1].depth < o[0].depth - 0.01);
	assert_true(o[1].radius < o[0].radius - 0.02);
	assert_true(o[1].radius > 0.5);
	for (int prior = 0; prior < 2; prior++)
		assert_true(o[prior].supported_error < 0.02);
}

/* A stray deep point 3 r past the rim of a half sphere, in the hole the
 * completion fills. Without a slide reach the repulsion, a normalised mean,
 * pushes it by its far neighbours' whole offset; with a 2 r reach it stays
 * until the front reaches it. Returns how far it moved along the sphere in r
 * within STRAY_ITERS iterations. */
#define STRAY_ITERS 8
#define STRAY_GAP_R 3.0

static double stray_moves(double reach_r)
{
	scene sc;
	make_scene(&sc, 0, 1, 3000, 800, 0.0, 0.0, 0.0, 11);
	size_t last = sc.samples.n - 1;
	double phi = STRAY_GAP_R * sc.r / SPHERE_R, start[3] = {cos(phi), 0.0, -sin(phi)};
	sc.samples.x[last] = (float)(SPHERE_R * start[0]);
	sc.samples.y[last] = (float)(SPHERE_R * start[1]);
	sc.samples.z[last] = (float)(SPHERE_R * start[2]);
	sc.samples.nx[last] = (float)start[0];
	sc.samples.ny[last] = (float)start[1];
	sc.samples.nz[last] = (float)start[2];
	dp_surface_params p;
	dp_surface_params_default(&p);
	p.max_iters = STRAY_ITERS;
	p.slide_reach_r = reach_r;
	dp_cloud out = {0};
	dp_surface_stats st;
	run_stage(tk_cl_context(), &sc, &p, &out, NULL, &st);
	double end[3] = {out.x[last], out.y[last], out.z[last]}, len = 0.0, cosang = 0.0;
	for (int a = 0; a < 3; a++)
		len += end[a] * end[a];
	for (int a = 0; a < 3; a++)
		cosang += start[a] * end[a] / sqrt(len);
	double moved = SPHERE_R * acos(fmin(cosang, 1.0)) / sc.r;
	printf("stray point %.1f r past the rim, slide reach %.1f r: moved %.2f r along the sphere in %d iterations\n",
	       STRAY_GAP_R, reach_r, moved, st.iterations);
	dp_cloud_free(&out);
	free_scene(&sc);
	return moved;
}

static void test_slide_reach(void **state)
{
	(void)state;
	assert_true(stray_moves(0.0) > 1.0);
	assert_true(stray_moves(2.0) < 0.25);
}

/* The inside test: a complete noisy sphere, and one point inside it with
 * no input near, its inner end above it and its normal towards the centre,
 * as points that turned about their inner end end up. Without balls it
 * stays inside; with the samples' balls (centre the inner end, radius the
 * distance to the sample but no more than to the nearest input point, as
 * dp_consolidate makes them) it moves out to the sphere and faces out. */
static double escape_outcome(int with_balls, size_t *escaped)
{
	scene sc;
	make_scene(&sc, 0, 0, 8000, 2000, 0.01 * SPHERE_R, 0.01 * SPHERE_R, 0.03 * SPHERE_R, 7);
	size_t n = sc.samples.n;
	float *radius = malloc(n * sizeof *radius), *d2 = malloc(n * sizeof *d2);
	int *idx = malloc(n * sizeof *idx);
	assert_true(radius && d2 && idx);
	dp_knn knn;
	dp_error err = {0};
	assert_int_equal(dp_knn_build(&knn, sc.input.n, sc.input.x, sc.input.y, sc.input.z, &err), DP_OK);
	assert_int_equal(dp_knn_query(&knn, n, sc.skeleton.x, sc.skeleton.y, sc.skeleton.z, 1, idx, d2, &err), DP_OK);
	dp_knn_free(&knn);
	for (size_t j = 0; j < n; j++) {
		float d[3] = {sc.samples.x[j] - sc.skeleton.x[j], sc.samples.y[j] - sc.skeleton.y[j],
			      sc.samples.z[j] - sc.skeleton.z[j]};
		radius[j] = fminf(sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), sqrtf(d2[j]));
	}
	free(d2);
	free(idx);
	radius[0] = 0.0f;
	sc.samples.x[0] = sc.samples.y[0] = 0.0f, sc.samples.z[0] = (float)(0.4 * SPHERE_R);
	sc.samples.nx[0] = sc.samples.ny[0] = 0.0f, sc.samples.nz[0] = -1.0f;
	sc.skeleton.x[0] = sc.skeleton.y[0] = 0.0f, sc.skeleton.z[0] = (float)(0.8 * SPHERE_R);
	dp_balls balls = {sc.samples.n, sc.skeleton.x, sc.skeleton.y, sc.skeleton.z, radius};
	dp_surface_params p;
	dp_surface_params_default(&p);
	dp_cloud out = {0};
	dp_surface_stats st;
	if (dp_surface(tk_cl_context(), &sc.input, &sc.samples, &sc.skeleton, with_balls ? &balls : NULL, sc.r, &p,
		       &out, NULL, &st, &err) != DP_OK)
		fail_msg("dp_surface: %s", err.message);
	float *q = out.x;
	double dist = fabs(sqrt((double)q[0] * q[0] + (double)out.y[0] * out.y[0] + (double)out.z[0] * out.z[0]) -
			   SPHERE_R);
	double facing = (out.x[0] * out.nx[0] + out.y[0] * out.ny[0] + out.z[0] * out.nz[0]) /
			sqrt((double)out.x[0] * out.x[0] + (double)out.y[0] * out.y[0] + (double)out.z[0] * out.z[0]);
	printf("  %s balls: the inside point ends %.3f R from the sphere, normal . radial %.2f, %zu escapes\n",
	       with_balls ? "with" : "without", dist, facing, st.escaped);
	*escaped = st.escaped;
	if (with_balls)
		assert_true(facing > 0.9);
	free(radius);
	dp_cloud_free(&out);
	free_scene(&sc);
	return dist;
}

static void test_escape(void **state)
{
	(void)state;
	size_t with_count, without_count;
	double with = escape_outcome(1, &with_count), without = escape_outcome(0, &without_count);
	(void)without_count;
	assert_true(without > 0.2 * SPHERE_R);
	assert_true(with < 0.05 * SPHERE_R);
	assert_true(with_count >= 1);
}

/* A plate scanned from one side, whose skeleton has contracted into clumps:
 * the front face z = +PLATE_T/2 of the square |x|, |y| <= 1 is the input and
 * the samples, and each sample's inner end is the node nearest under it of a
 * square lattice on the mid-plane, CLUMP_R r apart (the demo chair's back
 * rest, 4.8 r thick, had holes 2-3 r across in its skeleton sheet). Of the
 * surface points away from the rims (|x|, |y| < 0.8), *inside receives the
 * fraction that end inside the plate, nearer the mid-plane than a quarter of
 * its thickness, and *leaning the fraction whose normal leans more than 30
 * degrees from the plate's: a point over a hole hangs on a node to one side,
 * and without the lateral smoothing of inner ends its dpoint, and with it the
 * normal and the slide, lean into the plate. */
#define PLATE_T 0.125
#define CLUMP_R 3.0
static void plate(double end_smoothing_r, int sheet_points, int max_iters, double *inside_frac, double *leaning_frac,
		  size_t *moved)
{
	dp_rng rng;
	dp_rng_seed(&rng, 31);
	dp_cloud input = {0}, samples = {0}, skeleton = {0}, out = {0};
	dp_error err = {0};
	size_t n_in = 6000, n = 1500;
	assert_int_equal(dp_cloud_alloc(&input, n_in, 0, &err), DP_OK);
	assert_int_equal(dp_cloud_alloc(&samples, n, 1, &err), DP_OK);
	assert_int_equal(dp_cloud_alloc(&skeleton, n, 1, &err), DP_OK);
	for (size_t i = 0; i < n_in; i++) {
		input.x[i] = (float)(2.0 * dp_rng_uniform(&rng) - 1.0);
		input.y[i] = (float)(2.0 * dp_rng_uniform(&rng) - 1.0);
		input.z[i] = (float)(0.5 * PLATE_T + 0.002 * dp_rng_normal(&rng));
	}
	for (size_t i = 0; i < n; i++) {
		samples.x[i] = (float)(2.0 * dp_rng_uniform(&rng) - 1.0);
		samples.y[i] = (float)(2.0 * dp_rng_uniform(&rng) - 1.0);
		samples.z[i] = (float)(0.5 * PLATE_T);
		samples.nx[i] = samples.ny[i] = 0.0f;
		samples.nz[i] = 1.0f;
	}
	double r;
	assert_int_equal(dp_mean_spacing(n, samples.x, samples.y, samples.z, &r, &err), DP_OK);
	double node = CLUMP_R * r;
	for (size_t i = 0; i < n; i++) {
		skeleton.x[i] = (float)(node * floor(samples.x[i] / node + 0.5));
		skeleton.y[i] = (float)(node * floor(samples.y[i] / node + 0.5));
		skeleton.z[i] = 0.0f;
		skeleton.nx[i] = skeleton.ny[i] = 0.0f;
		skeleton.nz[i] = 1.0f;
	}
	dp_surface_params p;
	dp_surface_params_default(&p);
	p.end_smoothing_r = end_smoothing_r;
	p.sheet_points = sheet_points;
	if (max_iters >= 0)
		p.max_iters = max_iters;
	dp_surface_stats st;
	if (dp_surface(tk_cl_context(), &input, &samples, &skeleton, NULL, r, &p, &out, NULL, &st, &err) != DP_OK)
		fail_msg("dp_surface: %s", err.message);
	size_t middle = 0, inside = 0, leaning = 0;
	for (size_t i = 0; i < out.n; i++) {
		if (!(fabsf(out.x[i]) < 0.8f && fabsf(out.y[i]) < 0.8f))
			continue;
		middle++;
		inside += fabsf(out.z[i]) < 0.25 * PLATE_T;
		leaning += fabsf(out.nz[i]) < 0.866f;
	}
	assert_true(middle > n / 4);
	*inside_frac = (double)inside / (double)middle;
	*leaning_frac = (double)leaning / (double)middle;
	*moved = st.sheet_points;
	printf("  plate %.1f r thick, clumps %.0f r apart, end smoothing %.1f r, sheet step %s: of %zu points %zu "
	       "inside, %zu leaning, %zu moved across the sheet; %d iterations\n", PLATE_T / r, CLUMP_R,
	       end_smoothing_r, sheet_points ? "on" : "off", middle, inside, leaning, st.sheet_points, st.iterations);
	dp_cloud_free(&input);
	dp_cloud_free(&samples);
	dp_cloud_free(&skeleton);
	dp_cloud_free(&out);
}

/* Measured: 2.7% inside and 9.1% leaning without the smoothing, 0.5% and
 * 1.2% with it; the scene must show the failure for the check to mean
 * anything. */
static void test_end_smoothing(void **state)
{
	(void)state;
	double inside_off, leaning_off, inside_on, leaning_on;
	size_t moved;
	/* the smoothing alone: the sheet step would move the points counted
	 * inside out to the plate's faces */
	plate(0.0, 0, -1, &inside_off, &leaning_off, &moved);
	plate(2.0, 0, -1, &inside_on, &leaning_on, &moved);
	assert_true(leaning_off > 0.05);
	assert_true(inside_off > 0.015);
	assert_true(inside_on < 0.015);
	assert_true(leaning_on < 0.03);
}

/* The same plate without the smoothing, with the sheet step of the stage's
 * end (host/stages/sheet_points.h): the points stranded in the mid-plane
 * leave it. */
static void test_sheet_points(void **state)
{
	(void)state;
	double inside, leaning;
	size_t moved;
	plate(0.0, 1, -1, &inside, &leaning, &moved);
	assert_true(moved > 0);
	assert_true(inside < 0.005);
	/* with no iteration there is no data weight or spacing to read: the
	 * step does nothing */
	plate(0.0, 1, 0, &inside, &leaning, &moved);
	assert_int_equal(moved, 0);
}

/* Bad arguments fail with one message, without touching the output. */
static void test_errors(void **state)
{
	(void)state;
	scene sc;
	make_scene(&sc, 0, 0, 200, 50, 0.0, 0.0, 0.0, 5);
	dp_cloud out = {0};
	dp_error err = {0};
	dp_context *ctx = tk_ref_context();
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, 0.0, NULL, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	assert_non_null(strstr(err.message, "surface"));
	dp_cloud empty = {0};
	assert_int_equal(dp_surface(ctx, &empty, &sc.samples, &sc.skeleton, NULL, sc.r, NULL, &out, NULL, NULL, &err),
			 DP_ERR_EMPTY);
	sc.skeleton.n--;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, NULL, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	sc.skeleton.n++;
	dp_surface_params bad;
	dp_surface_params_default(&bad);
	bad.slide_reach_r = -1.0;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	bad.slide_reach_r = NAN;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	dp_surface_params_default(&bad);
	bad.escape_margin_r = -1.0;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	float radius[2] = {1.0f, NAN};
	dp_balls too_many = {sc.samples.n + 1, sc.samples.x, sc.samples.y, sc.samples.z, sc.samples.x};
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, &too_many, sc.r, NULL, &out, NULL, NULL,
				    &err),
			 DP_ERR_ARG);
	dp_balls no_arrays = {2, NULL, NULL, NULL, NULL};
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, &no_arrays, sc.r, NULL, &out, NULL, NULL,
				    &err),
			 DP_ERR_ARG);
	bad.escape_margin_r = NAN;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	dp_surface_params_default(&bad);
	bad.end_smoothing_r = -1.0;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	bad.end_smoothing_r = NAN;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	bad.end_smoothing_r = INFINITY;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	dp_surface_params_default(&bad);
	bad.min_move_r = -0.1;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	bad.min_move_r = NAN;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	bad.min_move_r = INFINITY;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, &bad, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	dp_balls nan_ball = {2, sc.samples.x, sc.samples.y, sc.samples.z, radius};
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, &nan_ball, sc.r, NULL, &out, NULL, NULL,
				    &err),
			 DP_ERR_ARG);
	assert_non_null(strstr(err.message, "ball 1"));
	sc.samples.x[3] = NAN;
	assert_int_equal(dp_surface(ctx, &sc.input, &sc.samples, &sc.skeleton, NULL, sc.r, NULL, &out, NULL, NULL, &err),
			 DP_ERR_ARG);
	assert_null(out.x);
	free_scene(&sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_sphere_complete),
		cmocka_unit_test(test_held_orientation),  cmocka_unit_test(test_sphere_one_sided),
		cmocka_unit_test(test_torus_one_sided),  cmocka_unit_test(test_backends_agree),
		cmocka_unit_test(test_priors),           cmocka_unit_test(test_slide_reach),
		cmocka_unit_test(test_escape),           cmocka_unit_test(test_end_smoothing),
		cmocka_unit_test(test_sheet_points),     cmocka_unit_test(test_errors),
	};
	int rc = cmocka_run_group_tests(tests, NULL, NULL);
	tk_teardown_contexts(NULL);
	return rc;
}
