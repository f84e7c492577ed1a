/* Coarse-to-fine deep points: the level counts, the midpoint insertion on
 * shapes with a known answer, and the whole pipeline growing a coarse level
 * past the input's own count (upsampling) with every output in step. */
#include "testkit.h"

#include "knn/knn.h"
#include "stages/refine.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SPHERE_POINTS 600
/* The one-view torus filled from the subset lies no farther from the torus
 * on average than the same run from every deep point (measured: 0.0018
 * against 0.0021 of its size, 95th percentile 0.0047 against 0.0060). */
#define FILL_ACCURACY_RATIO 1.0

static void test_levels(void **state)
{
	(void)state;
	size_t c[DP_MAX_LEVELS];
	/* no refinement below the coarse count, or when it is off */
	assert_int_equal(dp_refine_levels(4000, 2000, 4.0, c, DP_MAX_LEVELS), 1);
	assert_int_equal(c[0], 2000);
	assert_int_equal(dp_refine_levels(0, 9000, 4.0, c, DP_MAX_LEVELS), 1);
	/* 1000 -> 32000 at factor 4: three equal steps of 32^(1/3) */
	assert_int_equal(dp_refine_levels(1000, 32000, 4.0, c, DP_MAX_LEVELS), 4);
	assert_int_equal(c[0], 1000);
	assert_int_equal(c[3], 32000);
	for (int l = 1; l < 4; l++)
		assert_true(fabs((double)c[l] / (double)c[l - 1] - cbrt(32.0)) < 0.01);
	/* exactly one factor: one step */
	assert_int_equal(dp_refine_levels(1000, 4000, 4.0, c, DP_MAX_LEVELS), 2);
}

/* n Fibonacci points on the unit sphere with outward normals, and inner ends
 * at half the radius. */
static void fibonacci_sphere(size_t n, size_t cap, dp_cloud *s, dp_cloud *k)
{
	dp_error err = {0};
	if (dp_cloud_alloc(s, cap, 1, &err) != DP_OK || dp_cloud_alloc(k, cap, 1, &err) != DP_OK)
		fail_msg("%s", err.message);
	double golden = M_PI * (3.0 - sqrt(5.0));
	for (size_t i = 0; i < n; i++) {
		double z = 1.0 - 2.0 * ((double)i + 0.5) / (double)n, rho = sqrt(1.0 - z * z), a = golden * (double)i;
		s->x[i] = s->nx[i] = (float)(rho * cos(a));
		s->y[i] = s->ny[i] = (float)(rho * sin(a));
		s->z[i] = s->nz[i] = (float)z;
		k->x[i] = 0.5f * s->x[i], k->y[i] = 0.5f * s->y[i], k->z[i] = 0.5f * s->z[i];
		k->nx[i] = s->nx[i], k->ny[i] = s->ny[i], k->nz[i] = s->nz[i];
	}
	s->n = k->n = n;
}

/* Insertion on a sphere: the requested count, new points on the sphere well
 * within the spacing (the Hermite lift), inner ends on the inner sphere, no
 * two points closer than the gap, old rows untouched. */
static void test_insert_sphere(void **state)
{
	(void)state;
	size_t target = 4 * SPHERE_POINTS;
	dp_cloud s = {0}, k = {0};
	fibonacci_sphere(SPHERE_POINTS, target, &s, &k);
	float x0 = s.x[17], z0 = k.z[17];
	dp_error err = {0};
	double r = 0.0;
	assert_int_equal(dp_mean_spacing(s.n, s.x, s.y, s.z, &r, &err), DP_OK);
	size_t added = 0;
	if (dp_refine_insert(&s, &k, target, &added, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(s.n, target);
	assert_int_equal(k.n, target);
	assert_int_equal(added, target - SPHERE_POINTS);
	assert_true(s.x[17] == x0 && k.z[17] == z0);
	double worst = 0.0, worst_inner = 0.0;
	for (size_t i = SPHERE_POINTS; i < s.n; i++) {
		double d = sqrt((double)s.x[i] * s.x[i] + (double)s.y[i] * s.y[i] + (double)s.z[i] * s.z[i]);
		double di = sqrt((double)k.x[i] * k.x[i] + (double)k.y[i] * k.y[i] + (double)k.z[i] * k.z[i]);
		double dot = (s.x[i] * s.nx[i] + s.y[i] * s.ny[i] + s.z[i] * s.nz[i]) / d;
		worst = fmax(worst, fabs(d - 1.0));
		worst_inner = fmax(worst_inner, fabs(di - 0.5));
		assert_true(dot > 0.99);
	}
	printf("sphere: r %.4f, new points at most %.5f off the sphere, inner ends %.5f off theirs\n", r, worst,
	       worst_inner);
	/* a plain chord midpoint would sit up to r²/8 inside; the lift leaves a
	 * fraction of that */
	assert_true(worst < 0.02 * r);
	assert_true(worst_inner < 0.1 * r);
	double spacing = 0.0;
	assert_int_equal(dp_mean_spacing(s.n, s.x, s.y, s.z, &spacing, &err), DP_OK);
	dp_knn knn = {0};
	int idx[2];
	float d2[2];
	assert_int_equal(dp_knn_build(&knn, s.n, s.x, s.y, s.z, &err), DP_OK);
	for (size_t i = 0; i < s.n; i++) {
		assert_int_equal(dp_knn_query(&knn, 1, &s.x[i], &s.y[i], &s.z[i], 2, idx, d2, &err), DP_OK);
		assert_true(sqrtf(d2[1]) >= 0.4f * (float)spacing * 0.999f);
	}
	dp_knn_free(&knn);
	dp_cloud_free(&s);
	dp_cloud_free(&k);
}

/* Inserted points take an existing inner end, never a blend: a ball's
 * skeleton is one spot, and a straggler a few r off it must not grow a
 * bridge of midpoints towards it. The straggler is point 0's, the first end
 * of each of its edges; every new point's normal line passes through the
 * centre, so the end nearer it is always the other one. */
static void test_insert_keeps_skeleton_spots(void **state)
{
	(void)state;
	size_t target = 4 * SPHERE_POINTS;
	dp_cloud s = {0}, k = {0};
	fibonacci_sphere(SPHERE_POINTS, target, &s, &k);
	for (size_t i = 0; i < s.n; i++)
		k.x[i] = k.y[i] = k.z[i] = 0.0f;
	/* the straggler, under point 0 */
	k.x[0] = 0.3f * s.x[0], k.y[0] = 0.3f * s.y[0], k.z[0] = 0.3f * s.z[0];
	dp_error err = {0};
	size_t added = 0;
	if (dp_refine_insert(&s, &k, target, &added, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t at_straggler = 0;
	for (size_t i = SPHERE_POINTS; i < k.n; i++) {
		int centre = k.x[i] == 0.0f && k.y[i] == 0.0f && k.z[i] == 0.0f;
		int straggler = k.x[i] == k.x[0] && k.y[i] == k.y[0] && k.z[i] == k.z[0];
		assert_true(centre || straggler);
		at_straggler += straggler;
	}
	printf("%zu of %zu inserted points took the straggler\n", at_straggler, added);
	assert_int_equal(at_straggler, 0);
	dp_cloud_free(&s);
	dp_cloud_free(&k);
}

/* Growth beyond one subdivision (about 4x) takes several passes, each with
 * its gap test at the spacing it starts from: 8x must reach its target. */
static void test_insert_many_passes(void **state)
{
	(void)state;
	size_t n = SPHERE_POINTS / 2, target = 8 * n;
	dp_cloud s = {0}, k = {0};
	fibonacci_sphere(n, target, &s, &k);
	dp_error err = {0};
	size_t added = 0;
	if (dp_refine_insert(&s, &k, target, &added, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(s.n, target);
	assert_int_equal(added, target - n);
	dp_cloud_free(&s);
	dp_cloud_free(&k);
}

/* Two sheets 0.6 r apart facing away from each other (the two sides of a
 * thin part): insertion splits edges within each sheet, never across, so no
 * new point lands between them. */
static void test_insert_thin(void **state)
{
	(void)state;
	const int side = 16;
	size_t n = 2 * (size_t)side * side, target = 3 * n;
	dp_cloud s = {0}, k = {0};
	dp_error err = {0};
	if (dp_cloud_alloc(&s, target, 1, &err) != DP_OK || dp_cloud_alloc(&k, target, 1, &err) != DP_OK)
		fail_msg("%s", err.message);
	const float gap = 0.6f;
	size_t i = 0;
	for (int sheet = 0; sheet < 2; sheet++)
		for (int a = 0; a < side; a++)
			for (int b = 0; b < side; b++, i++) {
				float up = sheet ? 1.0f : -1.0f;
				s.x[i] = (float)a, s.y[i] = (float)b, s.z[i] = 0.5f * gap * up;
				s.nx[i] = s.ny[i] = 0.0f, s.nz[i] = up;
				k.x[i] = s.x[i], k.y[i] = s.y[i], k.z[i] = 0.0f;
				k.nx[i] = k.ny[i] = 0.0f, k.nz[i] = up;
			}
	s.n = k.n = n;
	size_t added = 0;
	if (dp_refine_insert(&s, &k, target, &added, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_true(added > n);
	for (size_t j = n; j < s.n; j++)
		assert_true(fabsf(fabsf(s.z[j]) - 0.5f * gap) < 1e-5f && s.nz[j] * s.z[j] > 0.0f);
	dp_cloud_free(&s);
	dp_cloud_free(&k);
}

/* The pipeline on a one-view scan of a sphere asked for more deep points
 * than the scan has: coarse level, refined levels, every output the same
 * length, the completed sphere covered and every normal outward along its
 * deep point. */
static void test_upsample_pipeline(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud mesh = {0}, scan = {0};
	tk_scan_shape("sphere", 1, 48, 0.002, 1, NULL, &mesh, &scan);
	/* the default coarse count is above the scan's: the coarse level takes
	 * every distinct input position */
	dp_params p;
	dp_params_default(&p);
	p.wlop.samples = 2 * scan.n;
	dp_result res = {0};
	if (dp_consolidate(tk_cl_context(), &scan, &p, &res, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t n = p.wlop.samples;
	tk_assert_rows_in_step(&res, n);
	assert_true(res.wlop.n <= scan.n && res.wlop.n > scan.n / 2);
	assert_true(res.levels >= 2);
	assert_int_equal(res.level[res.levels - 1].points, n);
	size_t against = 0;
	for (size_t i = 0; i < n; i++) {
		float m[3] = {res.surface.x[i] - res.skeleton.x[i], res.surface.y[i] - res.skeleton.y[i],
			      res.surface.z[i] - res.skeleton.z[i]};
		assert_true(isfinite(res.eta[i]) && res.eta[i] >= 1.0f);
		against += m[0] * res.surface.nx[i] + m[1] * res.surface.ny[i] + m[2] * res.surface.nz[i] < 0.0f;
	}
	dp_eval_result e;
	if (dp_eval(&mesh, &res.surface, NULL, &e, &err) != DP_OK)
		fail_msg("%s", err.message);
	printf("one-view sphere, %zu raw -> %zu deep points in %d levels: coverage %.3f, flipped %.4f, "
	       "%zu normals against their deep point\n",
	       scan.n, n, res.levels, e.coverage, e.normal_flipped, against);
	assert_int_equal(against, 0);
	assert_true(e.coverage >= 0.9);
	assert_true(e.normal_flipped <= 0.01);
	dp_result_free(&res);
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
}

/* Farthest-point subsets: m distinct rows in ascending order, and spread:
 * no point of the set lies farther from the subset than the subset's own
 * closest pair (what picking the farthest point each time guarantees), on
 * a cloud with a dense clump that an even subset must thin. */
static void test_subset_spread(void **state)
{
	(void)state;
	dp_error err = {0};
	enum { N = 900, M = 120 };
	float x[N], y[N], z[N];
	dp_rng rng;
	dp_rng_seed(&rng, 5);
	for (size_t i = 0; i < N; i++) {
		/* a third in a clump a tenth of the cube's size */
		double scale = i % 3 == 0 ? 0.1 : 1.0;
		x[i] = (float)(scale * dp_rng_uniform(&rng));
		y[i] = (float)(scale * dp_rng_uniform(&rng));
		z[i] = (float)(scale * dp_rng_uniform(&rng));
	}
	uint32_t keep[M];
	assert_int_equal(dp_refine_subset(N, x, y, z, M, keep, &err), DP_OK);
	double closest = INFINITY, farthest = 0.0;
	size_t in_clump = 0;
	for (size_t a = 0; a < M; a++) {
		assert_true(keep[a] < N);
		if (a > 0)
			assert_true(keep[a] > keep[a - 1]);
		in_clump += keep[a] % 3 == 0 && x[keep[a]] < 0.1f && y[keep[a]] < 0.1f && z[keep[a]] < 0.1f;
		for (size_t b = 0; b < a; b++) {
			double dx = x[keep[a]] - x[keep[b]], dy = y[keep[a]] - y[keep[b]], dz = z[keep[a]] - z[keep[b]];
			closest = fmin(closest, sqrt(dx * dx + dy * dy + dz * dz));
		}
	}
	for (size_t i = 0; i < N; i++) {
		double near = INFINITY;
		for (size_t a = 0; a < M; a++) {
			double dx = x[i] - x[keep[a]], dy = y[i] - y[keep[a]], dz = z[i] - z[keep[a]];
			near = fmin(near, sqrt(dx * dx + dy * dy + dz * dz));
		}
		farthest = fmax(farthest, near);
	}
	printf("subset of %d from %d: closest pair %.4f, farthest point from it %.4f, %zu in the clump\n", M, N,
	       closest, farthest, in_clump);
	assert_true(farthest <= closest);
	/* the clump holds a third of the points but a thousandth of the volume */
	assert_true(in_clump <= 3);
	uint32_t all[N];
	assert_int_equal(dp_refine_subset(N, x, y, z, N, all, &err), DP_OK);
	for (size_t i = 0; i < N; i++)
		assert_int_equal(all[i], i);
	assert_int_equal(dp_refine_subset(M, x, y, z, N, all, &err), DP_ERR_ARG);
}

/* The specification of dp_refine_subset: from point 0, each next pick the
 * point farthest from those picked (squared distances in double, ties to the
 * lower index), found by scanning every point for every pick. */
static void plain_subset(size_t n, const float *x, const float *y, const float *z, size_t m, uint32_t *keep)
{
	double *near = malloc(n * sizeof *near);
	assert_non_null(near);
	for (size_t i = 0; i < n; i++)
		near[i] = INFINITY;
	size_t pick = 0;
	for (size_t k = 0; k < m; k++) {
		keep[k] = (uint32_t)pick;
		near[pick] = -1.0;
		size_t next = pick;
		double far = -1.0;
		for (size_t i = 0; i < n; i++) {
			if (near[i] < 0.0)
				continue;
			double dx = (double)x[i] - x[pick], dy = (double)y[i] - y[pick], dz = (double)z[i] - z[pick];
			near[i] = fmin(near[i], dx * dx + dy * dy + dz * dz);
			if (near[i] > far) {
				far = near[i];
				next = i;
			}
		}
		pick = next;
	}
	free(near);
	for (size_t a = 1; a < m; a++)
		for (size_t b = a; b > 0 && keep[b - 1] > keep[b]; b--) {
			uint32_t t = keep[b];
			keep[b] = keep[b - 1];
			keep[b - 1] = t;
		}
}

/* The kd-tree and heap pick exactly what the plain scan picks: on a clump,
 * a spread, exact duplicates (equal distances: the tie rule decides), a grid
 * (many equal distances) and coordinates whose squares leave a float's range
 * (every point searched). */
static void test_subset_matches_plain(void **state)
{
	(void)state;
	dp_error err = {0};
	enum { N = 1500 };
	static float x[N], y[N], z[N];
	static uint32_t fast[N], plain[N];
	const size_t counts[] = {1, 2, 7, 120, 700, N};
	for (int shape = 0; shape < 3; shape++) {
		dp_rng rng;
		dp_rng_seed(&rng, 11 + (uint64_t)shape);
		for (size_t i = 0; i < N; i++) {
			double scale = i % 3 == 0 ? 0.1 : 1.0, big = shape == 2 ? 1e25 : 1.0;
			if (shape == 1) {
				/* a 10 x 10 x 15 grid */
				x[i] = (float)(i % 10), y[i] = (float)(i / 10 % 10), z[i] = (float)(i / 100);
			} else if (i % 7 == 6) {
				x[i] = x[i - 1], y[i] = y[i - 1], z[i] = z[i - 1];
			} else {
				x[i] = (float)(big * scale * dp_rng_uniform(&rng));
				y[i] = (float)(big * scale * dp_rng_uniform(&rng));
				z[i] = (float)(big * scale * dp_rng_uniform(&rng));
			}
		}
		for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
			size_t m = counts[c];
			assert_int_equal(dp_refine_subset(N, x, y, z, m, fast, &err), DP_OK);
			plain_subset(N, x, y, z, m, plain);
			for (size_t k = 0; k < m; k++)
				assert_int_equal(fast[k], plain[k]);
		}
	}
}

/* Fewer deep points than the coarse level: the pipeline runs at the coarse
 * count and keeps an even subset, rows of every output in step with a run
 * asked for the coarse count itself. On the demo chair at 1000 (two views of
 * 128 x 128 rays, 4452 points), run at 1000, the samples' normals came out
 * 98% inwards and the surface 0.034 diagonals off on average (0.14 at the
 * 95th percentile): parts a sample or two thick have no normal of their
 * own. */
static void test_subset_pipeline(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud mesh = {0}, scan = {0};
	tk_scan_shape("chair", 2, 128, 0.003, 1, NULL, &mesh, &scan);
	dp_params p;
	dp_params_default(&p);
	size_t coarse = p.refine.coarse_samples, m = 1000;
	dp_result full = {0}, few = {0};
	p.wlop.samples = coarse;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &full, &err) != DP_OK)
		fail_msg("%s", err.message);
	p.wlop.samples = m;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &few, &err) != DP_OK)
		fail_msg("%s", err.message);
	tk_assert_rows_in_step(&few, m);
	assert_int_equal(few.wlop.n, m);
	assert_int_equal(few.anchors.n, m);
	assert_int_equal(few.ran_with, coarse);
	assert_int_equal(full.ran_with, coarse);
	/* every kept row is a row of the full run, the same in every output */
	size_t found = 0;
	for (size_t i = 0, j = 0; i < m; i++) {
		while (j < coarse && (full.surface.x[j] != few.surface.x[i] || full.surface.y[j] != few.surface.y[i] ||
				      full.surface.z[j] != few.surface.z[i]))
			j++;
		if (j == coarse)
			break;
		found += full.skeleton.x[j] == few.skeleton.x[i] && full.wlop.x[j] == few.wlop.x[i] &&
			 full.anchors.z[j] == few.anchors.z[i] && full.eta[j] == few.eta[i] &&
			 full.settled_by[j] == few.settled_by[i];
	}
	assert_int_equal(found, m);
	dp_eval_result ew, es;
	if (dp_eval(&mesh, &few.wlop, NULL, &ew, &err) != DP_OK || dp_eval(&mesh, &few.surface, NULL, &es, &err) != DP_OK)
		fail_msg("%s", err.message);
	printf("chair at %zu of %zu: samples flipped %.4f; surface coverage %.3f, flipped %.4f, accuracy mean %.4f "
	       "p95 %.4f\n", m, coarse, ew.normal_flipped, es.coverage, es.normal_flipped, es.accuracy_mean,
	       es.accuracy_p95);
	assert_true(ew.normal_flipped < 0.05);
	assert_true(es.normal_flipped < 0.05);
	assert_true(es.accuracy_p95 < 0.02);
	assert_true(es.coverage > 0.95);
	dp_result_free(&full);
	dp_result_free(&few);
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
}

/* The coarse level of a one-sided scan with nothing thin goes down to
 * coarse_min (doubling): a one-view sphere fills its far side from there
 * (bench_completion at 2000 / 8000 / 32000: 0.959 / 0.997 / 0.984 covered
 * from 4000, 1.000 each now). A one-view torus (its tube 4 r across at
 * 1000) and a complete sphere keep coarse_samples. */
static void test_coarser_level(void **state)
{
	(void)state;
	const struct {
		const char *shape;
		int views, res;
		int coarser;
	} cases[] = {{"sphere", 1, 126, 1}, {"torus", 1, 160, 0}, {"sphere", 6, 48, 0}};
	for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		dp_error err = {0};
		dp_cloud mesh = {0}, scan = {0};
		tk_scan_shape(cases[c].shape, cases[c].views, cases[c].res, 0.003, 1, NULL, &mesh, &scan);
		dp_params p;
		dp_params_default(&p);
		dp_result res = {0};
		if (dp_consolidate(tk_cl_context(), &scan, &p, &res, &err) != DP_OK)
			fail_msg("%s", err.message);
		dp_eval_result e;
		if (dp_eval(&mesh, &res.surface, NULL, &e, &err) != DP_OK)
			fail_msg("%s", err.message);
		printf("%s, %d view%s, %zu points -> %zu deep points from a coarse level of %zu: coverage %.3f, "
		       "accuracy mean %.4f\n", cases[c].shape, cases[c].views, cases[c].views == 1 ? "" : "s", scan.n,
		       res.surface.n, res.level[0].points, e.coverage, e.accuracy_mean);
		size_t coarse = scan.n < p.refine.coarse_samples ? scan.n : p.refine.coarse_samples;
		if (cases[c].coarser) {
			assert_true(res.level[0].points < coarse);
			assert_true(res.level[0].points >= p.refine.coarse_min);
			assert_true(e.coverage >= 0.99);
		} else {
			/* WLOP ran at the coarse level; a one-sided scan's surface
			 * started on fill_samples of it (test_fill_level), never a
			 * complete one's */
			size_t ran = res.filled_from ? res.filled_from : res.level[0].points;
			assert_true(ran >= coarse - 1); /* distinct positions */
			if (cases[c].views > 1)
				assert_int_equal(res.filled_from, 0);
		}
		if (c == 0) {
			/* a level of a few points has no surface to grow from */
			dp_result bad = {0};
			p.refine.coarse_min = 4;
			assert_int_equal(dp_consolidate(tk_cl_context(), &scan, &p, &bad, &err), DP_ERR_ARG);
		}
		dp_result_free(&res);
		dp_cloud_free(&mesh);
		dp_cloud_free(&scan);
	}
}

/* The rows of `sub` are rows of `all` in ascending order, every column the
 * same (an even subset keeps rows, it does not move them); row[j] receives
 * the row of `all` that row j of `sub` is. */
static void assert_rows_of(const dp_cloud *sub, const dp_cloud *all, size_t *row)
{
	size_t k = 0;
	for (size_t j = 0; j < sub->n; j++, k++) {
		while (k < all->n && (all->x[k] != sub->x[j] || all->y[k] != sub->y[j] || all->z[k] != sub->z[j]))
			k++;
		assert_true(k < all->n);
		assert_true(all->nx[k] == sub->nx[j] && all->ny[k] == sub->ny[j] && all->nz[k] == sub->nz[j]);
		row[j] = k;
	}
}

/* `fill`'s samples, anchors and settle ways are rows of `off`'s, the same
 * rows of each. */
static void assert_same_rows(const dp_result *fill, const dp_result *off)
{
	assert_int_equal(fill->anchors.n, fill->wlop.n);
	size_t *row = malloc(fill->wlop.n * sizeof *row), *arow = malloc(fill->wlop.n * sizeof *arow);
	assert_non_null(row);
	assert_non_null(arow);
	assert_rows_of(&fill->wlop, &off->wlop, row);
	assert_rows_of(&fill->anchors, &off->anchors, arow);
	for (size_t j = 0; j < fill->wlop.n; j++) {
		assert_int_equal(row[j], arow[j]);
		assert_int_equal(fill->settled_by[j], off->settled_by[row[j]]);
	}
	free(row);
	free(arow);
}

/* A one-sided scan with a thin part (a one-view torus, its tube 4 r across
 * at 1000) keeps the coarse level for WLOP, sinking and the skeleton, and
 * its surface stage starts on fill_samples of those deep points: the same
 * rows of the samples and anchors, the count asked for in the end; kept
 * for a count below the coarse level, the samples and anchors are the
 * subset's rows among those kept. A scan from every side (the complete
 * sphere of test_coarser_level) never does. */
static void test_fill_level(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_cloud mesh = {0}, scan = {0};
	tk_scan_shape("torus", 1, 160, 0.003, 1, NULL, &mesh, &scan);
	dp_params p;
	dp_params_default(&p);
	dp_result fill = {0}, off = {0};
	if (dp_consolidate(tk_cl_context(), &scan, &p, &fill, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t m = p.refine.fill_samples;
	p.refine.fill_samples = 0;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &off, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_eval_result ef, eo;
	if (dp_eval(&mesh, &fill.surface, NULL, &ef, &err) != DP_OK || dp_eval(&mesh, &off.surface, NULL, &eo, &err) != DP_OK)
		fail_msg("%s", err.message);
	printf("one-view torus, %zu points -> %zu deep points: from %zu of %zu coverage %.3f, accuracy mean %.4f p95 "
	       "%.4f, flipped %.4f; from all %zu coverage %.3f, accuracy mean %.4f p95 %.4f, flipped %.4f\n", scan.n,
	       fill.surface.n, fill.level[0].points, fill.filled_from, ef.coverage, ef.accuracy_mean, ef.accuracy_p95,
	       ef.normal_flipped, off.level[0].points, eo.coverage, eo.accuracy_mean, eo.accuracy_p95,
	       eo.normal_flipped);
	assert_int_equal(off.filled_from, 0);
	assert_int_equal(fill.filled_from, off.level[0].points);
	assert_int_equal(fill.level[0].points, m);
	assert_int_equal(fill.wlop.n, m);
	assert_int_equal(fill.anchors.n, m);
	assert_int_equal(fill.surface.n, off.surface.n);
	assert_same_rows(&fill, &off);
	/* the sinking's own outcome, whichever anchors are kept */
	assert_int_equal(fill.sink_stats.converged, off.sink_stats.converged);
	assert_true(fill.sink_r == off.level[0].r && fill.level[0].r > fill.sink_r);
	assert_true(ef.coverage >= 0.99);
	assert_true(ef.normal_flipped <= 0.01);
	assert_true(ef.accuracy_mean <= FILL_ACCURACY_RATIO * eo.accuracy_mean);
	/* 1000 kept: of the 4000 deep points the subset's 2000 rows come first */
	dp_result few = {0};
	p.refine.fill_samples = m;
	p.wlop.samples = 1000;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &few, &err) != DP_OK)
		fail_msg("%s", err.message);
	printf("1000 kept: %zu samples and anchors among them\n", few.wlop.n);
	assert_int_equal(few.surface.n, 1000);
	assert_int_equal(few.filled_from, fill.filled_from);
	assert_true(few.wlop.n > 0 && few.wlop.n < few.surface.n);
	assert_same_rows(&few, &off);
	assert_int_equal(few.sink_stats.converged, off.sink_stats.converged);
	const dp_sink_stats *ss = &few.sink_stats;
	assert_int_equal(ss->settled_front + ss->settled_medial + ss->settled_width + ss->settled_slow +
				 ss->settled_flat + ss->unsettled,
			 few.anchors.n);
	dp_result_free(&few);
	dp_result_free(&fill);
	dp_result_free(&off);
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_levels),
		cmocka_unit_test(test_insert_sphere),
		cmocka_unit_test(test_insert_keeps_skeleton_spots),
		cmocka_unit_test(test_insert_many_passes),
		cmocka_unit_test(test_insert_thin),
		cmocka_unit_test(test_upsample_pipeline),
		cmocka_unit_test(test_subset_spread),
		cmocka_unit_test(test_subset_matches_plain),
		cmocka_unit_test(test_subset_pipeline),
		cmocka_unit_test(test_coarser_level),
		cmocka_unit_test(test_fill_level),
	};
	return cmocka_run_group_tests(tests, NULL, tk_teardown_contexts);
}
