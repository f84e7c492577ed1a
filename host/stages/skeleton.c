/* Forming the meso-skeleton (paper 4.2, DESIGN 4.2): Q starts at the anchors H
 * and is moved by the anisotropic L1-median of the anchors plus a repulsion
 * projected onto the long axes of each point's ellipsoid. The exact update is
 * documented at dp_skeleton in dpoints.h; every neighbour sum is an operator
 * (host/ops/operators.h), the O(n) combination steps (eigen-
 * decomposition, metric, projection and update) run here for both backends. */
#include "dpoints.h"

#include "backend/ops.h"
#include "core/common.h"
#include "core/eig3.h"
#include "core/parallel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Cell side of the grids of the weighted sums, in units of cutoff r (the reach
 * along a semi-axis of 1, about the shortest). Each query scans only the cells
 * its own ellipsoid's bounding box touches (reaches from about 1 to 1/eps = 10
 * times cutoff r); smaller cells fit the box more tightly but cost more rows
 * per query. Measured with bench/bench_skeleton.c (20 iterations at 67K
 * anchors, slab and torus): 1 to 2 are equally fast, 2.5 and 3 about 25%
 * slower. */
#define SKELETON_CELL_CUTOFFS 1.5
/* A thread of the PCA frames gets at least this many points (a Jacobi
 * eigen-decomposition is about a third of a microsecond). */
#define FRAMES_MIN_ITEMS 2048

void dp_skeleton_params_default(dp_skeleton_params *p)
{
	p->sigma_q = 2.0;
	p->eps = 0.1;
	p->mu = 0.4;
	p->cutoff = 3.0;
	p->min_axis_weight = 0.0;
	p->across_only = 1;
	p->max_iters = 100;
	p->window = 3;
	p->min_drop = 0.05;
	p->min_move_r = 1e-3;
}

static dp_status check_params(const dp_skeleton_params *p, dp_error *err)
{
	if (!(p->sigma_q > 0.0) || !isfinite(p->sigma_q))
		return dp_fail(err, DP_ERR_ARG, "skeleton: sigma_q %g must be positive", p->sigma_q);
	if (!(p->eps > 0.0) || !isfinite(p->eps))
		return dp_fail(err, DP_ERR_ARG, "skeleton: eps %g must be positive (it bounds the semi-axes)",
			       p->eps);
	if (!(p->mu >= 0.0) || !isfinite(p->mu))
		return dp_fail(err, DP_ERR_ARG, "skeleton: mu %g must be >= 0", p->mu);
	if (!(p->cutoff > 0.0) || !isfinite(p->cutoff))
		return dp_fail(err, DP_ERR_ARG, "skeleton: cutoff %g must be positive", p->cutoff);
	if (!(p->min_axis_weight >= 0.0 && p->min_axis_weight <= 1.0))
		return dp_fail(err, DP_ERR_ARG, "skeleton: min_axis_weight %g must be in [0, 1]",
			       p->min_axis_weight);
	if (p->max_iters < 0)
		return dp_fail(err, DP_ERR_ARG, "skeleton: max_iters %d must be >= 0", p->max_iters);
	if (p->window < 1)
		return dp_fail(err, DP_ERR_ARG, "skeleton: window %d must be >= 1", p->window);
	if (!(p->min_drop >= 0.0 && p->min_drop < 1.0))
		return dp_fail(err, DP_ERR_ARG, "skeleton: min_drop %g must be in [0, 1)", p->min_drop);
	if (!(p->min_move_r >= 0.0) || !isfinite(p->min_move_r))
		return dp_fail(err, DP_ERR_ARG, "skeleton: min_move_r %g must be >= 0", p->min_move_r);
	return DP_OK;
}

static dp_status check_anchors(const dp_cloud *h, double r, dp_error *err)
{
	if (!h || h->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "skeleton: no anchor points");
	if (!h->nx || !h->ny || !h->nz)
		return dp_fail(err, DP_ERR_ARG, "skeleton: the anchors carry no normals");
	if (!(r > 0.0) || !isfinite(r))
		return dp_fail(err, DP_ERR_ARG, "skeleton: spacing r = %g must be positive", r);
	for (size_t i = 0; i < h->n; i++)
		if (!isfinite(h->x[i]) || !isfinite(h->y[i]) || !isfinite(h->z[i]) || !isfinite(h->nx[i]) ||
		    !isfinite(h->ny[i]) || !isfinite(h->nz[i]))
			return dp_fail(err, DP_ERR_ARG, "skeleton: anchor %zu has a non-finite position or normal", i);
	return DP_OK;
}

/* Per-point arrays of one run, allocated once. */
typedef struct work {
	/* per query, in the near grid's order: 1, 6, 9, 3, 9, 3, 3, 3 per point */
	float *count, *cov, *frames, *semi, *metric, *reach, *median, *repulse;
	float *ux, *uy, *uz;    /* unit normals (zero stays zero) */
	float *gnx, *gny, *gnz; /* unit normals in the near grid's order */
	float *nx, *ny, *nz;    /* next positions */
	double *moves;          /* mean move per iteration, r */
	dp_grid near, inner, anchors;
} work;

static void work_free(work *w)
{
	float *arrays[] = {w->count, w->cov, w->frames, w->semi, w->metric, w->reach, w->median, w->repulse,
			   w->ux,    w->uy,  w->uz,     w->gnx,  w->gny,    w->gnz,   w->nx,     w->ny,      w->nz};
	for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
		free(arrays[k]);
	free(w->moves);
	dp_grid_free(&w->near);
	dp_grid_free(&w->inner);
	dp_grid_free(&w->anchors);
}

static dp_status work_alloc(work *w, size_t n, int max_iters, dp_error *err)
{
	memset(w, 0, sizeof *w);
	w->count = dp_alloc_array(n, sizeof(float));
	w->cov = dp_alloc_array(n, 6 * sizeof(float));
	w->frames = dp_alloc_array(n, 9 * sizeof(float));
	w->semi = dp_alloc_array(n, 3 * sizeof(float));
	w->metric = dp_alloc_array(n, 9 * sizeof(float));
	w->reach = dp_alloc_array(n, 3 * sizeof(float));
	w->median = dp_alloc_array(n, 3 * sizeof(float));
	w->repulse = dp_alloc_array(n, 3 * sizeof(float));
	w->ux = dp_alloc_array(n, sizeof(float));
	w->uy = dp_alloc_array(n, sizeof(float));
	w->uz = dp_alloc_array(n, sizeof(float));
	w->gnx = dp_alloc_array(n, sizeof(float));
	w->gny = dp_alloc_array(n, sizeof(float));
	w->gnz = dp_alloc_array(n, sizeof(float));
	w->nx = dp_alloc_array(n, sizeof(float));
	w->ny = dp_alloc_array(n, sizeof(float));
	w->nz = dp_alloc_array(n, sizeof(float));
	w->moves = dp_alloc_array((size_t)max_iters + 1, sizeof(double));
	if (!w->count || !w->cov || !w->frames || !w->semi || !w->metric || !w->reach || !w->median || !w->repulse ||
	    !w->ux || !w->uy || !w->uz || !w->gnx || !w->gny || !w->gnz || !w->nx || !w->ny || !w->nz || !w->moves) {
		work_free(w);
		return dp_fail(err, DP_ERR_NOMEM, "skeleton: out of memory for %zu points and a cap of %d iterations",
			       n, max_iters);
	}
	return DP_OK;
}

/* The semi-axes measure normal projections, so they need unit normals
 * whatever the caller passed. */
static void unit_normals(work *w, const dp_cloud *h)
{
	for (size_t i = 0; i < h->n; i++) {
		double x = h->nx[i], y = h->ny[i], z = h->nz[i], len = sqrt(x * x + y * y + z * z);
		double inv = len > 0.0 ? 1.0 / len : 0.0;
		w->ux[i] = (float)(x * inv);
		w->uy[i] = (float)(y * inv);
		w->uz[i] = (float)(z * inv);
	}
}

/* PCA axes of neighbourhoods [begin, end) (eigenvectors of their
 * covariance); each writes only its own frame. */
static void frames_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	work *w = arg;
	for (size_t i = begin; i < end; i++) {
		double a[6], ev[3], v[3][3];
		for (int k = 0; k < 6; k++)
			a[k] = w->cov[6 * i + k];
		dp_eig3_sym(a, ev, v);
		for (int m = 0; m < 3; m++)
			for (int c = 0; c < 3; c++)
				w->frames[9 * i + 3 * m + c] = (float)v[m][c];
	}
}

/* The metric rows v^m / (l^m r) of the ellipsoid distance. */
static void metric_from_semiaxes(work *w, size_t n, double r)
{
	for (size_t i = 0; i < n; i++)
		for (int m = 0; m < 3; m++) {
			float l = w->semi[3 * i + m];
			for (int c = 0; c < 3; c++)
				w->metric[9 * i + 3 * m + c] = (float)(w->frames[9 * i + 3 * m + c] / (l * r));
		}
}

/* Cell side and margin of the weighted sums' grids: the margin must cover the
 * longest reach; the cell grows only if that would exceed DP_GRID_MAX_MARGIN
 * (a tiny eps). */
static dp_status scan_grid_shape(float longest, double cutoff, double r, float *cell, int *margin, dp_error *err)
{
	if (!isfinite(longest))
		return dp_fail(err, DP_ERR_ARG, "skeleton: an ellipsoid has a non-finite reach (degenerate axes)");
	float c = (float)(SKELETON_CELL_CUTOFFS * cutoff * r);
	double cells;
	while ((cells = ceil((double)longest / (double)c)) > DP_GRID_MAX_MARGIN)
		c *= 2.0f;
	*cell = c;
	*margin = cells < 1.0 ? 1 : (int)cells;
	return DP_OK;
}

/* q_i ← q_i + C_i (m_i - q_i) + μ P_i ρ_i into w->nx/ny/nz, C_i = I when
 * the median step moves along the structure too (the paper); returns the
 * mean move in r. The per-query arrays are in the near grid's order (see
 * iterate). Across only, C_i = Σ_m (l_min / l^m)² v^m v^mᵀ: the step's part
 * along an axis as long as the shortest is kept, along a long axis of a curve
 * or a sheet under 1% of it is (l is at most 1/ε, at least 1/(1+ε)). Along a
 * sheet the median of an ellipsoid ten times wider than deep only drew points
 * towards denser spots and away from the rim: measured on the demo chair's
 * seat, the skeleton's largest hole grew from 1.4 r (the anchors) to 6.6 r
 * within 20 iterations, the surface points above a hole took inner ends up
 * to 10 r aside, and once off the scanned top such a point swung round its
 * inner end to hang 3-5 r under the seat (dpoints.h has the measured
 * effect). */
static double update(work *w, const dp_cloud *q, double r, const dp_skeleton_params *p)
{
	double total = 0.0;
	for (size_t s = 0; s < q->n; s++) {
		size_t i = w->near.perm[s];
		const float *v = w->frames + 9 * s, *l = w->semi + 3 * s, *rep = w->repulse + 3 * s;
		double l2 = (double)l[0] * l[0] + (double)l[1] * l[1] + (double)l[2] * l[2];
		double proj[3] = {0.0, 0.0, 0.0};
		for (int m = 0; m < 3; m++) {
			double wm = (double)l[m] * l[m] / l2;
			if (wm < p->min_axis_weight)
				continue;
			double along = wm * (v[3 * m] * rep[0] + v[3 * m + 1] * rep[1] + v[3 * m + 2] * rep[2]);
			for (int c = 0; c < 3; c++)
				proj[c] += along * v[3 * m + c];
		}
		double cur[3] = {q->x[i], q->y[i], q->z[i]}, step[3], nxt[3];
		for (int c = 0; c < 3; c++)
			step[c] = w->median[3 * s + c] - cur[c];
		if (p->across_only) {
			double shortest = fmin(fmin(l[0], l[1]), l[2]), across[3] = {0.0, 0.0, 0.0};
			for (int m = 0; m < 3; m++) {
				double keep = shortest / l[m];
				double along = keep * keep * (v[3 * m] * step[0] + v[3 * m + 1] * step[1] + v[3 * m + 2] * step[2]);
				for (int c = 0; c < 3; c++)
					across[c] += along * v[3 * m + c];
			}
			for (int c = 0; c < 3; c++)
				step[c] = across[c];
		}
		for (int c = 0; c < 3; c++)
			nxt[c] = cur[c] + step[c] + p->mu * proj[c];
		double dx = nxt[0] - cur[0], dy = nxt[1] - cur[1], dz = nxt[2] - cur[2];
		total += sqrt(dx * dx + dy * dy + dz * dz);
		w->nx[i] = (float)nxt[0];
		w->ny[i] = (float)nxt[1];
		w->nz[i] = (float)nxt[2];
	}
	return total / (double)q->n / r;
}

/* One iteration: the four operators over the current Q, then the update.
 * Queries go to the operators in the near grid's order (its sorted copy of Q),
 * so that neighbouring work-items scan the same cells: 20-30% faster than the
 * caller's order on PoCL (bench/bench_skeleton.c, 67K anchors). Every
 * per-query array is in that order; update() scatters the result back. */
static dp_status iterate(dp_context *ctx, const dp_cloud *h, dp_cloud *q, double r, const dp_skeleton_params *p,
			 work *w, float *anchor_cell, double *mean_move, dp_error *err)
{
	size_t n = q->n;
	float near_radius = (float)(p->sigma_q * r);
	dp_status st = dp_grid_build(&w->near, n, q->x, q->y, q->z, near_radius, err);
	if (st != DP_OK)
		return st;
	dp_skeleton_cov_args ca = {
		.data = &w->near, .nq = n, .qx = w->near.x, .qy = w->near.y, .qz = w->near.z, .radius = near_radius,
		.count = w->count, .cov = w->cov,
	};
	if ((st = dp_op_skeleton_cov(ctx, &ca, err)) != DP_OK)
		return st;
	dp_parallel_for(ctx->threads, n, FRAMES_MIN_ITEMS, frames_range, w);
	dp_grid_gather(&w->near, w->ux, w->gnx);
	dp_grid_gather(&w->near, w->uy, w->gny);
	dp_grid_gather(&w->near, w->uz, w->gnz);
	dp_skeleton_semiaxes_args sa = {
		.data = &w->near, .gnx = w->gnx, .gny = w->gny, .gnz = w->gnz, .nq = n, .qx = w->near.x,
		.qy = w->near.y, .qz = w->near.z, .frames = w->frames, .radius = near_radius, .eps = (float)p->eps,
		.semi = w->semi,
	};
	if ((st = dp_op_skeleton_semiaxes(ctx, &sa, err)) != DP_OK)
		return st;

	metric_from_semiaxes(w, n, r);
	float cutoff = (float)p->cutoff, min_d2 = (float)(DP_PAIR_EPS * r) * (float)(DP_PAIR_EPS * r);
	float longest = dp_skeleton_reach(n, w->metric, cutoff, w->reach), cell = 0.0f;
	int margin = 0;
	if ((st = scan_grid_shape(longest, p->cutoff, r, &cell, &margin, err)) != DP_OK)
		return st;
	if ((st = dp_grid_build_margin(&w->inner, n, q->x, q->y, q->z, cell, margin, err)) != DP_OK)
		return st;
	/* The anchors never move: re-bucket them only when the grid must change. */
	if (cell != *anchor_cell || margin > w->anchors.margin) {
		if ((st = dp_grid_build_margin(&w->anchors, h->n, h->x, h->y, h->z, cell, margin, err)) != DP_OK)
			return st;
		*anchor_cell = cell;
	}
	dp_skeleton_median_args ma = {
		.data = &w->anchors, .nq = n, .qx = w->near.x, .qy = w->near.y, .qz = w->near.z, .metric = w->metric,
		.reach = w->reach, .cutoff = cutoff, .min_d2 = min_d2, .median = w->median,
	};
	if ((st = dp_op_skeleton_median(ctx, &ma, err)) != DP_OK)
		return st;
	dp_skeleton_repulse_args ra = {
		.data = &w->inner, .nq = n, .qx = w->near.x, .qy = w->near.y, .qz = w->near.z, .metric = w->metric,
		.reach = w->reach, .cutoff = cutoff, .min_d2 = min_d2, .repulse = w->repulse,
	};
	if ((st = dp_op_skeleton_repulse(ctx, &ra, err)) != DP_OK)
		return st;

	*mean_move = update(w, q, r, p);
	size_t bytes = n * sizeof(float);
	memcpy(q->x, w->nx, bytes);
	memcpy(q->y, w->ny, bytes);
	memcpy(q->z, w->nz, bytes);
	return DP_OK;
}

/* Names the stage and iteration in front of an operator's or the grid's message. */
static dp_status stage_error(dp_error *err, dp_status st, int t)
{
	if (err) {
		char msg[DP_ERROR_MESSAGE_MAX];
		memcpy(msg, err->message, sizeof msg);
		msg[sizeof msg - 1] = '\0';
		dp_fail(err, st, "skeleton, iteration %d: %s", t + 1, msg);
	}
	return st;
}

/* The mean move has stopped falling (DESIGN 4.2: the largest move never gets
 * small, repulsion keeps points sliding along the skeleton). */
static int converged(const double *moves, int t, const dp_skeleton_params *p)
{
	if (moves[t] < p->min_move_r)
		return 1;
	return t >= p->window && moves[t] > (1.0 - p->min_drop) * moves[t - p->window];
}

dp_status dp_skeleton(dp_context *ctx, const dp_cloud *anchors, double r, const dp_skeleton_params *params,
		      dp_cloud *skeleton, dp_skeleton_stats *stats, dp_error *err)
{
	if (!ctx || !skeleton)
		return dp_fail(err, DP_ERR_ARG, "skeleton: no context or no output cloud");
	if (skeleton == anchors)
		return dp_fail(err, DP_ERR_ARG, "skeleton: the output cloud must not be the anchors");
	double t0 = dp_seconds(), pairs0 = ctx->pair_evaluations;
	dp_skeleton_params defaults;
	if (!params) {
		dp_skeleton_params_default(&defaults);
		params = &defaults;
	}
	if (stats)
		memset(stats, 0, sizeof *stats);
	memset(skeleton, 0, sizeof *skeleton);
	dp_status st = check_params(params, err);
	if (st == DP_OK)
		st = check_anchors(anchors, r, err);
	if (st != DP_OK)
		return st;
	if ((st = dp_cloud_copy(skeleton, anchors, err)) != DP_OK)
		return st;
	work w;
	if ((st = work_alloc(&w, anchors->n, params->max_iters, err)) != DP_OK) {
		dp_cloud_free(skeleton);
		return st;
	}

	unit_normals(&w, anchors);
	float anchor_cell = 0.0f;
	int t = 0, done = 0;
	for (; t < params->max_iters && !done; t++) {
		st = iterate(ctx, anchors, skeleton, r, params, &w, &anchor_cell, &w.moves[t], err);
		if (st != DP_OK) {
			stage_error(err, st, t);
			break;
		}
		done = converged(w.moves, t, params);
		if ((st = dp_progress(ctx, "skeleton", t + 1, w.moves[t], err)) != DP_OK)
			break;
	}
	if (st == DP_OK && stats) {
		stats->iterations = t;
		stats->converged = done;
		stats->last_mean_move = t > 0 ? w.moves[t - 1] : 0.0;
		stats->seconds = dp_seconds() - t0;
		stats->pair_evaluations = ctx->pair_evaluations - pairs0;
	}
	work_free(&w);
	if (st != DP_OK)
		dp_cloud_free(skeleton);
	return st;
}
