/* Completion quality at the library's defaults, as JSON lines: the numbers
 * by which coarse-to-fine deep points, deep-point orientation and same-sided
 * neighbourhoods are judged (README "Results measured here"), with the OpenCL
 * backend only: this measures quality, bench_stages compares the backends.
 *
 *   bench_completion [--case NAME,...] [--samples M,...] [--data DIR] [--device D] [--seed S] [--save DIR]
 *                    [--coarse N] [--surface-iters N] [--wlop-seed S] [--sink-depth 0|1] [--even-rounds N]
 *                    [--silhouette 0|1] [--face-scanner 0|1]
 *
 * Cases (all by default):
 *   sphere   one view of the built-in sphere at each --samples count (default
 *            2000,8000,32000): coverage, and the surface stage's seconds and
 *            pair evaluations per level, so its growth with the count shows;
 *   bunny1, bunny2  the real Stanford bunny, bun000 alone and bun000 +
 *            bun180 in the ground-truth frame, at the default deep-point count;
 *   heldout  the bunny's other scans, which no default was chosen on: bun090,
 *            bun180 and bun270 alone, and bun090 + bun270 (two opposite
 *            views, as bunny2, turned a quarter round);
 *   chair    the demo's chair (two views, 256 x 256 rays, noise 0.003), and
 *            its legs: whether each stays a tube in the surface and a curve
 *            in the skeleton (legs below); and its seat, scanned from above
 *            only: how deep its top's samples sank, near the rim and in the
 *            middle, against its half thickness;
 *   rods     the built-in thin parts (rods under 3 r thick) from two sides;
 *   statue   the paper's Fig. 12 statue at the defaults: stage times and caps;
 *   lamppost pcl/lamppost.pcd, a pole a few r thick: how far the surface and
 *            the skeleton lie from the data (median and 90th percentile, in
 *            r), which a thin part turned into a cloud makes many r.
 * Every case with a ground-truth mesh also prints sink_depth: per way of
 * settling (dp_settle), how far the coarse level's anchors (a one-sided
 * scan's: those of the fill level, dp_refine_params.fill_samples) lie from
 * the mesh point nearest their samples against the true depth there, the radius of
 * the largest ball inside the mesh that touches it at that point (the medial
 * ball, which a perfect anchor would centre; read two ways that bracket it,
 * see true_depth): medians in r of the distance, the true depth and the
 * per-anchor ratio (1: on the medial axis; above: sunk past it), and the
 * fraction nearer to another part of the mesh than to their own point by more
 * than the slack (past the axis whatever the normals say), and the count that
 * lie outside the mesh by its winding number (sunk through a face that was
 * never scanned, or from a sample whose normal came out inwards): the
 * skeleton points they become hang completed surface around themselves, off
 * the body.
 * --sink-depth 0 leaves sink_depth out (a quarter to a half of a case's time).
 * --surface-iters caps the coarse level's surface iterations instead of the
 * default: completion spreads with the iterations and so does the error of
 * what it completes, and a sweep of this shows the trade (README "Results
 * measured here").
 * --silhouette 0 lets completed points leave the scan's outline
 * (dp_surface_params.silhouette), to compare; every line prints the axis
 * found (all zero: none), the grazing fraction and how many were held.
 * --face-scanner 0 leaves normals facing away from a one-sided scan's
 * scanner as they are (dp_surface_params.face_scanner); every line prints
 * the direction towards the scanner (all zero: none) and how many normals
 * were turned, samples' before sinking and held points' in the surface stage.
 * --even-rounds sets dp_refine_params.even_rounds (default 0, off), whose
 * trade of even spacing against flips and accuracy these numbers show.
 * Real-data cases are skipped with a message when the data folder is absent.
 * Lengths are in bounding-box diagonals of the ground truth unless named _r. */
#include "dpoints_tools.h"
#include "core/eig3.h"
#include "knn/kdtree.h"
#include "knn/knn.h"
#include "tools/mesh.h"
#include "tools/shapes.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_SAMPLES "2000,8000,32000"
#define BUNNY_MAX_VIEWS 2
#define MAX_SIZES 8
#define NOISE 0.003
/* One-view sphere scans keep about 4 raw points per deep point. */
#define SPHERE_RES_PER_SQRT_SAMPLE 4.13
#define CHAIR_VIEWS 2
#define CHAIR_RES 256

typedef struct options {
	const char *cases;
	size_t samples[MAX_SIZES];
	int nsizes;
	const char *data;
	const char *device;
	size_t coarse;    /* --coarse: the coarse level's count instead of the default */
	int surface_iters; /* --surface-iters: the surface stage's cap, or -1 for the default */
	int even_rounds;   /* --even-rounds, or -1 for the default */
	const char *save; /* folder for each case's input, surface and skeleton PLYs, or NULL */
	uint64_t seed;
	uint64_t wlop_seed; /* --wlop-seed: WLOP's initial sample choice, or 0 for the library's default */
	int silhouette;     /* --silhouette 0 turns dp_surface_params.silhouette off */
	int face_scanner;   /* --face-scanner 0 turns dp_surface_params.face_scanner off */
	int sink_depth;     /* --sink-depth 0 leaves sink_depth out (a quarter to a half of a case's time) */
} options;

static const options *opts;

static int wanted(const options *o, const char *name)
{
	size_t len = strlen(name);
	for (const char *c = o->cases; (c = strstr(c, name)) != NULL; c += len)
		if ((c == o->cases || c[-1] == ',') && (c[len] == ',' || c[len] == '\0'))
			return 1;
	return 0;
}

static void print_stages(const dp_result *res)
{
	printf(",\"samples\":%zu,\"r\":%.6g,\"levels\":%d,\"seconds\":{\"wlop\":%.3f,\"sink\":%.3f,\"skeleton\":%.3f,"
	       "\"surface\":%.3f,\"total\":%.3f},\"iterations\":{\"wlop\":%d,\"sink\":%d,\"skeleton\":%d,\"surface\":%d},"
	       "\"capped\":{\"wlop\":%s,\"sink\":%s,\"skeleton\":%s,\"surface\":%s},\"surface_pairs\":%.4g,"
	       "\"normals_disagreeing\":%zu,\"escaped\":%zu,\"even_moved\":%zu,"
	       "\"silhouette\":{\"axis\":[%.3f,%.3f,%.3f],\"grazing\":%.4f,\"held\":%zu},"
	       "\"scanner\":{\"toward\":[%.3f,%.3f,%.3f],\"samples_turned\":%zu,\"scanner_turned\":%zu}",
	       res->surface.n, res->r, res->levels, res->wlop_stats.seconds, res->sink_stats.seconds,
	       res->skeleton_stats.seconds, res->surface_stats.seconds, res->seconds_total,
	       res->wlop_stats.iterations, res->sink_stats.iterations, res->skeleton_stats.iterations,
	       res->surface_stats.iterations, res->wlop_stats.converged ? "false" : "true",
	       res->sink_stats.converged ? "false" : "true", res->skeleton_stats.converged ? "false" : "true",
	       res->surface_stats.converged ? "false" : "true", res->surface_stats.pair_evaluations,
	       res->surface_stats.normals_disagreeing, res->surface_stats.escaped, res->even_moved,
	       res->surface_stats.silhouette_axis[0], res->surface_stats.silhouette_axis[1],
	       res->surface_stats.silhouette_axis[2], res->surface_stats.silhouette_grazing,
	       res->surface_stats.silhouette_held, res->surface_stats.scanner[0], res->surface_stats.scanner[1],
	       res->surface_stats.scanner[2], res->samples_turned, res->surface_stats.scanner_turned);
}

static void print_eval(const char *name, const dp_eval_result *e)
{
	printf(",\"%s\":{\"points\":%zu,\"accuracy_mean\":%.5f,\"accuracy_p95\":%.5f,\"coverage\":%.4f,"
	       "\"spacing_cv\":%.4f,\"scatter_median\":%.4f",
	       name, e->points, e->accuracy_mean, e->accuracy_p95, e->coverage, e->spacing_cv, e->scatter_median);
	if (e->has_normals)
		printf(",\"normal_angle_deg\":%.3f,\"normal_flipped\":%.4f,\"normal_flipped_clear\":%.4f",
		       e->normal_angle_deg, e->normal_flipped, e->normal_flipped_clear);
	printf("}");
}

/* The surface points without input support (η ≤ SUPPORTED_ETA): the
 * completed regions, where the method guesses. */
#define SUPPORTED_ETA 2.0f
static dp_status unsupported(const dp_result *res, dp_cloud *out, dp_error *err)
{
	size_t n = 0;
	for (size_t i = 0; i < res->surface.n; i++)
		n += res->eta[i] <= SUPPORTED_ETA;
	dp_status st = dp_cloud_alloc(out, n, 1, err);
	const dp_cloud *s = &res->surface;
	for (size_t i = 0, j = 0; st == DP_OK && i < s->n; i++) {
		if (res->eta[i] > SUPPORTED_ETA)
			continue;
		out->x[j] = s->x[i], out->y[j] = s->y[i], out->z[j] = s->z[i];
		out->nx[j] = s->nx[i], out->ny[j] = s->ny[i], out->nz[j] = s->nz[i];
		j++;
	}
	return st;
}

/* The chair's legs, between LEG_ZONE_LO and LEG_ZONE_HI of their length
 * (clear of the floor cap and the seat): per leg, how far the surface points
 * nearest it lie from its tube and the skeleton points from its axis (in r),
 * and the fraction of LEG_BINS height bins with a skeleton point within a leg
 * radius of the axis (a curve along the whole leg: 1); over all legs, the
 * surface points farther than LEG_APART radii from every axis (a cloud
 * joining the legs: 0). */
#define LEG_ZONE_LO 0.15
#define LEG_ZONE_HI 0.85
#define LEG_BINS 10
#define LEG_APART 2.0
static int nearest_leg(const dp_chair_parts *c, float x, float y, double *dist)
{
	int best = 0;
	for (int l = 0; l < 4; l++) {
		double d = hypot(x - c->leg[l][0], y - c->leg[l][1]);
		if (l == 0 || d < *dist) {
			best = l;
			*dist = d;
		}
	}
	return best;
}

/* The demo chair's shape and parts: 1, or 0 when the library lacks it. */
static int demo_chair(dp_shape *s, dp_chair_parts *c)
{
	dp_error err = {0};
	if (dp_shape_default("chair", s, &err) != DP_OK)
		return 0;
	dp_chair_layout(s, c);
	return 1;
}

static void print_legs(const dp_result *res)
{
	dp_shape s;
	dp_chair_parts c;
	if (!demo_chair(&s, &c))
		return;
	double lo = LEG_ZONE_LO * s.length, hi = LEG_ZONE_HI * s.length, r = res->r;
	double tube[4] = {0}, axis[4] = {0};
	size_t nsurf[4] = {0}, nskel[4] = {0}, apart = 0;
	int bins[4][LEG_BINS] = {{0}};
	for (size_t i = 0; i < res->surface.n; i++) {
		double d;
		if (res->surface.z[i] < lo || res->surface.z[i] > hi)
			continue;
		int l = nearest_leg(&c, res->surface.x[i], res->surface.y[i], &d);
		if (d > LEG_APART * s.radius) {
			apart++;
			continue;
		}
		nsurf[l]++;
		tube[l] += fabs(d - s.radius);
	}
	for (size_t i = 0; i < res->skeleton.n; i++) {
		double d, z = res->skeleton.z[i];
		if (z < lo || z > hi)
			continue;
		int l = nearest_leg(&c, res->skeleton.x[i], res->skeleton.y[i], &d);
		if (d > LEG_APART * s.radius)
			continue;
		nskel[l]++;
		axis[l] += d;
		if (d <= s.radius)
			bins[l][(int)fmin(LEG_BINS - 1, (z - lo) / (hi - lo) * LEG_BINS)] = 1;
	}
	printf(",\"legs\":[");
	for (int l = 0; l < 4; l++) {
		int span = 0;
		for (int b = 0; b < LEG_BINS; b++)
			span += bins[l][b];
		printf("%s{\"surface\":%zu,\"tube_mean_r\":%.3f,\"skeleton\":%zu,\"axis_mean_r\":%.3f,\"skeleton_span\":%.2f}",
		       l ? "," : "", nsurf[l], nsurf[l] ? tube[l] / nsurf[l] / r : 0.0, nskel[l],
		       nskel[l] ? axis[l] / nskel[l] / r : 0.0, (double)span / LEG_BINS);
	}
	printf("],\"legs_apart\":%zu,\"leg_radius_r\":%.3f", apart, s.radius / r);
}

/* Samples of the seat's top within this (in r) of the seat's rim, and
 * farther than SEAT_MIDDLE_R from it. */
#define SEAT_RIM_R 5.0
#define SEAT_MIDDLE_R 15.0

static int by_value(const void *a, const void *b);

/* The median of n values (sorted in place); 0 for none. */
static double median(float *v, size_t n)
{
	if (n == 0)
		return 0.0;
	qsort(v, n, sizeof *v, by_value);
	return v[n / 2];
}

/* How deep the anchors of the seat's top sank, in r: the samples facing up
 * within a spacing of the top, near its rim and in its middle. The seat
 * spans half its thickness down to its mid-plane, the depth sinking should
 * reach. */
static void print_seat(const dp_result *res)
{
	dp_shape s;
	dp_chair_parts c;
	if (!demo_chair(&s, &c))
		return;
	const dp_cloud *w = &res->wlop, *a = &res->anchors;
	float *rim = malloc(w->n * sizeof *rim), *middle = malloc(w->n * sizeof *middle);
	size_t nrim = 0, nmiddle = 0;
	double r = res->sink_r;
	for (size_t i = 0; rim && middle && i < w->n; i++) {
		if (fabs(w->z[i] - c.seat_hi[2]) > r || w->nz[i] < 0.9f)
			continue;
		double edge = fmin(fmin(w->x[i] - c.seat_lo[0], c.seat_hi[0] - w->x[i]),
				   fmin(w->y[i] - c.seat_lo[1], c.seat_hi[1] - w->y[i])) / r;
		if (edge < 0.0)
			continue;
		float d[3] = {w->x[i] - a->x[i], w->y[i] - a->y[i], w->z[i] - a->z[i]};
		float depth = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (float)r;
		if (edge < SEAT_RIM_R)
			rim[nrim++] = depth;
		else if (edge > SEAT_MIDDLE_R)
			middle[nmiddle++] = depth;
	}
	if (rim && middle)
		printf(",\"seat\":{\"half_thickness_r\":%.2f,\"rim_depth_r\":%.2f,\"middle_depth_r\":%.2f,"
		       "\"rim_samples\":%zu,\"middle_samples\":%zu}",
		       0.5 * (c.seat_hi[2] - c.seat_lo[2]) / r, median(rim, nrim), median(middle, nmiddle), nrim, nmiddle);
	free(rim);
	free(middle);
}

/* The true depth of sink_depth. The mesh is sampled TRUE_SPACING_R r apart
 * (from its area; at least TRUE_MIN_SAMPLES, at most TRUE_MAX_SAMPLES). At the
 * sample nearest an anchor's WLOP sample the normal is the PCA normal of the
 * samples within TRUE_NORMAL_R r, signed by the triangle's: a facet's own
 * normal is off by a few degrees on a decimated mesh (the bunny's), and a ball
 * grown along it leaves the surface sideways early; over 2 r the PCA mixes in
 * the next face at a plate's edge (the chair's edge anchors' true depths moved
 * 15% between 0.1 r and 0.15 r spacing; over 1 r, within 2%, and the whole
 * line within 1%). The largest ball touching the mesh there from inside is
 * found by bisection: the ball of radius R - TRUE_SLACK_R r about the point R
 * inside must hold no sample (the samples' own spacing stops the full ball at
 * once), and these balls are nested, so emptiness falls once as R grows. That
 * R overshoots the tangent ball by half the slack on a slab and on a sphere
 * alike, which is taken off. WLOP samples farther than NEAR_SURFACE_R r from
 * every mesh sample (outliers) are left out. The mesh must be wound outwards,
 * as the data folder's and the built-in shapes are. */
#define TRUE_SPACING_R 0.15
#define TRUE_MIN_SAMPLES 100000
#define TRUE_MAX_SAMPLES 3000000
#define TRUE_NORMAL_R 1.0
#define TRUE_NORMAL_CAP 2048
#define TRUE_SLACK_R 0.5
#define TRUE_MAX_R 100.0
#define TRUE_TOLERANCE_R 0.01
#define NEAR_SURFACE_R 2.0
#define SETTLE_KINDS (DP_SETTLE_FLAT + 1)

typedef struct truth_set {
	dp_cloud g;     /* mesh samples with their triangles' normals */
	dp_kdtree tree;
	uint32_t idx[TRUE_NORMAL_CAP];
	float d2[TRUE_NORMAL_CAP];
} truth_set;

/* The PCA normal of the samples around sample k, signed by its triangle's. */
static void smooth_normal(truth_set *t, uint32_t k, double r, double n[3])
{
	const dp_cloud *g = &t->g;
	float reach = (float)(TRUE_NORMAL_R * r);
	size_t m = dp_kdtree_nearest_within(&t->tree, g->x[k], g->y[k], g->z[k], reach * reach, TRUE_NORMAL_CAP,
					    t->idx, t->d2);
	dp_moments mom = {0};
	for (size_t j = 0; j < m; j++) {
		double d[3] = {g->x[t->idx[j]] - g->x[k], g->y[t->idx[j]] - g->y[k], g->z[t->idx[j]] - g->z[k]};
		dp_moments_add(&mom, d);
	}
	double cov[6], w[3], v[3];
	double tri[3] = {g->nx[k], g->ny[k], g->nz[k]};
	if (m < 3) {
		memcpy(n, tri, sizeof tri);
		return;
	}
	dp_moments_cov(&mom, cov);
	dp_eig3_smallest(cov, w, v);
	double sign = v[0] * tri[0] + v[1] * tri[1] + v[2] * tri[2] < 0.0 ? -1.0 : 1.0;
	for (int c = 0; c < 3; c++)
		n[c] = sign * v[c];
}

/* Whether the slack-shrunk ball about the point R inside along n is empty. */
static int ball_free(const truth_set *t, const float p[3], const double n[3], double R, double slack)
{
	double inner = R - slack;
	if (inner <= 0.0)
		return 1;
	return !dp_kdtree_any_within(&t->tree, (float)(p[0] - R * n[0]), (float)(p[1] - R * n[1]),
				     (float)(p[2] - R * n[2]), (float)(inner * inner));
}

/* The true depth at sample k into *slack_r, and the tangent ball through the
 * sample that first entered the shrunk ball into *contact_r; -1 in both where
 * no ball up to TRUE_MAX_R r closes (an open rim, or a part thinner than the
 * slack, which the shrunk balls never reach). Where the contact lies straight
 * across, as on a slab or a sphere, the two agree; off the normal line (a
 * plate's edge, an inside corner, a body curving round) the shrunk ball slides
 * on along the surface and the first depth reads high, up to the whole slack
 * and more where the surface grazes the ball, while the second takes a sample
 * that entered the ball for a contact and reads low. */
static void true_depth(truth_set *t, uint32_t k, double r, double *slack_r, double *contact_r)
{
	const dp_cloud *g = &t->g;
	float p[3] = {g->x[k], g->y[k], g->z[k]};
	double n[3], slack = TRUE_SLACK_R * r, lo = slack, hi = 2.0 * slack, cap = TRUE_MAX_R * r;
	*slack_r = *contact_r = -1.0;
	smooth_normal(t, k, r, n);
	while (hi < cap && ball_free(t, p, n, hi, slack)) {
		lo = hi;
		hi *= 2.0;
	}
	if (hi >= cap) {
		hi = cap;
		if (ball_free(t, p, n, hi, slack))
			return;
	}
	while (hi - lo > TRUE_TOLERANCE_R * r) {
		double mid = 0.5 * (lo + hi);
		if (ball_free(t, p, n, mid, slack))
			lo = mid;
		else
			hi = mid;
	}
	*slack_r = *contact_r = fmax(lo - 0.5 * slack, 0.0) / r;
	float c[3] = {(float)(p[0] - hi * n[0]), (float)(p[1] - hi * n[1]), (float)(p[2] - hi * n[2])};
	float reach = (float)(hi - slack);
	uint32_t q;
	float d2;
	if (dp_kdtree_nearest_within(&t->tree, c[0], c[1], c[2], reach * reach, 1, &q, &d2) == 1) {
		double d[3] = {p[0] - g->x[q], p[1] - g->y[q], p[2] - g->z[q]};
		double along = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
		if (along > 0.0)
			*contact_r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (2.0 * along) / r;
	}
}

/* Whether (x, y, z) lies outside the mesh: its winding number, the solid
 * angle its triangles subtend there over 4π (Van Oosterom and Strackee's
 * formula per triangle), is below one half. The number counts the closed
 * parts that hold the point, so it reads right where a mesh's parts overlap
 * (where the nearest face's side can be an inner face's), and it stays near
 * one inside a body with a few holes (the bunny's base). `corners` holds each
 * face's corners. */
static int is_outside(const double *corners, size_t nfaces, float x, float y, float z)
{
	double total = 0.0;
	for (size_t f = 0; f < nfaces; f++) {
		const double *t = corners + 9 * f;
		double a[3] = {t[0] - x, t[1] - y, t[2] - z}, b[3] = {t[3] - x, t[4] - y, t[5] - z};
		double c[3] = {t[6] - x, t[7] - y, t[8] - z};
		double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
		double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
		double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
		double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
			     a[2] * (b[0] * c[1] - b[1] * c[0]);
		double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
		double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
		total += 2.0 * atan2(det, la * lb * lc + ab * lc + ac * lb + bc * la);
	}
	return total / (4.0 * M_PI) < 0.5;
}

/* Per way of settling: anchors (and those whose ball never closed, left out
 * of the rest), the medians of their distance from their mesh point, of the
 * true depth there by either reading and of the per-anchor ratios, and the
 * fraction of them nearer to some other mesh sample than to their own by more
 * than the slack: past the medial axis whatever the normals say; and how many
 * of them, open ones included, lie outside the mesh (is_outside). */
static void print_sink_depth(const dp_result *res, const dp_cloud *mesh)
{
	static const char *const kind[] = {"unsettled", "front", "medial", "width", "slow", "flat"};
	_Static_assert(sizeof kind / sizeof *kind == SETTLE_KINDS, "a name for every dp_settle code");
	const dp_cloud *w = &res->wlop, *a = &res->anchors;
	double r = res->sink_r;
	dp_error err = {0};
	truth_set *t = calloc(1, sizeof *t);
	size_t n = a->n;
	float *depth = malloc(n * sizeof *depth), *truth = malloc(n * sizeof *truth);
	float *ratio = malloc(n * sizeof *ratio), *contact = malloc(n * sizeof *contact);
	float *ratio_contact = malloc(n * sizeof *ratio_contact);
	double *corners = NULL;
	if (!t || !depth || !truth || !ratio || !contact || !ratio_contact || !res->settled_by ||
	    dp_mesh_check(mesh, "sink_depth", &err) != DP_OK || !(corners = malloc(mesh->nfaces * 9 * sizeof *corners)))
		goto out;
	for (size_t f = 0; f < mesh->nfaces; f++)
		dp_mesh_triangle(mesh, f, corners + 9 * f, corners + 9 * f + 3, corners + 9 * f + 6);
	double area = dp_mesh_area(mesh), want = area / (TRUE_SPACING_R * r * TRUE_SPACING_R * r);
	size_t samples = (size_t)fmin(fmax(want, TRUE_MIN_SAMPLES), TRUE_MAX_SAMPLES);
	if (dp_mesh_sample(mesh, samples, 0.0, 1, &t->g, &err) != DP_OK ||
	    dp_kdtree_build(&t->tree, t->g.n, t->g.x, t->g.y, t->g.z, &err) != DP_OK)
		goto out;
	printf(",\"sink_depth\":{\"mesh_spacing_r\":%.3f", sqrt(area / (double)samples) / r);
	for (int k = 0; k < SETTLE_KINDS; k++) {
		size_t m = 0, past = 0, open = 0, outside = 0;
		for (size_t i = 0; i < n; i++) {
			uint32_t near;
			float d2;
			float rr = (float)(NEAR_SURFACE_R * r);
			if (res->settled_by[i] != k ||
			    dp_kdtree_nearest_within(&t->tree, w->x[i], w->y[i], w->z[i], rr * rr, 1, &near, &d2) != 1)
				continue;
			outside += is_outside(corners, mesh->nfaces, a->x[i], a->y[i], a->z[i]);
			const dp_cloud *g = &t->g;
			float v[3] = {g->x[near] - a->x[i], g->y[near] - a->y[i], g->z[near] - a->z[i]};
			float own = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
			double truth_r, contact_r;
			true_depth(t, near, r, &truth_r, &contact_r);
			if (truth_r < 0.0) {
				open++;
				continue;
			}
			float other = own - (float)(TRUE_SLACK_R * r);
			past += other > 0.0f &&
				dp_kdtree_any_within(&t->tree, a->x[i], a->y[i], a->z[i], other * other);
			depth[m] = own / (float)r;
			truth[m] = (float)truth_r;
			contact[m] = (float)contact_r;
			ratio[m] = depth[m] / fmaxf(truth[m], (float)TRUE_TOLERANCE_R);
			ratio_contact[m] = depth[m] / fmaxf(contact[m], (float)TRUE_TOLERANCE_R);
			m++;
		}
		if (m + open == 0)
			continue;
		printf(",\"%s\":{\"anchors\":%zu,\"open\":%zu,\"depth_r\":%.2f,\"true_r\":%.2f,\"ratio\":%.2f,"
		       "\"contact_r\":%.2f,\"ratio_contact\":%.2f,\"past\":%.3f,\"outside\":%zu}",
		       kind[k], m, open, median(depth, m), median(truth, m), median(ratio, m), median(contact, m),
		       median(ratio_contact, m), m ? (double)past / (double)m : 0.0, outside);
	}
	printf("}");
out:
	if (err.message[0])
		fprintf(stderr, "bench_completion: sink_depth: %s\n", err.message);
	if (t) {
		dp_kdtree_free(&t->tree);
		dp_cloud_free(&t->g);
	}
	free(t);
	free(depth);
	free(truth);
	free(ratio);
	free(contact);
	free(ratio_contact);
	free(corners);
}

/* The library's defaults with this run's --surface-iters and --even-rounds. */
static void bench_params(dp_params *p)
{
	dp_params_default(p);
	if (opts->surface_iters >= 0)
		p->surface.max_iters = opts->surface_iters;
	if (opts->even_rounds >= 0)
		p->refine.even_rounds = opts->even_rounds;
	if (opts->wlop_seed)
		p->wlop.seed = opts->wlop_seed;
	p->surface.silhouette = opts->silhouette;
	p->surface.face_scanner = opts->face_scanner;
}

/* Reads `file` under the data folder into `in`: 1, or 0 after a "skipped"
 * message when it cannot be read. */
static int read_data(const char *file, const char *name, dp_cloud *in)
{
	char path[4096];
	dp_error err = {0};
	snprintf(path, sizeof path, "%s/%s", opts->data, file);
	if (dp_cloud_read(path, in, DP_READ_POINTS, &err) == DP_OK)
		return 1;
	fprintf(stderr, "bench_completion: %s skipped: %s\n", name, err.message);
	return 0;
}

/* Consolidates `in`, evaluates input and surface against `mesh`, prints one
 * line. `samples` 0 keeps the library's default count. */
static int run(dp_context *ctx, const char *name, const dp_cloud *mesh, const dp_cloud *in, size_t samples)
{
	dp_error err = {0};
	dp_params p;
	bench_params(&p);
	if (samples)
		p.wlop.samples = samples;
	if (opts->coarse)
		p.refine.coarse_samples = opts->coarse;
	dp_result res = {0};
	dp_cloud guessed = {0};
	dp_eval_result ei, es, eg;
	int rc = -1;
	if (dp_consolidate(ctx, in, &p, &res, &err) != DP_OK || dp_eval(mesh, in, NULL, &ei, &err) != DP_OK ||
	    dp_eval(mesh, &res.surface, NULL, &es, &err) != DP_OK || unsupported(&res, &guessed, &err) != DP_OK)
		goto out;
	printf("{\"bench\":\"completion\",\"case\":\"%s\",\"wlop_seed\":%llu,\"raw\":%zu", name, (unsigned long long)p.wlop.seed, in->n);
	print_stages(&res);
	print_eval("input", &ei);
	print_eval("surface", &es);
	if (guessed.n >= 2 && dp_eval(mesh, &guessed, NULL, &eg, &err) == DP_OK)
		print_eval("surface_unsupported", &eg);
	if (opts->sink_depth)
		print_sink_depth(&res, mesh);
	if (!strcmp(name, "chair")) {
		print_legs(&res);
		print_seat(&res);
	}
	if (opts->save) {
		char path[4096];
		const char *what[3] = {"input", "surface", "skeleton"};
		const dp_cloud *clouds[3] = {in, &res.surface, &res.skeleton};
		for (int c = 0; c < 3; c++) {
			snprintf(path, sizeof path, "%s/%s_%s.ply", opts->save, name, what[c]);
			if (dp_cloud_write_ply(path, clouds[c], 0, &err) != DP_OK)
				fprintf(stderr, "bench_completion: %s\n", err.message);
		}
	}
	printf(",\"levels_detail\":[");
	for (int l = 0; l < res.levels; l++)
		printf("%s{\"points\":%zu,\"r\":%.5g,\"iterations\":%d,\"seconds\":%.3f,\"pairs\":%.4g}",
		       l ? "," : "", res.level[l].points, res.level[l].r, res.level[l].iterations, res.level[l].seconds,
		       res.level[l].pair_evaluations);
	printf("]}\n");
	fflush(stdout);
	rc = 0;
out:
	if (rc)
		fprintf(stderr, "bench_completion: %s: %s\n", name, err.message);
	dp_result_free(&res);
	dp_cloud_free(&guessed);
	return rc;
}

static int shape_scan(const char *shape, int views, int res_rays, uint64_t seed, dp_cloud *mesh, dp_cloud *scan,
		      dp_error *err)
{
	dp_shape s;
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = views;
	sp.res = res_rays;
	sp.noise = NOISE;
	sp.normals = 0;
	sp.seed = seed;
	if (dp_shape_default(shape, &s, err) != DP_OK || dp_shape_mesh(&s, mesh, err) != DP_OK ||
	    dp_scan(mesh, &sp, scan, NULL, err) != DP_OK)
		return -1;
	return 0;
}

static int run_shape(dp_context *ctx, const char *shape, int views, int res_rays, size_t samples, const options *o,
		     const char *name)
{
	dp_error err = {0};
	dp_cloud mesh = {0}, scan = {0};
	int rc = shape_scan(shape, views, res_rays, o->seed, &mesh, &scan, &err);
	if (rc)
		fprintf(stderr, "bench_completion: %s: %s\n", name, err.message);
	else
		rc = run(ctx, name, &mesh, &scan, samples);
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
	return rc;
}

/* bun.conf's `bmesh NAME tx ty tz qx qy qz qw`: world = R(q)ᵀ p + t. */
static int read_view(const char *dir, const char *name, dp_cloud *view)
{
	char path[4096], line[512], file[256];
	double t[3], q[4];
	int found = 0;
	snprintf(path, sizeof path, "%s/stanford-bunny/bun.conf", dir);
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	while (!found && fgets(line, sizeof line, f))
		found = sscanf(line, "bmesh %255s %lf %lf %lf %lf %lf %lf %lf", file, &t[0], &t[1], &t[2], &q[0], &q[1],
			       &q[2], &q[3]) == 8 &&
			strcmp(file, name) == 0;
	fclose(f);
	dp_error err = {0};
	snprintf(path, sizeof path, "%s/stanford-bunny/%s", dir, name);
	if (!found || dp_cloud_read(path, view, DP_READ_POINTS, &err) != DP_OK)
		return -1;
	double x = q[0], y = q[1], z = q[2], w = q[3];
	double m[3][3] = {
		{1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)},
		{2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)},
		{2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)},
	};
	for (size_t i = 0; i < view->n; i++) {
		double v[3] = {view->x[i], view->y[i], view->z[i]};
		view->x[i] = (float)(m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2] + t[0]);
		view->y[i] = (float)(m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2] + t[1]);
		view->z[i] = (float)(m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2] + t[2]);
	}
	return 0;
}

/* Scans of the bunny posed into the ground-truth frame and merged, judged as
 * case `name`; skipped, with a message, without the data. */
static int run_bunny(dp_context *ctx, const options *o, const char *name, int views, const char *const *scans)
{
	dp_cloud mesh = {0}, v[BUNNY_MAX_VIEWS] = {{0}}, all = {0};
	dp_error err = {0};
	char path[4096];
	snprintf(path, sizeof path, "%s/stanford-bunny/bun_zipper_res2.ply", o->data);
	int rc = 0;
	if (dp_cloud_read(path, &mesh, DP_READ_MESH, &err) != DP_OK) {
		fprintf(stderr, "bench_completion: bunny skipped: %s\n", err.message);
		return 0;
	}
	size_t total = 0;
	for (int i = 0; i < views; i++) {
		if (read_view(o->data, scans[i], &v[i])) {
			fprintf(stderr, "bench_completion: %s skipped: cannot read %s with its pose\n", name, scans[i]);
			goto out;
		}
		total += v[i].n;
	}
	if (dp_cloud_alloc(&all, total, 0, &err) != DP_OK) {
		rc = -1;
		goto out;
	}
	for (int i = 0, k = 0; i < views; i++)
		for (size_t j = 0; j < v[i].n; j++, k++)
			all.x[k] = v[i].x[j], all.y[k] = v[i].y[j], all.z[k] = v[i].z[j];
	rc = run(ctx, name, &mesh, &all, 0);
out:
	dp_cloud_free(&mesh);
	for (int i = 0; i < views; i++)
		dp_cloud_free(&v[i]);
	dp_cloud_free(&all);
	return rc;
}

static int run_statue(dp_context *ctx)
{
	dp_cloud in = {0};
	dp_error err = {0};
	if (!read_data("paper/statue-fig12b-raw.xyz", "statue", &in))
		return 0;
	dp_params p;
	bench_params(&p);
	dp_result res = {0};
	int rc = -1;
	if (dp_consolidate(ctx, &in, &p, &res, &err) == DP_OK) {
		printf("{\"bench\":\"completion\",\"case\":\"statue\",\"wlop_seed\":%llu,\"raw\":%zu", (unsigned long long)p.wlop.seed, in.n);
		print_stages(&res);
		printf("}\n");
		rc = 0;
	} else {
		fprintf(stderr, "bench_completion: statue: %s\n", err.message);
	}
	dp_result_free(&res);
	dp_cloud_free(&in);
	return rc;
}

static int by_value(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/* Median and 90th percentile of the distances from c's points to the input
 * indexed by knn, in r. */
static int print_to_input(const char *name, const dp_knn *knn, const dp_cloud *c, double r, dp_error *err)
{
	if (c->n == 0) {
		printf(",\"%s_to_input_r\":null", name);
		return 0;
	}
	int *idx = malloc(c->n * sizeof *idx);
	float *d2 = malloc(c->n * sizeof *d2);
	int rc = -1;
	if (idx && d2 && dp_knn_query(knn, c->n, c->x, c->y, c->z, 1, idx, d2, err) == DP_OK) {
		qsort(d2, c->n, sizeof *d2, by_value);
		printf(",\"%s_to_input_r\":{\"median\":%.3f,\"p90\":%.3f}", name, sqrt(d2[c->n / 2]) / r,
		       sqrt(d2[(size_t)(0.9 * (double)(c->n - 1))]) / r);
		rc = 0;
	}
	free(idx);
	free(d2);
	return rc;
}

static int run_lamppost(dp_context *ctx)
{
	dp_cloud in = {0};
	dp_error err = {0};
	if (!read_data("pcl/lamppost.pcd", "lamppost", &in))
		return 0;
	dp_params p;
	bench_params(&p);
	dp_result res = {0};
	dp_knn knn = {0};
	int rc = -1;
	if (dp_consolidate(ctx, &in, &p, &res, &err) == DP_OK && dp_knn_build(&knn, in.n, in.x, in.y, in.z, &err) == DP_OK) {
		printf("{\"bench\":\"completion\",\"case\":\"lamppost\",\"wlop_seed\":%llu,\"raw\":%zu", (unsigned long long)p.wlop.seed, in.n);
		print_stages(&res);
		printf(",\"sink_settled\":{\"front\":%zu,\"medial\":%zu,\"width\":%zu,\"slow\":%zu,\"flat\":%zu,"
		       "\"unsettled\":%zu}",
		       res.sink_stats.settled_front, res.sink_stats.settled_medial, res.sink_stats.settled_width,
		       res.sink_stats.settled_slow, res.sink_stats.settled_flat, res.sink_stats.unsettled);
		if (print_to_input("surface", &knn, &res.surface, res.r, &err) == 0 &&
		    print_to_input("skeleton", &knn, &res.skeleton, res.r, &err) == 0)
			rc = 0;
		printf("}\n");
	}
	if (rc)
		fprintf(stderr, "bench_completion: lamppost: %s\n", err.message);
	dp_knn_free(&knn);
	dp_result_free(&res);
	dp_cloud_free(&in);
	return rc;
}

static int parse(int argc, char **argv, options *o)
{
	const char *sizes = DEFAULT_SAMPLES;
	o->cases = "sphere,bunny1,bunny2,heldout,chair,rods,statue,lamppost";
	o->data = getenv("DP_DATA_DIR") ? getenv("DP_DATA_DIR") : "../shared/data";
	o->device = NULL;
	o->save = NULL;
	o->coarse = 0;
	o->surface_iters = -1;
	o->even_rounds = -1;
	o->seed = 7;
	o->wlop_seed = 0;
	o->sink_depth = 1;
	o->silhouette = 1;
	o->face_scanner = 1;
	for (int i = 1; i + 1 < argc; i += 2) {
		if (!strcmp(argv[i], "--case"))
			o->cases = argv[i + 1];
		else if (!strcmp(argv[i], "--samples"))
			sizes = argv[i + 1];
		else if (!strcmp(argv[i], "--data"))
			o->data = argv[i + 1];
		else if (!strcmp(argv[i], "--device"))
			o->device = argv[i + 1];
		else if (!strcmp(argv[i], "--coarse"))
			o->coarse = strtoull(argv[i + 1], NULL, 10);
		else if (!strcmp(argv[i], "--surface-iters") || !strcmp(argv[i], "--even-rounds")) {
			char *end;
			long v = strtol(argv[i + 1], &end, 10);
			if (*end || v < 0 || v > INT_MAX)
				return -1;
			*(argv[i][2] == 's' ? &o->surface_iters : &o->even_rounds) = (int)v;
		} else if (!strcmp(argv[i], "--save"))
			o->save = argv[i + 1];
		else if (!strcmp(argv[i], "--seed"))
			o->seed = strtoull(argv[i + 1], NULL, 10);
		else if (!strcmp(argv[i], "--wlop-seed"))
			o->wlop_seed = strtoull(argv[i + 1], NULL, 10);
		else if (!strcmp(argv[i], "--sink-depth") && (!strcmp(argv[i + 1], "0") || !strcmp(argv[i + 1], "1")))
			o->sink_depth = argv[i + 1][0] == '1';
		else if (!strcmp(argv[i], "--silhouette") && (!strcmp(argv[i + 1], "0") || !strcmp(argv[i + 1], "1")))
			o->silhouette = argv[i + 1][0] == '1';
		else if (!strcmp(argv[i], "--face-scanner") && (!strcmp(argv[i + 1], "0") || !strcmp(argv[i + 1], "1")))
			o->face_scanner = argv[i + 1][0] == '1';
		else
			return -1;
	}
	if (argc % 2 == 0)
		return -1;
	o->nsizes = 0;
	while (*sizes && o->nsizes < MAX_SIZES) {
		char *end;
		unsigned long long m = strtoull(sizes, &end, 10);
		if (m < 2 || (*end && *end != ','))
			return -1;
		o->samples[o->nsizes++] = (size_t)m;
		sizes = *end ? end + 1 : end;
	}
	return o->nsizes ? 0 : -1;
}

int main(int argc, char **argv)
{
	options o;
	opts = &o;
	if (parse(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_completion [--case sphere,bunny1,bunny2,heldout,chair,rods,statue,lamppost] "
				"[--samples M,...] [--data DIR] [--device D] [--seed S] [--save DIR] [--coarse N] "
				"[--surface-iters N] [--wlop-seed S] [--sink-depth 0|1] [--even-rounds N] [--silhouette 0|1]\n"
				"                        [--face-scanner 0|1]\n");
		return 2;
	}
	dp_context *ctx = NULL;
	dp_error err = {0};
	if (dp_context_create(&ctx, DP_BACKEND_CL, o.device, &err) != DP_OK) {
		fprintf(stderr, "bench_completion: %s\n", err.message);
		return 1;
	}
	int rc = 0;
	for (int i = 0; wanted(&o, "sphere") && i < o.nsizes; i++) {
		int res_rays = (int)lround(SPHERE_RES_PER_SQRT_SAMPLE * sqrt((double)o.samples[i]));
		char name[64];
		snprintf(name, sizeof name, "one_view_sphere_%zu", o.samples[i]);
		rc |= run_shape(ctx, "sphere", 1, res_rays, o.samples[i], &o, name);
	}
	static const char *const front[] = {"bun000.ply"}, *const front_back[] = {"bun000.ply", "bun180.ply"},
			       *const sides[] = {"bun090.ply", "bun270.ply"}, *const back[] = {"bun180.ply"};
	if (wanted(&o, "bunny1"))
		rc |= run_bunny(ctx, &o, "bunny_one_view", 1, front);
	if (wanted(&o, "bunny2"))
		rc |= run_bunny(ctx, &o, "bunny_two_views", 2, front_back);
	if (wanted(&o, "heldout")) {
		rc |= run_bunny(ctx, &o, "bunny_one_view_bun090", 1, sides);
		rc |= run_bunny(ctx, &o, "bunny_one_view_bun180", 1, back);
		rc |= run_bunny(ctx, &o, "bunny_one_view_bun270", 1, sides + 1);
		rc |= run_bunny(ctx, &o, "bunny_two_views_bun090_bun270", 2, sides);
	}
	if (wanted(&o, "chair"))
		rc |= run_shape(ctx, "chair", CHAIR_VIEWS, CHAIR_RES, 0, &o, "chair");
	if (wanted(&o, "rods"))
		rc |= run_shape(ctx, "rods", 2, CHAIR_RES, 0, &o, "rods");
	if (wanted(&o, "statue"))
		rc |= run_statue(ctx);
	if (wanted(&o, "lamppost"))
		rc |= run_lamppost(ctx);
	dp_context_free(ctx);
	return rc ? 1 : 0;
}
