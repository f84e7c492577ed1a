/* Sinking (paper 4.1, DESIGN 4.1): inner points start on their surface points
 * and move against the normals, smoothed over the static neighbourhood P_i,
 * until they meet an opposing front or slow down. The settled inner points are
 * the anchors H. The math is stated once, in dpoints.h beside dp_sink; the
 * neighbour sums are the operators of host/ops/operators.h. */
#include "backend/ops.h"
#include "stages/flat.h"
#include "stages/meet.h"
#include "stages/width.h"
#include "core/common.h"
#include "core/parallel.h"
#include "knn/kdtree.h"
#include "knn/knn.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void dp_sink_params_default(dp_sink_params *p)
{
	memset(p, 0, sizeof *p);
	p->sigma_p = 5.0;
	p->settle_radius_r = 1.0;
	p->front_factor = 2.0;
	p->omega_deg = 45.0;
	p->first_step_r = 0.5;
	p->slow_fraction = 0.5;
	p->max_iters = 200;
	p->medial_margin_r = 0.25;
	p->medial_fraction = 0.15;
	p->medial_fraction_cap_r = 3.0;
	p->meet_shift_r = 2.0;
	p->slow_margin_r = 1.0;
	p->width_factor = 2.0;
	p->flat_angle_deg = 10.0;
	p->wall_min_r = 0.5;
}

static dp_status check_params(const dp_sink_params *p, double r, dp_error *err)
{
	if (!(r > 0.0 && isfinite(r)))
		return dp_fail(err, DP_ERR_ARG, "sink: spacing r = %g is not a positive number", r);
	if (!(p->sigma_p > 0.0 && isfinite(p->sigma_p)))
		return dp_fail(err, DP_ERR_ARG, "sink: sigma_p = %g is not positive", p->sigma_p);
	if (!(p->settle_radius_r > 0.0 && isfinite(p->settle_radius_r)))
		return dp_fail(err, DP_ERR_ARG, "sink: settle radius %g r is not positive", p->settle_radius_r);
	if (!(p->front_factor >= 0.0 && isfinite(p->front_factor)))
		return dp_fail(err, DP_ERR_ARG, "sink: front factor %g is not a finite number >= 0", p->front_factor);
	if (!(p->omega_deg > 0.0 && p->omega_deg < 180.0))
		return dp_fail(err, DP_ERR_ARG, "sink: omega = %g degrees is not in (0, 180)", p->omega_deg);
	if (!(p->first_step_r > 0.0 && isfinite(p->first_step_r)))
		return dp_fail(err, DP_ERR_ARG, "sink: first step %g r is not positive", p->first_step_r);
	if (!(p->slow_fraction >= 0.0 && p->slow_fraction < 1.0))
		return dp_fail(err, DP_ERR_ARG, "sink: slow fraction %g is not in [0, 1)", p->slow_fraction);
	if (p->max_iters < 1)
		return dp_fail(err, DP_ERR_ARG, "sink: max_iters = %d is not >= 1", p->max_iters);
	if (!(p->medial_margin_r >= 0.0 && isfinite(p->medial_margin_r)))
		return dp_fail(err, DP_ERR_ARG, "sink: medial margin %g r is not a finite number >= 0 (0 turns the test off)",
			       p->medial_margin_r);
	if (!(p->medial_fraction >= 0.0 && p->medial_fraction < 1.0))
		return dp_fail(err, DP_ERR_ARG, "sink: medial fraction %g is not in [0, 1)", p->medial_fraction);
	if (!(p->medial_fraction_cap_r >= 0.0 && isfinite(p->medial_fraction_cap_r)))
		return dp_fail(err, DP_ERR_ARG, "sink: medial fraction cap %g r is not a finite number >= 0",
			       p->medial_fraction_cap_r);
	if (!(p->meet_shift_r >= 0.0 && isfinite(p->meet_shift_r) && isfinite((float)(p->meet_shift_r * r))))
		return dp_fail(err, DP_ERR_ARG, "sink: meeting shift %g r is not a finite number >= 0 (0 turns it off)",
			       p->meet_shift_r);
	if (!(p->slow_margin_r >= 0.0))
		return dp_fail(err, DP_ERR_ARG, "sink: slow-down margin %g r is not a number >= 0 (a huge value such as 1e9: the paper's rule)",
			       p->slow_margin_r);
	if (!(p->width_factor >= 0.0 && isfinite(p->width_factor)))
		return dp_fail(err, DP_ERR_ARG, "sink: width factor %g is not a finite number >= 0 (0 turns the bound off)",
			       p->width_factor);
	if (!(p->flat_angle_deg >= 0.0 && p->flat_angle_deg < 90.0))
		return dp_fail(err, DP_ERR_ARG, "sink: flat-face angle %g degrees is not in [0, 90) (0 turns it off)",
			       p->flat_angle_deg);
	if (!(p->wall_min_r >= 0.0 && isfinite(p->wall_min_r)))
		return dp_fail(err, DP_ERR_ARG, "sink: thin-wall distance %g r is not a finite number >= 0 (0 turns the rule off)",
			       p->wall_min_r);
	/* the widest scale becomes a grid cell, a float */
	double widest = DP_WIDTH_MIN_SCALE_R * (double)(1u << (DP_WIDTH_SCALES - 1));
	if (p->width_factor > 0.0 && !isfinite((float)(r * widest)))
		return dp_fail(err, DP_ERR_ARG, "sink: the width bound's widest scale, %g r with r = %g, overflows a float",
			       widest, r);
	/* Lengths go to the device as floats. */
	if (!isfinite((float)(r * fmax(p->sigma_p, p->settle_radius_r * fmax(p->front_factor, 1.0)))))
		return dp_fail(err, DP_ERR_ARG, "sink: radii of r = %g overflow a float", r);
	return DP_OK;
}

static dp_status check_surface(const dp_cloud *s, dp_error *err)
{
	if (s->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "sink: the surface has no points");
	if (!s->x || !s->y || !s->z)
		return dp_fail(err, DP_ERR_ARG, "sink: the surface has no position arrays");
	if (!s->nx || !s->ny || !s->nz)
		return dp_fail(err, DP_ERR_ARG, "sink: the surface points have no normals (estimate them first)");
	for (size_t i = 0; i < s->n; i++) {
		if (!isfinite(s->x[i]) || !isfinite(s->y[i]) || !isfinite(s->z[i]))
			return dp_fail(err, DP_ERR_ARG, "sink: surface point %zu has a non-finite coordinate", i);
		if (!isfinite(s->nx[i]) || !isfinite(s->ny[i]) || !isfinite(s->nz[i]))
			return dp_fail(err, DP_ERR_ARG, "sink: surface point %zu has a non-finite normal", i);
	}
	return DP_OK;
}

/* Per-point float arrays, carved from one block. Suffix _q: the inner grid's
 * sorted order; _s: the surface grid's sorted order; c_: compacted per
 * unsettled point (the queries of one pass). */
enum {
	SUNK_X, SUNK_Y, SUNK_Z,     /* inner points after the step, caller order */
	MOVE,                       /* step taken last iteration (settled: 0), caller order */
	DEPTH0,                     /* depth before this iteration's step, caller order */
	MOVE_S, STOP, STOP_S, C_DEPTH,
	SURF_X_Q, SURF_Y_Q, SURF_Z_Q, NORM_X_Q, NORM_Y_Q, NORM_Z_Q,
	NORM_X_S, NORM_Y_S, NORM_Z_S, SUNK_X_S, SUNK_Y_S, SUNK_Z_S,
	C_QX, C_QY, C_QZ, C_PX, C_PY, C_PZ, C_NX, C_NY, C_NZ,
	C_STEP, C_OUT_X, C_OUT_Y, C_OUT_Z, C_OUT_W,
	NARRAYS
};

typedef struct sink_state {
	size_t n;
	const dp_cloud *s;
	float *q[3];          /* the inner points: the anchors' position arrays */
	float *a[NARRAYS];
	float *block;
	unsigned char *settled; /* a dp_settle per point (DP_SETTLE_NONE: still sinking) */
	uint32_t *list;       /* the unsettled points of the current pass */
	size_t nlist;
	dp_grid inner, surface;
	dp_kdtree surface_tree; /* the surface points, for the medial test */
	dp_width width;         /* the width bound (width.h) */
	int width_on;
	dp_flat flat;           /* flat faces (flat.h) */
	int flat_on;
} sink_state;

static void collect_unsettled(sink_state *st)
{
	st->nlist = 0;
	for (size_t i = 0; i < st->n; i++)
		if (st->settled[i] == DP_SETTLE_NONE)
			st->list[st->nlist++] = (uint32_t)i;
}

/* Copies per-point arrays into the compacted query slots of the list. */
static void compact(const sink_state *st, const float *const src[3], int dst)
{
	for (size_t j = 0; j < st->nlist; j++)
		for (int c = 0; c < 3; c++)
			st->a[dst + c][j] = src[c][st->list[j]];
}

static void compact_surface(const sink_state *st)
{
	const float *p[3] = {st->s->x, st->s->y, st->s->z}, *nrm[3] = {st->s->nx, st->s->ny, st->s->nz};
	compact(st, p, C_PX);
	compact(st, nrm, C_NX);
}

/* Settle test of every unsettled point; *settled receives how many settled. */
static dp_status settle_by_front(dp_context *ctx, sink_state *st, float radius, float far_d2, float wall_min,
				 float cos_w, float meet_shift, size_t *settled, dp_error *err)
{
	dp_status rc = dp_grid_build(&st->inner, st->n, st->q[0], st->q[1], st->q[2], radius, err);
	if (rc != DP_OK)
		return rc;
	const float *attrs[6] = {st->s->x, st->s->y, st->s->z, st->s->nx, st->s->ny, st->s->nz};
	for (int c = 0; c < 6; c++)
		dp_grid_gather(&st->inner, attrs[c], st->a[SURF_X_Q + c]);
	const float *q[3] = {st->q[0], st->q[1], st->q[2]};
	compact(st, q, C_QX);
	compact_surface(st);
	dp_sink_front_args fa = {
		.inner = &st->inner,
		.sx = st->a[SURF_X_Q], .sy = st->a[SURF_Y_Q], .sz = st->a[SURF_Z_Q],
		.nx = st->a[NORM_X_Q], .ny = st->a[NORM_Y_Q], .nz = st->a[NORM_Z_Q],
		.nq = st->nlist,
		.qx = st->a[C_QX], .qy = st->a[C_QY], .qz = st->a[C_QZ],
		.px = st->a[C_PX], .py = st->a[C_PY], .pz = st->a[C_PZ],
		.qnx = st->a[C_NX], .qny = st->a[C_NY], .qnz = st->a[C_NZ],
		.radius = radius, .far_d2 = far_d2, .wall_min = wall_min, .min_dot = st->a[C_OUT_X],
	};
	rc = dp_op_sink_front(ctx, &fa, err);
	if (rc != DP_OK)
		return rc;
	dp_meet_args meet = {
		.inner = &st->inner,
		.sx = st->a[SURF_X_Q], .sy = st->a[SURF_Y_Q], .sz = st->a[SURF_Z_Q],
		.nx = st->a[NORM_X_Q], .ny = st->a[NORM_Y_Q], .nz = st->a[NORM_Z_Q],
		.radius = radius, .far_d2 = far_d2, .wall_min = wall_min, .cos_w = cos_w, .max_shift = meet_shift,
	};
	size_t kept = 0;
	for (size_t j = 0; j < st->nlist; j++) {
		uint32_t i = st->list[j];
		if (st->a[C_OUT_X][j] > cos_w) {
			st->list[kept++] = i;
			continue;
		}
		st->settled[i] = DP_SETTLE_FRONT;
		if (meet_shift > 0.0f) {
			/* the grid holds copies: moving q_i changes no other point's test */
			float q[3] = {st->q[0][i], st->q[1][i], st->q[2][i]};
			float p[3] = {st->s->x[i], st->s->y[i], st->s->z[i]};
			float n[3] = {st->s->nx[i], st->s->ny[i], st->s->nz[i]};
			float shift = dp_meet_shift(&meet, q, p, n);
			for (int c = 0; c < 3; c++)
				st->q[c][i] -= shift * n[c];
		}
	}
	*settled = st->nlist - kept;
	st->nlist = kept;
	return DP_OK;
}

/* How far inner point i has sunk below its surface point. */
static float depth_of(const sink_state *st, size_t i)
{
	float dx = st->q[0][i] - st->s->x[i], dy = st->q[1][i] - st->s->y[i], dz = st->q[2][i] - st->s->z[i];
	return sqrtf(dx * dx + dy * dy + dz * dz);
}

/* A thread of the medial test and the width bound gets at least this many
 * points: a test is a few microseconds, handing a range to a pool worker
 * several. */
#define SETTLE_MIN_ITEMS 256

/* Drops the listed points a threaded test marked settled (it marks, the list
 * is compacted here, in order); returns how many. */
static size_t drop_settled(sink_state *st)
{
	size_t kept = 0;
	for (size_t j = 0; j < st->nlist; j++) {
		uint32_t i = st->list[j];
		if (st->settled[i] == DP_SETTLE_NONE)
			st->list[kept++] = i;
	}
	size_t dropped = st->nlist - kept;
	st->nlist = kept;
	return dropped;
}

typedef struct medial_job {
	sink_state *st;
	float margin;   /* the margin's fixed part, in coordinates */
	float fraction; /* and its part in proportion to the point's depth, */
	float cap;      /* which is at most this, in coordinates */
} medial_job;

/* Marks listed points whose ball holds a surface point: list entries are
 * distinct points, so the threads write disjoint bytes of `settled`. */
static void medial_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	const medial_job *job = arg;
	sink_state *st = job->st;
	for (size_t j = begin; j < end; j++) {
		uint32_t i = st->list[j];
		float d = depth_of(st, i);
		/* only points deeper than their whole margin can be past the axis by more */
		float limit = d - fminf(d * job->fraction, job->cap) - job->margin;
		if (limit > 0.0f &&
		    dp_kdtree_any_within(&st->surface_tree, st->q[0][i], st->q[1][i], st->q[2][i], limit * limit))
			st->settled[i] = DP_SETTLE_MEDIAL;
	}
}

/* The medial test: an inner point nearer to some surface point than to its
 * own by more than `margin` plus `fraction` of its depth (that part at most
 * `cap`) has passed the medial axis (the centre of its inscribed ball), so it
 * settles; dpoints.h (1b) has why the margin grows with depth. Opposing
 * fronts cannot stop points whose far side was never scanned (a one-sided
 * scan of a pole or a wing): there nothing settles, the steps never shrink,
 * and measured on such scans the deep points ended ~100 r long. The scanned
 * sides of the same part still bound the ball. Distances are exact, on the host: the ball of radius
 * depth less the whole margin around the inner point must hold no surface
 * point. */
static void settle_past_medial(int threads, sink_state *st, float margin, float fraction, float cap,
			       size_t *settled)
{
	*settled = 0;
	if (!(margin > 0.0f))
		return;
	medial_job job = {st, margin, fraction, cap};
	dp_parallel_for(threads, st->nlist, SETTLE_MIN_ITEMS, medial_range, &job);
	*settled = drop_settled(st);
}

/* The width bound (width.h): an inner point as deep as its surface point's
 * part is wide has left the part, or is about to. Each point reads only its
 * own bound and level, so the threads write disjoint slots. */
static void width_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	sink_state *st = arg;
	for (size_t j = begin; j < end; j++) {
		uint32_t i = st->list[j];
		if (dp_width_too_deep(&st->width, i, depth_of(st, i)))
			st->settled[i] = DP_SETTLE_WIDTH;
	}
}

static void settle_by_width(int threads, sink_state *st, size_t *settled)
{
	*settled = 0;
	if (!st->width_on)
		return;
	dp_parallel_for(threads, st->nlist, SETTLE_MIN_ITEMS, width_range, st);
	*settled = drop_settled(st);
}

static void flat_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	sink_state *st = arg;
	for (size_t j = begin; j < end; j++) {
		uint32_t i = st->list[j];
		if (dp_flat_too_deep(&st->flat, st->q, i, DP_FLAT_PAST))
			st->settled[i] = DP_SETTLE_FLAT;
	}
}

/* Plates while sinking (flat.h): a point twice as deep as the edge band
 * beside its face shows the face's half thickness to be has passed the far
 * face, and settles at that depth. Slow-down also stops a one-sided plate's
 * middle, but only as it creeps in from the rim, row by row, while the middle
 * sinks on: with a slow-down margin of 1 r it never caught up on the demo
 * chair's back rest, whose middle sank 74 r through the plate to the
 * iteration cap. The evidence at a face's rim is no measure of a plate here:
 * along a closed cylinder's side it is the depth of the crease with the end
 * cap, and the side's points, which meet the opposite side R deep, would
 * stop a few r in. */
static void settle_by_flat(int threads, sink_state *st, size_t *settled)
{
	*settled = 0;
	if (!st->flat_on)
		return;
	dp_parallel_for(threads, st->nlist, SETTLE_MIN_ITEMS, flat_range, st);
	*settled = drop_settled(st);
}

/* Step lengths t of the unsettled points into C_STEP (compacted); points whose
 * step falls below `slow` settle and leave the list. */
static dp_status steps(dp_context *ctx, sink_state *st, int first_iteration, float first, float slow,
		       float radius, float margin, size_t *settled, dp_error *err)
{
	*settled = 0;
	if (first_iteration) {
		for (size_t j = 0; j < st->nlist; j++)
			st->a[C_STEP][j] = first;
		return DP_OK;
	}
	/* Where a settled neighbour stopped, and how deep each listed point is:
	 * only neighbours that stopped no shallower than depth - margin slow a
	 * point down (dpoints.h, sinking step 2). */
	for (size_t i = 0; i < st->n; i++)
		st->a[STOP][i] = st->settled[i] != DP_SETTLE_NONE ? depth_of(st, i) : INFINITY;
	for (size_t j = 0; j < st->nlist; j++)
		st->a[C_DEPTH][j] = depth_of(st, st->list[j]);
	dp_grid_gather(&st->surface, st->a[MOVE], st->a[MOVE_S]);
	dp_grid_gather(&st->surface, st->a[STOP], st->a[STOP_S]);
	compact_surface(st);
	dp_sink_step_args sa = {
		.surface = &st->surface, .move = st->a[MOVE_S], .stop = st->a[STOP_S], .nq = st->nlist,
		.px = st->a[C_PX], .py = st->a[C_PY], .pz = st->a[C_PZ], .depth = st->a[C_DEPTH],
		.radius = radius, .margin = margin, .mean = st->a[C_OUT_X],
	};
	dp_status rc = dp_op_sink_step(ctx, &sa, err);
	if (rc != DP_OK)
		return rc;
	size_t kept = 0;
	for (size_t j = 0; j < st->nlist; j++) {
		float t = st->a[C_OUT_X][j];
		if (t < slow) {
			st->settled[st->list[j]] = DP_SETTLE_SLOW;
			continue;
		}
		st->a[C_STEP][kept] = t;
		st->list[kept++] = st->list[j];
	}
	*settled = st->nlist - kept;
	st->nlist = kept;
	return DP_OK;
}

/* A sinking point that got less than this fraction of the slow-down step
 * deeper in one iteration has stopped (sinking step 2, stalls): the smoothing
 * holds it against the settled neighbours it has passed. 1 (the slow-down's
 * own threshold) stopped the one-view bunny's body short of its middle. */
#define DP_SINK_STALL 0.2f

static void mark_depths(sink_state *st)
{
	for (size_t j = 0; j < st->nlist; j++)
		st->a[DEPTH0][st->list[j]] = depth_of(st, st->list[j]);
}

static void settle_stalled(sink_state *st, float least, size_t *settled)
{
	for (size_t j = 0; j < st->nlist; j++) {
		uint32_t i = st->list[j];
		if (depth_of(st, i) - st->a[DEPTH0][i] < least)
			st->settled[i] = DP_SETTLE_SLOW;
	}
	*settled = drop_settled(st);
}

/* Sinks the listed points by their steps, smooths them over P_i and records
 * every point's move. */
static dp_status sink_and_smooth(dp_context *ctx, sink_state *st, float radius, float inv_r2, float phi_scale,
				 dp_error *err)
{
	const dp_cloud *s = st->s;
	float *b[3] = {st->a[SUNK_X], st->a[SUNK_Y], st->a[SUNK_Z]};
	for (int c = 0; c < 3; c++)
		memcpy(b[c], st->q[c], st->n * sizeof(float));
	for (size_t j = 0; j < st->nlist; j++) {
		uint32_t i = st->list[j];
		float t = st->a[C_STEP][j];
		b[0][i] -= t * s->nx[i];
		b[1][i] -= t * s->ny[i];
		b[2][i] -= t * s->nz[i];
	}
	for (int c = 0; c < 3; c++)
		dp_grid_gather(&st->surface, b[c], st->a[SUNK_X_S + c]);
	const float *bc[3] = {b[0], b[1], b[2]};
	compact(st, bc, C_QX);
	compact_surface(st);
	dp_sink_smooth_args ma = {
		.surface = &st->surface,
		.nx = st->a[NORM_X_S], .ny = st->a[NORM_Y_S], .nz = st->a[NORM_Z_S],
		.ix = st->a[SUNK_X_S], .iy = st->a[SUNK_Y_S], .iz = st->a[SUNK_Z_S],
		.nq = st->nlist,
		.px = st->a[C_PX], .py = st->a[C_PY], .pz = st->a[C_PZ],
		.qnx = st->a[C_NX], .qny = st->a[C_NY], .qnz = st->a[C_NZ],
		.qx = st->a[C_QX], .qy = st->a[C_QY], .qz = st->a[C_QZ],
		.radius = radius, .inv_r2 = inv_r2, .phi_scale = phi_scale,
		.out_x = st->a[C_OUT_X], .out_y = st->a[C_OUT_Y], .out_z = st->a[C_OUT_Z], .out_w = st->a[C_OUT_W],
	};
	dp_status rc = dp_op_sink_smooth(ctx, &ma, err);
	if (rc != DP_OK)
		return rc;
	/* The move that sets the neighbours' next step is the sinking step alone
	 * (dpoints.h says why); settled points count 0. */
	memset(st->a[MOVE], 0, st->n * sizeof(float));
	for (size_t j = 0; j < st->nlist; j++) {
		uint32_t i = st->list[j];
		float w = st->a[C_OUT_W][j];
		/* w >= 1 whenever p_i is in its own neighbourhood (its own weight
		 * is 1 for a unit normal); a zero normal can underflow it, and then
		 * the point keeps its sunk position. */
		for (int c = 0; c < 3; c++)
			st->q[c][i] = b[c][i] + (w > 0.0f ? st->a[C_OUT_X + c][j] / w : 0.0f);
		st->a[MOVE][i] = st->a[C_STEP][j];
	}
	return DP_OK;
}

static dp_status run(dp_context *ctx, sink_state *st, double r, const dp_sink_params *p, dp_sink_stats *stats,
		     dp_error *err)
{
	float static_radius = (float)(p->sigma_p * r);
	float settle_radius = (float)(p->settle_radius_r * r);
	float far = (float)(p->front_factor * p->settle_radius_r * r);
	float first = (float)(p->first_step_r * r), slow = (float)(p->slow_fraction * p->first_step_r * r);
	double cos_w = cos(p->omega_deg * M_PI / 180.0);
	float inv_r2 = (float)(1.0 / (r * r)), phi_scale = (float)(1.0 / (1.0 - cos_w));
	const dp_cloud *s = st->s;

	dp_status rc = dp_grid_build(&st->surface, st->n, s->x, s->y, s->z, static_radius, err);
	if (rc != DP_OK)
		return rc;
	const float *nrm[3] = {s->nx, s->ny, s->nz};
	for (int c = 0; c < 3; c++)
		dp_grid_gather(&st->surface, nrm[c], st->a[NORM_X_S + c]);

	float medial_margin = (float)(p->medial_margin_r * r), meet_shift = (float)(p->meet_shift_r * r);
	float slow_margin = (float)(p->slow_margin_r * r);
	/* squared distances must not overflow (the medial test compares them, the
	 * width bound's grids hold them) */
	if ((medial_margin > 0.0f || p->width_factor > 0.0) &&
	    (rc = dp_check_span("sink", st->n, s->x, s->y, s->z, err)) != DP_OK)
		return rc;
	if (medial_margin > 0.0f && (rc = dp_kdtree_build(&st->surface_tree, st->n, s->x, s->y, s->z, err)) != DP_OK)
		return rc;

	if (p->width_factor > 0.0) {
		if ((rc = dp_width_init(&st->width, st->n, s->x, s->y, s->z, r, p->width_factor, err)) != DP_OK)
			return rc;
		st->width_on = 1;
	}

	if (p->flat_angle_deg > 0.0) {
		const float *pos[3] = {s->x, s->y, s->z}, *nrm3[3] = {s->nx, s->ny, s->nz};
		if ((rc = dp_flat_init(&st->flat, ctx->threads, st->n, pos, nrm3, r, p->flat_angle_deg, err)) != DP_OK)
			return rc;
		dp_flat_update(&st->flat, ctx->threads, st->q, NULL);
		st->flat_on = 1;
	}

	size_t settled_total = 0;
	for (int it = 1; it <= p->max_iters; it++) {
		collect_unsettled(st);
		if (st->nlist == 0)
			break;
		size_t by_front, by_medial = 0, by_width = 0, by_flat = 0, by_slow, by_stall = 0;
		rc = settle_by_front(ctx, st, settle_radius, far * far, (float)(p->wall_min_r * r), (float)cos_w,
				     meet_shift, &by_front, err);
		if (rc == DP_OK) {
			settle_past_medial(ctx->threads, st, medial_margin, (float)p->medial_fraction,
					   (float)(p->medial_fraction_cap_r * r), &by_medial);
			settle_by_width(ctx->threads, st, &by_width);
			settle_by_flat(ctx->threads, st, &by_flat);
			rc = steps(ctx, st, it == 1, first, slow, static_radius, slow_margin, &by_slow, err);
		}
		if (rc == DP_OK) {
			mark_depths(st);
			rc = sink_and_smooth(ctx, st, static_radius, inv_r2, phi_scale, err);
		}
		if (rc != DP_OK)
			return rc;
		settle_stalled(st, DP_SINK_STALL * slow, &by_stall);
		by_slow += by_stall;
		stats->iterations = it;
		stats->settled_front += by_front;
		stats->settled_medial += by_medial;
		stats->settled_width += by_width;
		stats->settled_slow += by_slow;
		stats->settled_flat += by_flat;
		settled_total += by_front + by_medial + by_width + by_flat + by_slow;
		if ((rc = dp_progress(ctx, "sink", it, (double)settled_total, err)) != DP_OK)
			return rc;
	}
	stats->unsettled = st->n - settled_total;
	stats->converged = settled_total == st->n;
	if (st->flat_on) {
		/* Every point that stopped without evidence (slow-down, the width
		 * bound, a plate's band) takes its face's depth from all the
		 * evidence now, and the counts are taken again at the end. */
		dp_flat_update(&st->flat, ctx->threads, st->q, st->settled);
		for (size_t i = 0; i < st->n; i++) {
			unsigned char why = st->settled[i];
			int blind = why == DP_SETTLE_SLOW || why == DP_SETTLE_WIDTH || why == DP_SETTLE_FLAT;
			if (blind && dp_flat_too_deep(&st->flat, st->q, i, 1.0f))
				st->settled[i] = DP_SETTLE_FLAT;
		}
		/* the crease samples beside the faces, which no face depth reached */
		dp_flat_cross(&st->flat, ctx->threads, st->q, st->settled);
		size_t n_slow = 0, n_width = 0, n_flat = 0;
		for (size_t i = 0; i < st->n; i++) {
			n_slow += st->settled[i] == DP_SETTLE_SLOW;
			n_width += st->settled[i] == DP_SETTLE_WIDTH;
			n_flat += st->settled[i] == DP_SETTLE_FLAT;
		}
		stats->settled_slow = n_slow;
		stats->settled_width = n_width;
		stats->settled_flat = n_flat;
	}
	return rc;
}

dp_status dp_sink(dp_context *ctx, const dp_cloud *surface, double r, const dp_sink_params *params,
		  dp_cloud *anchors, unsigned char *settled_by, dp_sink_stats *stats, dp_error *err)
{
	if (!anchors)
		return dp_fail(err, DP_ERR_ARG, "sink: no output cloud");
	if (anchors == surface)
		return dp_fail(err, DP_ERR_ARG, "sink: the output cloud must not be the surface");
	memset(anchors, 0, sizeof *anchors);
	if (!ctx || !surface)
		return dp_fail(err, DP_ERR_ARG, "sink: no context or no surface points");
	dp_sink_params defaults;
	if (!params) {
		dp_sink_params_default(&defaults);
		params = &defaults;
	}
	dp_status rc = check_params(params, r, err);
	if (rc == DP_OK)
		rc = check_surface(surface, err);
	if (rc != DP_OK)
		return rc;

	double t0 = dp_seconds(), pairs0 = ctx->pair_evaluations;
	dp_sink_stats local = {0};
	sink_state st = {.n = surface->n, .s = surface};
	rc = dp_cloud_alloc(anchors, st.n, 1, err);
	if (rc != DP_OK)
		return rc;
	const float *src[6] = {surface->x, surface->y, surface->z, surface->nx, surface->ny, surface->nz};
	float *dst[6] = {anchors->x, anchors->y, anchors->z, anchors->nx, anchors->ny, anchors->nz};
	for (int c = 0; c < 6; c++)
		memcpy(dst[c], src[c], st.n * sizeof(float));
	st.q[0] = anchors->x;
	st.q[1] = anchors->y;
	st.q[2] = anchors->z;
	st.block = dp_alloc_array(st.n, NARRAYS * sizeof(float));
	st.settled = settled_by ? settled_by : calloc(st.n, 1);
	if (settled_by)
		memset(settled_by, DP_SETTLE_NONE, st.n);
	st.list = dp_alloc_array(st.n, sizeof *st.list);
	if (!st.block || !st.settled || !st.list) {
		rc = dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for %zu points", st.n);
	} else {
		for (int k = 0; k < NARRAYS; k++)
			st.a[k] = st.block + (size_t)k * st.n;
		memset(st.a[MOVE], 0, st.n * sizeof(float));
		rc = run(ctx, &st, r, params, &local, err);
	}
	free(st.block);
	if (st.settled != settled_by)
		free(st.settled);
	free(st.list);
	dp_width_free(&st.width);
	dp_flat_free(&st.flat);
	dp_kdtree_free(&st.surface_tree);
	dp_grid_free(&st.inner);
	dp_grid_free(&st.surface);
	if (rc != DP_OK) {
		dp_cloud_free(anchors);
		return rc;
	}
	local.seconds = dp_seconds() - t0;
	local.pair_evaluations = ctx->pair_evaluations - pairs0;
	if (stats)
		*stats = local;
	return DP_OK;
}
