/* Surface point consolidation (paper 4.3, DESIGN 4.3): the position update,
 * normal update, re-attachment and stopping test, on the host; every
 * neighbour sum is an operator of host/ops/operators.h.
 *
 * One iteration: (1) dpoint lengths, data and neighbourhood passes at p;
 * (2) slide p += μ̂R; (3) re-attach at the slid p: the skeleton point h the
 * inner end hangs on; (3b) move the inner end q across the normal to under
 * the point (smooth_ends); (4) data and prior step at the slid p with that
 * q; (5) re-bucket, PCA normals, normal update. The paper adds the terms of
 * one fixed-point update together; doing the tangential slide first has the
 * same fixed points and avoids the drift described at slide(). Re-attaching
 * before the prior step matters as much: re-attached after it, a point that
 * slid along a skeletal curve gets a shorter dpoint that the length averaging
 * then keeps (measured on a one-sided torus: the unsupported half sank 0.2 ρ
 * towards the core).
 *
 * The minimal-volume prior (Eq. 9). Taken literally — the gradient of
 * ½ Σ γ_k L_k² through the point's own length, a pull of γ L_i/W_i straight
 * towards q_i — it does not vanish on the surface, and measured on a complete
 * noisy sphere of radius 21 r it beat the data term everywhere: all points
 * left the data within 10 iterations and the set contracted onto the
 * skeleton. What the paper shows it doing (Fig. 17) is closing missing regions
 * flat instead of bulging them out like their neighbours. So the option is
 * implemented as a membrane: the dpoint may only shorten, towards the depth of
 * the θ-weighted centroid of P_i, g_i = γ_i min(0, (c_i - p_i)·m_i). Like
 * Laplacian smoothing it removes volume where the surface bulges; on data the
 * data term holds the points (the pull is the curvature offset of P_i, a
 * fraction of r); where there is no input it flattens the closure between
 * the scanned rims. */
#include "backend/ops.h"
#include "stages/balls.h"
#include "stages/scanner.h"
#include "stages/sheet_points.h"
#include "stages/silhouette.h"
#include "stages/surface.h"
#include "core/common.h"
#include "core/distinct.h"
#include "core/eig3.h"
#include "core/parallel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A PCA neighbourhood whose middle eigenvalue is below this (in r²) is a
 * point or a line: its smallest axis is no normal, keep the old one. */
#define PCA_MIN_SPREAD 1e-6
/* Same-sided neighbourhoods: a surface neighbour counts when its normal is
 * within 90° of the point's (the far side of a part thinner than σp r faces
 * away); without the test every cosine passes. */
#define SAME_SIDE_COS 0.0f
#define ANY_SIDE_COS -2.0f
/* A thread of the normal update gets at least this many points (an
 * eigen-decomposition is a tenth of a microsecond). */
#define NORMALS_MIN_ITEMS 2048
/* Skeleton points in one cube of this side (in r) are one candidate of
 * re-attachment. */
#define SKELETON_MERGE_R 0.05
/* A point is held by input when Σθ of the input reaches this (an input point
 * within about 1 r). The inside test moves only points input does not hold,
 * and only those take their normal's sign from their dpoint (update_normals). */
#define HELD_SUPPORT 1.0f
/* Balls within this (in r) of lying inside another are left out of the
 * inside test (balls.h). */
#define BALL_SLACK_R 0.5
/* The smoothing of inner ends sums over 3 widths (weights down to e^-9), but
 * no further than the surface grid's cell, since its scan reaches only the
 * adjacent cells (e^-6.25 at the default 2 r and σp = 5). */
#define END_REACH 3.0f
/* The set is at rest when no more than one point in this many moves more
 * than min_move_r in an iteration: a sharp crease or a noisy spot can keep a
 * few points jittering (the kitten of the data folder: the largest move of
 * an iteration 0.04-0.13 r for 100 iterations, the 99.9th percentile below
 * 0.05 r after 30). */
#define STILL_PER 1000

void dp_surface_params_default(dp_surface_params *p)
{
	p->sigma_p = 5.0;
	/* The paper's 0.4 never settles: β̂ falls with the fifth power of the
	 * tangential distance, so R_i is nearly the offset from the nearest
	 * neighbour, and each point hops away from it by 0.4 of that every
	 * iteration, onto the next one's doorstep. Measured on the chair at
	 * iteration 90 of 96: median move 0.36 r per iteration, 93% of it
	 * tangential, and 56% of the inner ends re-attached in one iteration.
	 * Halved, points spread into holes more slowly but stop boiling; mean
	 * of WLOP seeds 1-6 (coverage / flipped / spacing CV / 95th percentile
	 * accuracy): chair 0.964 / 2.9% / 0.37 / 0.0156 -> 0.964 / 2.6% / 0.31
	 * / 0.0146, two-view bunny 0.951 / 0.98% / 0.33 / 0.041 -> 0.954 /
	 * 0.75% / 0.25 / 0.037, one-view bunny 0.776 / 2.4% / 0.50 / 0.054 ->
	 * 0.761 / 2.6% / 0.47 / 0.048; one-view sphere at 2000 / 8000 / 32000
	 * deep points covered 0.999 / 0.996 / 0.977 -> 1.000 / 0.997 / 0.989. */
	p->mu_hat = 0.2;
	p->prior = DP_SURFACE_PRIOR_VOLUME;
	p->data_along_normal = 1;
	p->tangent_floor_r = 0.01;
	p->slide_reach_r = 0.0;
	p->normal_radius_r = 3.0;
	p->reattach = 1;
	p->reattach_radius_r = 2.0;
	p->end_smoothing_r = 2.0;
	p->max_iters = 200;
	p->same_side = 1;
	p->orient_by_dpoint = 1;
	p->window = 10;
	p->min_drop = 0.05;
	p->min_growth = 0.005;
	p->escape_margin_r = 1.0;
	/* Measured, the 99.9th percentile of a point's move in an iteration:
	 * complete scans of the data folder (knot, sphere, kitten) below 0.1 r
	 * within 10-30 iterations, scans with holes 0.5-1.8 r while they fill
	 * (two-view bunny, fertility, anchor). With it the complete ones stop
	 * at 21, 19 and 14 iterations instead of the cap of 200, 136 and 118,
	 * their accuracy the same to 0.0003 of the diagonal and their spacing
	 * variation 0.04-0.06 instead of 0.03-0.04; every bench_completion case
	 * stops where it did, and a 20000-point sphere scan with a hole 0.3 R
	 * across still fills it (coverage 1.000, 80 iterations instead of the
	 * cap). */
	p->min_move_r = 0.1;
	/* Measured over WLOP seeds 1-6 (bench_completion, coverage / flipped
	 * / spacing variation / 95th percentile): chair 0.965 / 1.46% / 0.22 /
	 * 0.0136 -> 0.974 / 1.05% / 0.23 / 0.0120; the one- and two-view
	 * bunnies unchanged. */
	p->sheet_points = 1;
	p->silhouette = 1;
	p->silhouette_axis[0] = p->silhouette_axis[1] = p->silhouette_axis[2] = 0.0;
	/* between the bunny's scans (0.006-0.057) and the data folder's
	 * complete ones (0.077 and more): silhouette.h */
	p->silhouette_grazing = 0.065;
	/* The margin is also the room completion has to bulge out beyond the
	 * scan's edge, and the volume prior takes it: at 3 r the two-view
	 * bunny's closed base hung 196 of its 8051 points more than 0.02
	 * diagonals below the true base (WLOP seed 1; 64 at 2.5 r), where the
	 * true surface lies within 1.4 r of the outline.
	 * Seen along the six bunny scans' axes, the share of the true surface
	 * outside the outline grown by 2 / 2.5 / 3 r is at most 1.2% / 0.20% /
	 * 0.003% (bun270; four of the six have none at 2 r). Means over WLOP
	 * seeds 1-6 (coverage / flipped / 95th percentile; 3 r -> 2.5 r): one
	 * view 0.855 / 1.03% / 0.036 -> 0.845 / 0.94% / 0.034, two views 0.958
	 * / 0.47% / 0.022 -> 0.967 / 0.48% / 0.017, bun270 0.794 / 2.47% /
	 * 0.044 -> 0.805 / 2.12% / 0.042, bun090 + bun270 0.969 / 0.92% / 0.032
	 * -> 0.973 / 0.85% / 0.028 (README (37)). */
	p->silhouette_margin_r = 2.5;
	/* Measured over WLOP seeds 1-6 (bench_completion, coverage / flipped /
	 * 95th percentile; 2.5 r all round -> 1 r where the edge faces the
	 * scanner, the anchors' outline and the surface's both): two views
	 * 0.966 / 0.48% / 0.0174 -> 0.978 / 0.48% / 0.0127 (the closed base had
	 * hung up to 2.4 r below the feet, whose scanned fronts face the
	 * scanner, and anchors sat on its edge), one view 0.845 / 0.94% / 0.034
	 * -> 0.857 / 0.90% / 0.033, bun270 0.805 / 2.12% -> 0.804 / 1.98%, bun090
	 * + bun270 0.974 / 0.88% -> 0.982 / 0.80%, bun090 about the same, but
	 * bun180 0.844 / 0.48% -> 0.839 / 0.78% (its ears' cloud held tighter);
	 * the one-view spheres unchanged (their rims turn away), the chair has
	 * no axis. Only the surface's outline: two views 0.966; only the
	 * anchors': 0.969. Turning taken at 70° from the axis instead of 50°:
	 * bun270 0.805 -> 0.766; 1.5 r there: two views 0.978 / 0.55%
	 * (README (44)). */
	p->silhouette_edge_margin_r = 1.0;
	/* Measured over WLOP seeds 1-6 (bench_completion, the one-view bunny,
	 * coverage / flipped / spacing CV / 95th percentile): off 0.854 / 1.38%
	 * / 0.50 / 0.036; at 0.3 0.848 / 1.16%, 0.5 0.855 / 1.03%, 0.6 0.855 /
	 * 0.96%, 0.7 0.853 / 1.06%, 0.8 0.851 / 1.10%, the rest unchanged. 0.5
	 * for what it guarantees (scanner.h: views up to 30° off the axis); 0.6
	 * measured best by less than the spread between seeds. */
	p->face_scanner = 1;
	p->face_scanner_cos = 0.5;
	p->scanner_side = 0;
	p->use_viewpoint = 0;
	p->viewpoint[0] = p->viewpoint[1] = p->viewpoint[2] = 0.0;
}

/* Working arrays, one allocation each, reused by every iteration. */
enum {
	A_PX, A_PY, A_PZ, A_NX, A_NY, A_NZ, A_QX, A_QY, A_QZ, A_LEN, A_GLEN,
	A_ETA, A_SA, A_OX, A_OY, A_OZ, A_L, A_VAR, A_RX, A_RY, A_RZ, A_NN, A_D2, A_TX, A_TY, A_TZ,
	A_MX, A_MY, A_MZ, A_SX, A_SY, A_SZ, A_DEPTH, A_GNX, A_GNY, A_GNZ, A_KX, A_KY, A_KZ,
	A_EX, A_EY, A_EZ, A_EDIST, A_HX, A_HY, A_HZ, A_GHX, A_GHY, A_GHZ, A_AX, A_AY, A_AZ, A_EW,
	A_COUNT
};

typedef struct work {
	float *a[A_COUNT];
	float *cov;
	int32_t *best;
	int32_t *escape;        /* per point: the ball it leaves this iteration, or -1 */
	dp_ball_set balls;
	dp_silhouette outline;  /* zero when not held to one */
	uint32_t *of;           /* skeleton merge: first point of each merged position */
	double *move, *spacing; /* per iteration (in r), for the stopping test */
	double *cv;             /* per iteration: variation of the NN spacing (std / mean) */
	size_t *moving;         /* per iteration: points that moved more than min_move_r, or escaped */
	dp_grid input, surface, skeleton;
	float scanner[3];       /* towards the scanner (face_scanner); all zero: none */
	int at_eye;             /* facing the scanner's eye at `eye`, per point, instead */
	double eye[3];
	float scanner_cos;
} work;

static void work_free(work *w)
{
	for (int k = 0; k < A_COUNT; k++)
		free(w->a[k]);
	free(w->cov);
	free(w->best);
	free(w->escape);
	dp_ball_set_free(&w->balls);
	dp_silhouette_free(&w->outline);
	free(w->of);
	free(w->move);
	free(w->spacing);
	free(w->cv);
	free(w->moving);
	dp_grid_free(&w->input);
	dp_grid_free(&w->surface);
	dp_grid_free(&w->skeleton);
}

static dp_status work_alloc(work *w, size_t n, int max_iters, dp_error *err)
{
	memset(w, 0, sizeof *w);
	int ok = 1;
	for (int k = 0; k < A_COUNT; k++)
		ok &= (w->a[k] = dp_alloc_array(n, sizeof(float))) != NULL;
	ok &= (w->cov = dp_alloc_array(n, 6 * sizeof(float))) != NULL;
	ok &= (w->best = dp_alloc_array(n, sizeof(int32_t))) != NULL;
	ok &= (w->escape = dp_alloc_array(n, sizeof(int32_t))) != NULL;
	ok &= (w->of = dp_alloc_array(n, sizeof(uint32_t))) != NULL;
	ok &= (w->move = dp_alloc_array((size_t)max_iters + 1, sizeof(double))) != NULL;
	ok &= (w->spacing = dp_alloc_array((size_t)max_iters + 1, sizeof(double))) != NULL;
	ok &= (w->cv = dp_alloc_array((size_t)max_iters + 1, sizeof(double))) != NULL;
	ok &= (w->moving = dp_alloc_array((size_t)max_iters + 1, sizeof(size_t))) != NULL;
	if (!ok) {
		work_free(w);
		return dp_fail(err, DP_ERR_NOMEM, "surface: out of memory for %zu points and a cap of %d iterations", n,
			       max_iters);
	}
	return DP_OK;
}

static int finite3(size_t n, const float *x, const float *y, const float *z)
{
	for (size_t i = 0; i < n; i++)
		if (!isfinite(x[i]) || !isfinite(y[i]) || !isfinite(z[i]))
			return 0;
	return 1;
}

static dp_status check_balls(const dp_balls *b, size_t n, dp_error *err)
{
	if (b->n > n)
		return dp_fail(err, DP_ERR_ARG, "surface: %zu balls for %zu samples", b->n, n);
	if (b->n && (!b->x || !b->y || !b->z || !b->radius))
		return dp_fail(err, DP_ERR_ARG, "surface: the balls have no arrays");
	for (size_t i = 0; i < b->n; i++)
		if (!isfinite(b->x[i]) || !isfinite(b->y[i]) || !isfinite(b->z[i]) || !isfinite(b->radius[i]))
			return dp_fail(err, DP_ERR_ARG, "surface: ball %zu is not finite", i);
	return DP_OK;
}

static dp_status check_args(const dp_context *ctx, const dp_cloud *input, const dp_cloud *samples,
			    const dp_cloud *skeleton, const dp_balls *balls, double r, const dp_surface_params *p,
			    const dp_cloud *surface, dp_error *err)
{
	if (!ctx || !input || !samples || !skeleton || !surface)
		return dp_fail(err, DP_ERR_ARG, "surface: NULL argument");
	if (surface == input || surface == samples || surface == skeleton)
		return dp_fail(err, DP_ERR_ARG, "surface: the output cloud must not be an input");
	if (samples->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "surface: no samples");
	if (input->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "surface: the input holds no points");
	if (!input->x || !input->y || !input->z || !samples->x || !samples->y || !samples->z || !skeleton->x ||
	    !skeleton->y || !skeleton->z)
		return dp_fail(err, DP_ERR_ARG, "surface: a cloud has no position arrays");
	if (!samples->nx || !samples->ny || !samples->nz)
		return dp_fail(err, DP_ERR_ARG, "surface: the samples have no normals");
	if (skeleton->n != samples->n)
		return dp_fail(err, DP_ERR_ARG, "surface: %zu skeleton points for %zu samples", skeleton->n,
			       samples->n);
	if (samples->n > UINT32_MAX || input->n > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "surface: more points than 32-bit indices reach");
	if (!(r > 0.0) || !isfinite(r))
		return dp_fail(err, DP_ERR_ARG, "surface: spacing r = %g is not a positive number", r);
	if (!(p->sigma_p > 0.0) || !(p->mu_hat >= 0.0 && p->mu_hat <= 1.0) || !(p->tangent_floor_r > 0.0) ||
	    !(p->slide_reach_r >= 0.0) || !isfinite(p->slide_reach_r * r) ||
	    !(p->normal_radius_r > 0.0) || !(p->reattach_radius_r > 0.0) || p->max_iters < 0 || p->window < 1 ||
	    !(p->min_drop >= 0.0 && p->min_drop < 1.0) || !(p->min_growth >= 0.0) ||
	    !(p->min_move_r >= 0.0) || !isfinite(p->min_move_r) ||
	    !(p->escape_margin_r >= 0.0) || !isfinite(p->escape_margin_r * r) ||
	    !(p->end_smoothing_r >= 0.0) || !isfinite(p->end_smoothing_r * r) ||
	    (p->prior != DP_SURFACE_PRIOR_VOLUME && p->prior != DP_SURFACE_PRIOR_MINIMAL) ||
	    !(p->silhouette_grazing >= 0.0 && p->silhouette_grazing <= 1.0) || !(p->silhouette_margin_r >= 0.0) ||
	    !isfinite(p->silhouette_margin_r * r) || !(p->silhouette_edge_margin_r >= 0.0) ||
	    !isfinite(p->silhouette_edge_margin_r * r) || !isfinite(p->silhouette_axis[0]) ||
	    !isfinite(p->silhouette_axis[1]) || !isfinite(p->silhouette_axis[2]) ||
	    !isfinite(p->sigma_p * r) || !isfinite(p->normal_radius_r * r) || !isfinite(p->reattach_radius_r * r))
		return dp_fail(err, DP_ERR_ARG, "surface: a parameter is out of range");
	if (dp_scanner_check(p, "surface: ", err) != DP_OK)
		return DP_ERR_ARG;
	if (!finite3(input->n, input->x, input->y, input->z))
		return dp_fail(err, DP_ERR_ARG, "surface: non-finite input point");
	if (!finite3(samples->n, samples->x, samples->y, samples->z) ||
	    !finite3(samples->n, samples->nx, samples->ny, samples->nz))
		return dp_fail(err, DP_ERR_ARG, "surface: non-finite sample or normal");
	if (!finite3(skeleton->n, skeleton->x, skeleton->y, skeleton->z))
		return dp_fail(err, DP_ERR_ARG, "surface: non-finite skeleton point");
	return balls ? check_balls(balls, samples->n, err) : DP_OK;
}

/* The normals in the surface grid's order, for the same-sided tests. */
static void gather_normals(work *w)
{
	dp_grid_gather(&w->surface, w->a[A_NX], w->a[A_GNX]);
	dp_grid_gather(&w->surface, w->a[A_NY], w->a[A_GNY]);
	dp_grid_gather(&w->surface, w->a[A_NZ], w->a[A_GNZ]);
}

/* Dpoint lengths and their grid-order copy for the neighbour pass, and each
 * point's side for the data term: input counts when it lies in front of the
 * inner end along m_i ((c - p)·m + |p - q| > 0). Without the test, or where
 * the dpoint has no length to tell a side by, s = 0 admits all input. */
static void lengths(work *w, size_t n, double r, int same_side)
{
	float **a = w->a;
	float min_len = DP_PAIR_EPS * (float)r;
	for (size_t i = 0; i < n; i++) {
		float d[3] = {a[A_PX][i] - a[A_QX][i], a[A_PY][i] - a[A_QY][i], a[A_PZ][i] - a[A_QZ][i]};
		float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
		int sided = same_side && len > min_len;
		a[A_LEN][i] = len;
		for (int c = 0; c < 3; c++)
			a[A_SX + c][i] = sided ? d[c] / len : 0.0f;
		a[A_DEPTH][i] = sided ? len : 1.0f;
	}
	dp_grid_gather(&w->surface, a[A_LEN], a[A_GLEN]);
	gather_normals(w);
}

/* The dpoint orientation m_i of the current p_i and its length; the normal
 * where the dpoint has no length. */
static void dpoint(float **a, size_t i, float min_len, float m[3], float *len_out)
{
	float d[3] = {a[A_PX][i] - a[A_QX][i], a[A_PY][i] - a[A_QY][i], a[A_PZ][i] - a[A_QZ][i]};
	float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	for (int c = 0; c < 3; c++)
		m[c] = len > min_len ? d[c] / len : a[A_NX + c][i];
	*len_out = len;
}

/* The tangential part of the update, p_i += μ̂ R_i. It runs first, so that
 * the prior sees where the point has slid to. Applied together (as Eq. 6 is
 * printed), the prior restores |p - q| as it was before the slide, and each
 * tangential step then lengthens the dpoint by |μ̂R|²/2ℓ: an outward drift of
 * the unsupported regions that the length averaging spreads (measured: the
 * far half of a one-sided sphere ended 0.07 R outside after 100 iterations;
 * with the slide first the whole output is 0.006 R from the sphere on
 * average).
 *
 * With slide_reach_r a point whose nearest neighbour is farther than that
 * does not slide: R_i is cleared, so the settle step, which counts the
 * slide in the iteration's move, sees none either. R_i is the β̂-weighted
 * mean of the neighbours' tangential offsets, whatever their distance, so an
 * isolated point is pushed by the whole offset (1.4 r per iteration from
 * neighbours 3.5 r away) and runs off until none is within σp r: the loose
 * halo around a one-view scan's completed ears and under the demo chair's
 * seat. Measured (bench_completion, defaults otherwise): a reach of 1.5 r
 * takes the chair's flipped normals 7.2% -> 0.7% and its 95th percentile
 * 0.048 -> 0.014 diagonals, the two-view bunny's flips 3.9% -> 1.6%, but
 * coverage falls (chair 0.87 -> 0.69, bunny 0.966 -> 0.927, one-view bunny
 * 0.76 -> 0.57), because spreading into a hole thins its front the same way:
 * completion by repulsion needs the escape. Hence off by default. */
static void slide(work *w, size_t n, const dp_surface_params *p, double r)
{
	float **a = w->a, mu = (float)p->mu_hat;
	float reach = (float)(p->slide_reach_r * r);
	for (size_t i = 0; i < n; i++) {
		if (reach > 0.0f && a[A_NN][i] > reach)
			a[A_RX][i] = a[A_RY][i] = a[A_RZ][i] = 0.0f;
		for (int c = 0; c < 3; c++)
			a[A_PX + c][i] += mu * a[A_RX + c][i];
	}
}

/* The data and prior part of the update of DESIGN 4.3 at the slid p_i with
 * the (re-attached) q_i. Returns the mean move of the whole iteration in r;
 * *moving receives how many points moved more than min_move_r. */
static double settle(work *w, size_t n, double r, const dp_surface_params *p, size_t *moving)
{
	float **a = w->a;
	float min_len = DP_PAIR_EPS * (float)r, mu = (float)p->mu_hat;
	double total = 0.0, still2 = (p->min_move_r * r) * (p->min_move_r * r);
	size_t count = 0;
	for (size_t i = 0; i < n; i++) {
		float nrm[3] = {a[A_NX][i], a[A_NY][i], a[A_NZ][i]};
		float m[3], len;
		dpoint(a, i, min_len, m, &len);
		float L = a[A_L][i];
		float gamma = 1.0f / (1.0f + a[A_VAR][i]);
		float support = a[A_ETA][i] * a[A_SA][i];
		/* c̄ - p at the slid point is the offset measured before the slide
		 * minus the slide; along n the slide (orthogonal to n) drops out. */
		float on = a[A_OX][i] * nrm[0] + a[A_OY][i] * nrm[1] + a[A_OZ][i] * nrm[2];
		float pull[3];
		for (int c = 0; c < 3; c++)
			pull[c] = p->data_along_normal ? on * nrm[c] : a[A_OX + c][i] - mu * a[A_RX + c][i];
		float g;
		if (p->prior == DP_SURFACE_PRIOR_VOLUME) {
			g = gamma * (L - len);
		} else {
			/* the centroid offset was measured before the slide, like c̄ */
			float to_centroid = 0.0f;
			for (int c = 0; c < 3; c++)
				to_centroid += (a[A_MX + c][i] - mu * a[A_RX + c][i]) * m[c];
			g = gamma * fminf(to_centroid, 0.0f);
		}
		float inv = 1.0f / (gamma + support);
		double move2 = 0.0;
		for (int c = 0; c < 3; c++) {
			float step = (support * pull[c] + g * m[c]) * inv;
			a[A_PX + c][i] += step;
			double whole = (double)step + (double)mu * a[A_RX + c][i];
			move2 += whole * whole;
		}
		total += sqrt(move2);
		count += move2 > still2;
	}
	*moving = count;
	return total / (double)n / r;
}

/* The skeleton grid that re-attachment searches, one point per spot: a
 * ball's skeleton contracts to one spot, refined levels copy inner ends, and
 * every query scanned every copy (measured: a one-view sphere at 32000 deep
 * points, 51 distinct positions, and re-attachment 16e9 of the stage's 28e9
 * pairs). Points in one cube of side SKELETON_MERGE_R r count as the first
 * of them, an existing skeleton point, and each inner end starts there: one
 * never re-attached ends up to 0.09 r from where the skeleton put it. */
static dp_status skeleton_grid(work *w, const dp_cloud *k, size_t n, double r, float cell, dp_error *err)
{
	float *kx = w->a[A_KX], *ky = w->a[A_KY], *kz = w->a[A_KZ];
	double inv = 1.0 / (SKELETON_MERGE_R * r);
	const float *src[3] = {k->x, k->y, k->z};
	float *key[3] = {kx, ky, kz};
	for (int c = 0; c < 3; c++)
		for (size_t i = 0; i < n; i++) {
			/* beyond float range the exact coordinate is the key */
			float cube = (float)floor(src[c][i] * inv);
			key[c][i] = isfinite(cube) ? cube : src[c][i];
		}
	size_t distinct;
	dp_status s = dp_distinct(n, kx, ky, kz, w->of, &distinct, err);
	if (s != DP_OK)
		return s;
	size_t m = 0;
	for (size_t i = 0; i < n; i++) {
		/* every inner end starts at its cube's point, so the first
		 * re-attachment counts only real moves */
		uint32_t first = w->of[i];
		w->a[A_QX][i] = w->a[A_HX][i] = k->x[first];
		w->a[A_QY][i] = w->a[A_HY][i] = k->y[first];
		w->a[A_QZ][i] = w->a[A_HZ][i] = k->z[first];
		if (first == i) {
			kx[m] = k->x[i];
			ky[m] = k->y[i];
			kz[m++] = k->z[i];
		}
	}
	return dp_grid_build(&w->skeleton, m, kx, ky, kz, cell, err);
}

/* Re-attachment: q_i ← the chosen skeleton point. Returns how many changed. */
static size_t reattach(work *w, size_t n)
{
	float **a = w->a;
	const dp_grid *k = &w->skeleton;
	size_t changed = 0;
	for (size_t i = 0; i < n; i++) {
		int32_t b = w->best[i];
		if (b < 0 || (k->x[b] == a[A_HX][i] && k->y[b] == a[A_HY][i] && k->z[b] == a[A_HZ][i]))
			continue;
		a[A_QX][i] = a[A_HX][i] = k->x[b];
		a[A_QY][i] = a[A_HY][i] = k->y[b];
		a[A_QZ][i] = a[A_HZ][i] = k->z[b];
		changed++;
	}
	return changed;
}

/* Lateral smoothing of the inner ends: q_i = h_i + T_i (a_i - h_i), h_i the
 * skeleton point q_i hangs on (re-attachment's choice), a_i the mean of those
 * of P_i (surface_ends in operators.h, weights exp(-(d/σ r)²)), T_i = I -
 * n_i n_iᵀ. The skeleton is a set of spots, and where a sheet or a curve has
 * contracted into clumps a few r apart, a point over a hole hangs on a spot
 * to one side. Traced on the demo chair's back rest (4.8 r thick, scanned
 * from the front, holes of 2-3 r in its skeleton sheet): the dpoint leans,
 * the prior holds the point on the sphere of radius L about that spot, which
 * dips into the plate; as input support fades the normal follows the leaning
 * dpoint, and the slide along the leaning tangent plane carries the point
 * into the middle of the plate with a normal along it (40 iterations from
 * the front face to 1 r inside): half the chair's flipped normals. Only the
 * part of the offset across n_i is taken, so the inner end moves under the
 * point and never deeper or shallower: the whole offset moved unsupported
 * backs inwards (one-view bunny coverage 0.81 -> 0.75, chair 0.98 -> 0.93).
 * Means over WLOP seeds 1-6 (bench_completion: coverage / flipped / spacing
 * variation / 95th percentile): one-view bunny 0.807 / 2.32% / 0.49 / 0.045
 * -> 0.797 / 1.90% / 0.47 / 0.042, two views 0.951 / 0.90% / 0.25 / 0.039 ->
 * 0.950 / 0.43% / 0.23 / 0.039, chair 0.982 / 2.42% / 0.26 / 0.0145 -> 0.965
 * / 1.70% / 0.21 / 0.0137. σ = 1.5 r did half as much for the chair (seeds
 * 1-3: 2.24% flipped), 2.5 r cost it coverage (0.938). The stage hands back
 * h, not q: the next level re-attaches to the skeleton, and smoothed ends as
 * its targets spread a ball's one spot into a cloud that inner ends wandered
 * over (one-view sphere at 32000 deep points: coverage 0.985 -> 0.925; with
 * h, 0.986). */
static void smooth_ends(work *w, size_t n)
{
	float **a = w->a;
	for (size_t i = 0; i < n; i++) {
		if (!(a[A_EW][i] > 0.0f)) {
			/* no neighbour on its side within reach, not even itself */
			for (int c = 0; c < 3; c++)
				a[A_QX + c][i] = a[A_HX + c][i];
			continue;
		}
		float d[3], dn = 0.0f;
		for (int c = 0; c < 3; c++) {
			d[c] = a[A_PX + c][i] + a[A_AX + c][i] - a[A_HX + c][i];
			dn += d[c] * a[A_NX + c][i];
		}
		for (int c = 0; c < 3; c++)
			a[A_QX + c][i] = a[A_HX + c][i] + d[c] - dn * a[A_NX + c][i];
	}
}

typedef struct normals_job {
	work *w;
	float min_len;
	int orient_by_dpoint;
	size_t disagreeing[DP_PARALLEL_MAX];
	size_t turned[DP_PARALLEL_MAX];
} normals_job;

/* Points [begin, end): each writes only its own rows. */
static void normals_range(void *arg, size_t begin, size_t end, int part)
{
	normals_job *job = arg;
	float **a = job->w->a;
	float min_len = job->min_len;
	int orient_by_dpoint = job->orient_by_dpoint;
	const float *sc = job->w->scanner;
	int at_eye = job->w->at_eye, facing = at_eye || sc[0] != 0.0f || sc[1] != 0.0f || sc[2] != 0.0f;
	const double *eye = job->w->eye;
	size_t disagreeing = 0, turned = 0;
	for (size_t i = begin; i < end; i++) {
		const float *c = job->w->cov + 6 * i;
		double s[6] = {c[0], c[1], c[2], c[3], c[4], c[5]}, ev[3], v0[3];
		double old[3] = {a[A_NX][i], a[A_NY][i], a[A_NZ][i]}, pca[3] = {old[0], old[1], old[2]};
		float m[3], len;
		dpoint(a, i, min_len, m, &len);
		dp_eig3_smallest(s, ev, v0);
		if (ev[1] > PCA_MIN_SPREAD) {
			double by_old = v0[0] * old[0] + v0[1] * old[1] + v0[2] * old[2];
			double by_m = v0[0] * m[0] + v0[1] * m[1] + v0[2] * m[2];
			int has_len = len > min_len;
			disagreeing += has_len && (by_old < 0.0) != (by_m < 0.0);
			/* Where input holds the point its old normal carries the data's
			 * orientation (the MST's, then this update's), which is right
			 * where the dpoint is not: a thin part's tip whose inner end
			 * sank out of it (the two-view bunny's ear). */
			int held = a[A_ETA][i] - 1.0f >= HELD_SUPPORT;
			double sign = (orient_by_dpoint && has_len && !held ? by_m : by_old) < 0.0 ? -1.0 : 1.0;
			/* input that holds a point was scanned, and so faced the
			 * scanner (scanner.h) */
			double to[3] = {sc[0], sc[1], sc[2]}, dist = 1.0;
			if (at_eye) {
				for (int k = 0; k < 3; k++)
					to[k] = eye[k] - a[A_PX + k][i];
				dist = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
			}
			double by_scanner = dist > 0.0 ? (v0[0] * to[0] + v0[1] * to[1] + v0[2] * to[2]) / dist : 0.0;
			if (facing && held && fabs(by_scanner) > job->w->scanner_cos &&
			    (by_scanner < 0.0) != (sign < 0.0)) {
				sign = -sign;
				turned++;
			}
			for (int k = 0; k < 3; k++)
				pca[k] = sign * v0[k];
		}
		for (int k = 0; k < 3; k++)
			a[A_TX + k][i] = (float)pca[k];
		double wpca = (double)a[A_ETA][i] - 1.0, v[3], norm = 0.0;
		for (int k = 0; k < 3; k++) {
			v[k] = wpca * pca[k] + m[k];
			norm += v[k] * v[k];
		}
		norm = sqrt(norm);
		if (!(norm > 0.0))
			continue; /* ñ = -m exactly: keep the old normal */
		a[A_NX][i] = (float)(v[0] / norm);
		a[A_NY][i] = (float)(v[1] / norm);
		a[A_NZ][i] = (float)(v[2] / norm);
	}
	job->disagreeing[part] = disagreeing;
	job->turned[part] = turned;
}

/* n_i = normalize((η - 1) ñ + m) from the covariances of the new positions.
 * ñ, the PCA normal, has no sign of its own. Taken from the old normal, a
 * flip survives wherever the data weight η - 1 is large enough to outvote
 * m: a flipped point keeps its flipped neighbours flipped (measured: 5-7% of
 * real scans' surface points, nearly all in completed regions). The deep
 * point knows better there: m_i runs from the inner end outwards by
 * construction, so with orient_by_dpoint ñ takes the sign of m_i wherever
 * the dpoint has a length and no input holds the point; where input holds
 * it, the old normal, which carries the data's orientation (normals_range).
 * Where the scan was taken from one side (w->scanner), a held point's ñ
 * faces the scanner wherever it points clearly along the view axis.
 * Returns how many PCA normals the old rule would have signed against m_i;
 * *turned receives how many held ones the scanner turned. */
static size_t update_normals(int threads, work *w, size_t n, double r, int orient_by_dpoint, size_t *turned)
{
	normals_job job = {.w = w, .min_len = DP_PAIR_EPS * (float)r, .orient_by_dpoint = orient_by_dpoint};
	int parts = dp_parallel_for(threads, n, NORMALS_MIN_ITEMS, normals_range, &job);
	size_t disagreeing = 0;
	*turned = 0;
	for (int k = 0; k < parts; k++) {
		disagreeing += job.disagreeing[k];
		*turned += job.turned[k];
	}
	return disagreeing;
}

/* The inside test (balls.h): decides every move first, from the inner ends
 * as they are, then moves. Returns how many moved. */
static size_t escape(work *w, size_t n, double r, const dp_surface_params *p)
{
	float **a = w->a;
	float margin = (float)(p->escape_margin_r * r);
	const dp_ball_set *b = &w->balls;
	for (size_t i = 0; i < n; i++) {
		float dist = 0.0f;
		int32_t k = a[A_ETA][i] - 1.0f < HELD_SUPPORT
				    ? dp_ball_set_deepest(b, a[A_PX][i], a[A_PY][i], a[A_PZ][i], a[A_NX][i], a[A_NY][i],
							  a[A_NZ][i], margin, &dist)
				    : -1;
		w->escape[i] = dist > 0.0f ? k : -1;
		a[A_EDIST][i] = dist;
		if (w->escape[i] >= 0)
			for (int d = 0; d < 3; d++) {
				/* A_A is free again: the smoothing has used it */
				a[A_EX + d][i] = a[A_QX + d][b->row[k]];
				a[A_AX + d][i] = a[A_HX + d][b->row[k]];
			}
	}
	size_t moved = 0;
	for (size_t i = 0; i < n; i++) {
		int32_t k = w->escape[i];
		if (k < 0)
			continue;
		float c[3] = {b->grid.x[k], b->grid.y[k], b->grid.z[k]}, f = b->radius[k] / a[A_EDIST][i];
		for (int d = 0; d < 3; d++) {
			a[A_PX + d][i] = c[d] + f * (a[A_PX + d][i] - c[d]);
			a[A_QX + d][i] = a[A_EX + d][i];
			a[A_HX + d][i] = a[A_AX + d][i];
		}
		moved++;
	}
	return moved;
}

/* Done when in each of the last `window` iterations at most one point in
 * STILL_PER points moved more than min_move_r or escaped: the set has come
 * to rest (dpoints.h has the measurement). Otherwise compares the last
 * `window` iterations with the `window` before them (means, as single
 * iterations jitter by a few per cent): done when the mean move has not
 * fallen by min_drop, the spacing (the area per point is ∝ its square) has
 * not grown by min_growth and its variation has not fallen by min_growth. */
static int stop_test(const work *w, size_t n, int t, const dp_surface_params *p)
{
	int k = p->window;
	if (p->min_move_r > 0.0 && t >= k) {
		int resting = 1;
		for (int j = 0; j < k && resting; j++)
			resting = w->moving[t - j] <= n / STILL_PER;
		if (resting)
			return 1;
	}
	if (t < 2 * k)
		return 0;
	double move_new = 0.0, move_old = 0.0, sp_new = 0.0, sp_old = 0.0, cv_new = 0.0, cv_old = 0.0;
	for (int j = 0; j < k; j++) {
		move_new += w->move[t - j];
		move_old += w->move[t - k - j];
		sp_new += w->spacing[t - j];
		sp_old += w->spacing[t - k - j];
		cv_new += w->cv[t - j];
		cv_old += w->cv[t - k - j];
	}
	return move_new > (1.0 - p->min_drop) * move_old && sp_new < (1.0 + p->min_growth) * sp_old &&
	       cv_new > (1.0 - p->min_growth) * cv_old;
}

/* The view axis, given or, with none, the one the samples' normals (unit,
 * in A_N*) show, if any: the outline the points are held in (silhouette.h)
 * and the side the scan was taken from (scanner.h), unless the scanner's eye
 * is given. */
static dp_status view(work *w, const dp_cloud *input, const dp_cloud *scan, size_t n, double r,
		      const dp_surface_params *p, dp_surface_stats *st, dp_error *err)
{
	w->scanner_cos = (float)p->face_scanner_cos;
	if (p->face_scanner && p->use_viewpoint) {
		w->at_eye = st->scanner_at_eye = 1;
		memcpy(w->eye, p->viewpoint, sizeof w->eye);
	}
	float axis[3];
	int found = 0;
	dp_silhouette_pick(p->silhouette_axis, n, w->a[A_NX], w->a[A_NY], w->a[A_NZ], p->silhouette_grazing, &found,
			   axis, &st->silhouette_grazing);
	if (!found)
		return DP_OK;
	int side = p->scanner_side;
	dp_status s;
	if (p->face_scanner && !w->at_eye && !side &&
	    (s = dp_scanner_side(n, w->a[A_PX], w->a[A_PY], w->a[A_PZ], w->a[A_NX], w->a[A_NY], w->a[A_NZ], axis,
				 p->face_scanner_cos, r, &side, err)) != DP_OK)
		return s;
	if (p->face_scanner && !w->at_eye && side) {
		for (int c = 0; c < 3; c++)
			st->scanner[c] = w->scanner[c] = (float)side * axis[c];
	}
	if (!p->silhouette)
		return DP_OK;
	for (int c = 0; c < 3; c++)
		st->silhouette_axis[c] = axis[c];
	return dp_silhouette_build(&w->outline, input, axis, r, p->silhouette_margin_r * r, scan,
				   p->silhouette_edge_margin_r * r, err);
}

static dp_status run(dp_context *ctx, const char *stage, const dp_cloud *input, const dp_cloud *samples,
		     const dp_cloud *scan, dp_cloud *skeleton, const dp_balls *balls, double r,
		     const dp_surface_params *p, work *w, dp_surface_stats *st, dp_error *err)
{
	size_t n = samples->n;
	float **a = w->a;
	float fr = (float)r, radius = (float)(p->sigma_p * r), min_d2 = (DP_PAIR_EPS * radius) * (DP_PAIR_EPS * radius);
	float normal_radius = (float)(p->normal_radius_r * r), reattach_radius = (float)(p->reattach_radius_r * r);
	float surface_cell = fmaxf(radius, normal_radius);
	float side_cos = p->same_side ? SAME_SIDE_COS : ANY_SIDE_COS;
	int smoothing = p->end_smoothing_r > 0.0;
	float end_sigma = (float)(p->end_smoothing_r * r);
	dp_status s;

	memcpy(a[A_PX], samples->x, n * sizeof(float));
	memcpy(a[A_PY], samples->y, n * sizeof(float));
	memcpy(a[A_PZ], samples->z, n * sizeof(float));
	for (size_t i = 0; i < n; i++) {
		double x = samples->nx[i], y = samples->ny[i], z = samples->nz[i];
		double len = sqrt(x * x + y * y + z * z);
		if (!(len > 0.0))
			return dp_fail(err, DP_ERR_ARG, "surface: sample %zu has a zero normal", i);
		a[A_NX][i] = a[A_TX][i] = (float)(x / len);
		a[A_NY][i] = a[A_TY][i] = (float)(y / len);
		a[A_NZ][i] = a[A_TZ][i] = (float)(z / len);
	}
	if ((s = dp_grid_build(&w->input, input->n, input->x, input->y, input->z, radius, err)) != DP_OK ||
	    (s = skeleton_grid(w, skeleton, n, r, reattach_radius, err)) != DP_OK ||
	    (s = dp_grid_build(&w->surface, n, a[A_PX], a[A_PY], a[A_PZ], surface_cell, err)) != DP_OK)
		return s;
	int escaping = balls && p->escape_margin_r > 0.0;
	if (escaping && (s = dp_ball_set_build(&w->balls, balls, (float)(BALL_SLACK_R * r), err)) != DP_OK)
		return s;
	if ((p->silhouette || p->face_scanner) && (s = view(w, input, scan, n, r, p, st, err)) != DP_OK)
		return s;

	dp_surface_data_args data = {
		.input = &w->input, .nq = n, .px = a[A_PX], .py = a[A_PY], .pz = a[A_PZ], .sx = a[A_SX],
		.sy = a[A_SY], .sz = a[A_SZ], .depth = a[A_DEPTH], .radius = radius,
		.r = fr, .min_d2 = min_d2, .eta = a[A_ETA], .sum_alpha = a[A_SA], .ox = a[A_OX], .oy = a[A_OY],
		.oz = a[A_OZ],
	};
	dp_surface_neighbour_args nb = {
		.surface = &w->surface, .glen = a[A_GLEN], .gnx = a[A_GNX], .gny = a[A_GNY], .gnz = a[A_GNZ], .nq = n,
		.px = a[A_PX], .py = a[A_PY], .pz = a[A_PZ], .nx = a[A_NX], .ny = a[A_NY], .nz = a[A_NZ],
		.len = a[A_LEN], .radius = radius, .r = fr, .min_d2 = min_d2, .tfloor = (float)p->tangent_floor_r,
		.side_cos = side_cos, .L = a[A_L], .var = a[A_VAR],
		.rx = a[A_RX], .ry = a[A_RY], .rz = a[A_RZ], .nn = a[A_NN], .mx = a[A_MX], .my = a[A_MY],
		.mz = a[A_MZ],
	};
	dp_surface_ends_args ends = {
		.surface = &w->surface, .gnx = a[A_GNX], .gny = a[A_GNY], .gnz = a[A_GNZ], .nq = n, .px = a[A_PX],
		.py = a[A_PY], .pz = a[A_PZ], .nx = a[A_NX], .ny = a[A_NY], .nz = a[A_NZ], .gsx = a[A_GHX],
		.gsy = a[A_GHY], .gsz = a[A_GHZ], .radius = fminf(END_REACH * end_sigma, surface_cell),
		.sigma = end_sigma, .side_cos = side_cos, .wsum = a[A_EW], .ox = a[A_AX], .oy = a[A_AY], .oz = a[A_AZ],
	};
	dp_surface_covariance_args cov = {
		.surface = &w->surface, .gnx = a[A_GNX], .gny = a[A_GNY], .gnz = a[A_GNZ], .nq = n, .px = a[A_PX],
		.py = a[A_PY], .pz = a[A_PZ], .nx = a[A_NX], .ny = a[A_NY], .nz = a[A_NZ], .radius = normal_radius,
		.r = fr, .side_cos = side_cos, .cov = w->cov,
	};
	dp_surface_reattach_args re = {
		.skeleton = &w->skeleton, .nq = n, .qx = a[A_QX], .qy = a[A_QY], .qz = a[A_QZ], .px = a[A_PX],
		.py = a[A_PY], .pz = a[A_PZ], .nx = a[A_TX], .ny = a[A_TY], .nz = a[A_TZ],
		.radius = reattach_radius, .r = fr, .best = w->best, .dist2 = a[A_D2],
	};

	for (int t = 1; t <= p->max_iters; t++) {
		lengths(w, n, r, p->same_side);
		if ((s = dp_op_surface_data(ctx, &data, err)) != DP_OK ||
		    (s = dp_op_surface_neighbour(ctx, &nb, err)) != DP_OK)
			return s;
		double spacing = 0.0, spacing2 = 0.0;
		for (size_t i = 0; i < n; i++) {
			spacing += a[A_NN][i];
			spacing2 += (double)a[A_NN][i] * a[A_NN][i];
		}
		double mean_nn = spacing / (double)n;
		w->spacing[t] = mean_nn / r;
		w->cv[t] = mean_nn > 0.0 ? sqrt(fmax(spacing2 / (double)n - mean_nn * mean_nn, 0.0)) / mean_nn : 0.0;
		slide(w, n, p, r);
		if (p->reattach) {
			if ((s = dp_op_surface_reattach(ctx, &re, err)) != DP_OK)
				return s;
			st->reattached += reattach(w, n);
		}
		if (smoothing) {
			for (int c = 0; c < 3; c++)
				dp_grid_gather(&w->surface, a[A_HX + c], a[A_GHX + c]);
			if ((s = dp_op_surface_ends(ctx, &ends, err)) != DP_OK)
				return s;
			smooth_ends(w, n);
		}
		w->move[t] = settle(w, n, r, p, &w->moving[t]);
		/* an escape is a jump, not a step of the iteration's flow, and is
		 * left out of the mean move the stopping test watches (a few points
		 * escape in most iterations of a one-view scan), but a set in which
		 * points still jump is not at rest */
		if (escaping) {
			size_t escaped = escape(w, n, r, p);
			st->escaped += escaped;
			w->moving[t] += escaped;
		}
		/* after every other move: a point pushed out and held back each
		 * iteration is at rest against the outline, not moving */
		if (w->outline.nearest)
			st->silhouette_held += dp_silhouette_hold(&w->outline, n, a[A_PX], a[A_PY], a[A_PZ]);
		if ((s = dp_grid_build(&w->surface, n, a[A_PX], a[A_PY], a[A_PZ], surface_cell, err)) != DP_OK)
			return s;
		gather_normals(w);
		if ((s = dp_op_surface_covariance(ctx, &cov, err)) != DP_OK)
			return s;
		size_t turned;
		st->normals_disagreeing = update_normals(ctx->threads, w, n, r, p->orient_by_dpoint, &turned);
		st->scanner_turned += turned;
		st->iterations = t;
		st->last_mean_move = w->move[t];
		if ((s = dp_progress(ctx, stage, t, w->move[t], err)) != DP_OK)
			return s;
		if (stop_test(w, n, t, p)) {
			st->converged = 1;
			break;
		}
	}
	if (st->iterations > 0)
		st->spacing_growth = w->spacing[st->iterations] / w->spacing[1];
	/* η of the final positions: the sheet step reads it, and the caller
	 * gets it. */
	lengths(w, n, r, p->same_side);
	if ((s = dp_op_surface_data(ctx, &data, err)) != DP_OK)
		return s;
	/* Without an iteration the spacing is unmeasured and the normals are
	 * the samples'. */
	if (p->sheet_points && st->iterations > 0) {
		/* A_E and A_EDIST are free once the iterations are over */
		dp_sheet_points_args sheet = {
			.n = n, .px = a[A_PX], .py = a[A_PY], .pz = a[A_PZ], .nx = a[A_NX], .ny = a[A_NY], .nz = a[A_NZ],
			.hx = a[A_HX], .hy = a[A_HY], .hz = a[A_HZ], .eta = a[A_ETA], .held_support = HELD_SUPPORT,
			.spots = w->skeleton.n, .sx = w->skeleton.x, .sy = w->skeleton.y, .sz = w->skeleton.z,
			/* the points' spacing now: completion spreads them (the chair's
			 * by 1.6 times), and in r the faces' sampling windows and the
			 * off-sheet distance are too small (chair flipped 1.29%) */
			.r = r * w->spacing[st->iterations],
			.to_x = a[A_EX], .to_y = a[A_EY], .to_z = a[A_EZ], .chosen = a[A_EDIST],
		};
		if ((s = dp_sheet_points_lift(&sheet, &st->sheet_points, err)) != DP_OK)
			return s;
		if (st->sheet_points > 0) {
			/* a lifted point may have crossed the outline */
			if (w->outline.nearest)
				st->silhouette_held += dp_silhouette_hold(&w->outline, n, a[A_PX], a[A_PY], a[A_PZ]);
			lengths(w, n, r, p->same_side);
			return dp_op_surface_data(ctx, &data, err);
		}
	}
	return DP_OK;
}

dp_status dp_surface(dp_context *ctx, const dp_cloud *input, const dp_cloud *samples, dp_cloud *skeleton,
		     const dp_balls *balls, double r, const dp_surface_params *params, dp_cloud *surface,
		     float *eta, dp_surface_stats *stats, dp_error *err)
{
	return dp_surface_as(ctx, "surface", input, samples, samples, skeleton, balls, r, params, surface, eta, stats,
			     err);
}

dp_status dp_surface_as(dp_context *ctx, const char *stage, const dp_cloud *input, const dp_cloud *samples,
			const dp_cloud *scan, dp_cloud *skeleton, const dp_balls *balls, double r,
			const dp_surface_params *params, dp_cloud *surface, float *eta, dp_surface_stats *stats,
			dp_error *err)
{
	double t0 = dp_seconds();
	dp_surface_params defaults;
	if (!params) {
		dp_surface_params_default(&defaults);
		params = &defaults;
	}
	if (surface && surface != input && surface != samples && surface != skeleton)
		memset(surface, 0, sizeof *surface);
	dp_status s = check_args(ctx, input, samples, skeleton, balls, r, params, surface, err);
	if (s != DP_OK)
		return s;
	size_t n = samples->n;
	work w;
	if ((s = work_alloc(&w, n, params->max_iters, err)) != DP_OK)
		return s;
	dp_surface_stats st = {0};
	double pairs0 = ctx->pair_evaluations;
	s = run(ctx, stage, input, samples, scan, skeleton, balls, r, params, &w, &st, err);
	if (s == DP_OK)
		s = dp_cloud_alloc(surface, n, 1, err);
	if (s == DP_OK) {
		size_t bytes = n * sizeof(float);
		memcpy(surface->x, w.a[A_PX], bytes);
		memcpy(surface->y, w.a[A_PY], bytes);
		memcpy(surface->z, w.a[A_PZ], bytes);
		memcpy(surface->nx, w.a[A_NX], bytes);
		memcpy(surface->ny, w.a[A_NY], bytes);
		memcpy(surface->nz, w.a[A_NZ], bytes);
		if (eta)
			memcpy(eta, w.a[A_ETA], bytes);
		memcpy(skeleton->x, w.a[A_HX], bytes);
		memcpy(skeleton->y, w.a[A_HY], bytes);
		memcpy(skeleton->z, w.a[A_HZ], bytes);
		if (skeleton->nx) {
			memcpy(skeleton->nx, w.a[A_NX], bytes);
			memcpy(skeleton->ny, w.a[A_NY], bytes);
			memcpy(skeleton->nz, w.a[A_NZ], bytes);
		}
	}
	work_free(&w);
	st.seconds = dp_seconds() - t0;
	st.pair_evaluations = ctx->pair_evaluations - pairs0;
	if (stats)
		*stats = st;
	return s;
}
