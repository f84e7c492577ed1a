/* WLOP (Huang et al. 2009; DESIGN 4.0): m random input points move, Jacobi
 * style, to the density-weighted mean (or L1 median) of the input near them
 * plus a repulsion from each other, until the mean move is below tol * h.
 *
 * The mean, not the largest move as DESIGN 4.0 has it: on real scans a few
 * samples in sparse regions never settle. With one or two input points and
 * one other sample within h, the normalised repulsion moves a sample by
 * mu times its neighbour's distance whatever θ is, and the attraction pulls it
 * back: on the statue of the paper's Fig. 12 the largest move stays at
 * 0.4-0.6 h through 200 iterations while the mean falls steadily.
 *
 * Nor does the mean reach a small tol on real scans within the paper's 30-40
 * iterations: it decays like a slow power law as the samples keep evening
 * out (statue, 4000 samples: 0.0089 h at 35 iterations, 0.0043 h at 100,
 * 0.0021 h at 250) while the spacing's coefficient of variation has long
 * settled (0.278, 0.237, 0.235). So WLOP also stops when the mean move is
 * below stall_tol and has fallen by less than min_drop over the last window
 * of iterations (statue: about 60 iterations, variation 0.245). */
#include "backend/ops.h"
#include "core/common.h"
#include "core/distinct.h"
#include "knn/knn.h"
#include "stages/wlop.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void dp_wlop_params_default(dp_wlop_params *p)
{
	memset(p, 0, sizeof *p);
	p->samples = 0;
	p->ratio = 0.1;
	p->h = 0.0;
	p->h_factor = 5.0;
	p->mu = 0.45;
	/* The scans of the data folder stop within 17-93 iterations at their
	 * default counts, but a scan without noise has no floor for the stall
	 * test to find: its mean move falls by a steady few percent an
	 * iteration down to tol. The built-in scanner's one-view cylinder took
	 * 121 iterations, a one-view sphere's coarser levels (pipeline.c) 108 at
	 * 1000 samples and 179 at 2000, and the two-view bunny reached 100 at
	 * WLOP seeds 5 and 6 (101 at 6 uncapped): each warned of a cap at 100. */
	p->max_iters = 200;
	p->tol = 0.002;
	p->stall_tol = 0.01;
	p->window = 10;
	p->min_drop = 0.1;
	p->theta_k = 4.0;
	p->weight = DP_WLOP_GAUSSIAN;
	p->sqrt_density = 0;
	p->seed = 1;
}

static dp_status check_params(const dp_wlop_params *p, dp_error *err)
{
	if (p->samples == 0 && !(p->ratio > 0.0 && p->ratio <= 1.0))
		return dp_fail(err, DP_ERR_ARG, "wlop: sample ratio %g is not in (0, 1]", p->ratio);
	if (!isfinite(p->h) || (p->h <= 0.0 && !(p->h_factor > 0.0 && isfinite(p->h_factor))))
		return dp_fail(err, DP_ERR_ARG, "wlop: support radius h = %g (factor %g) is not usable", p->h,
			       p->h_factor);
	/* h^2 is taken in float by every kernel */
	if (p->h * p->h > FLT_MAX)
		return dp_fail(err, DP_ERR_ARG, "wlop: support radius h = %g is too large: h^2 overflows single precision",
			       p->h);
	/* μ < 1/2 is the convergence condition of LOP (Lipman et al. 2007). */
	if (!(p->mu >= 0.0 && p->mu < 0.5))
		return dp_fail(err, DP_ERR_ARG, "wlop: repulsion weight mu = %g is not in [0, 0.5)", p->mu);
	if (p->max_iters < 0)
		return dp_fail(err, DP_ERR_ARG, "wlop: max_iters = %d is negative", p->max_iters);
	if (!(p->tol >= 0.0 && isfinite(p->tol)))
		return dp_fail(err, DP_ERR_ARG, "wlop: tolerance %g is not a finite number >= 0", p->tol);
	if (!(p->stall_tol >= 0.0 && isfinite(p->stall_tol)) || p->window < 1 || !(p->min_drop >= 0.0 && p->min_drop < 1.0))
		return dp_fail(err, DP_ERR_ARG, "wlop: stall_tol %g, window %d or min_drop %g out of range", p->stall_tol,
			       p->window, p->min_drop);
	if (!(p->theta_k > 0.0 && isfinite(p->theta_k)))
		return dp_fail(err, DP_ERR_ARG, "wlop: theta_k = %g is not positive", p->theta_k);
	if (p->weight != DP_WLOP_L1 && p->weight != DP_WLOP_GAUSSIAN)
		return dp_fail(err, DP_ERR_ARG, "wlop: unknown weight %d", (int)p->weight);
	return DP_OK;
}

static dp_status check_input(const dp_cloud *in, dp_error *err)
{
	if (in->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "wlop: the input has no points");
	if (!in->x || !in->y || !in->z)
		return dp_fail(err, DP_ERR_ARG, "wlop: the input has no position arrays");
	for (size_t j = 0; j < in->n; j++)
		if (!isfinite(in->x[j]) || !isfinite(in->y[j]) || !isfinite(in->z[j]))
			return dp_fail(err, DP_ERR_ARG, "wlop: input point %zu has a non-finite coordinate", j);
	return dp_check_span("wlop", in->n, in->x, in->y, in->z, err);
}

/* m distinct input positions at random: a partial Fisher–Yates shuffle of the
 * indices that passes over points repeating an earlier pick's position. Two
 * samples at one position would skip each other's repulsion (d² < min_d2)
 * and move together for ever, and duplicate points are common in merged
 * scans. */
static dp_status choose_samples(const dp_cloud *in, size_t m, uint64_t seed, dp_cloud *s, dp_error *err)
{
	size_t n = in->n, ndistinct = 0, next = 0;
	size_t *order = dp_alloc_array(n, sizeof *order);
	uint32_t *of = dp_alloc_array(n, sizeof *of);
	unsigned char *taken = calloc(n, 1);
	dp_status st = DP_OK;
	if (!order || !of || !taken) {
		st = dp_fail(err, DP_ERR_NOMEM, "wlop: out of memory choosing %zu of %zu points", m, n);
		goto done;
	}
	st = dp_distinct(n, in->x, in->y, in->z, of, &ndistinct, err);
	if (st != DP_OK)
		goto done;
	if (ndistinct < m) {
		st = dp_fail(err, DP_ERR_ARG, "wlop: the input has %zu distinct positions, fewer than %zu samples",
			     ndistinct, m);
		goto done;
	}
	for (size_t j = 0; j < n; j++)
		order[j] = j;
	dp_rng rng;
	dp_rng_seed(&rng, seed);
	for (size_t t = 0; t < m;) {
		size_t r = next + (size_t)(dp_rng_uniform(&rng) * (double)(n - next));
		size_t j = order[r];
		order[r] = order[next];
		order[next++] = j;
		if (taken[of[j]])
			continue;
		taken[of[j]] = 1;
		s->x[t] = in->x[j];
		s->y[t] = in->y[j];
		s->z[t] = in->z[j];
		t++;
	}
done:
	free(order);
	free(of);
	free(taken);
	return st;
}

/* Buffers of one run, allocated once; per-sample arrays are in the sample
 * grid's sorted order, inv_v in the input grid's. */
typedef struct wlop_work {
	dp_grid input, sample;
	float *inv_v;
	float *w, *ax, *ay, *az, *aw, *rx, *ry, *rz, *rw;
} wlop_work;

static void work_free(wlop_work *wk)
{
	dp_grid_free(&wk->input);
	dp_grid_free(&wk->sample);
	free(wk->inv_v);
	float **bufs[] = {&wk->w, &wk->ax, &wk->ay, &wk->az, &wk->aw, &wk->rx, &wk->ry, &wk->rz, &wk->rw};
	for (size_t b = 0; b < sizeof bufs / sizeof bufs[0]; b++)
		free(*bufs[b]);
}

static dp_status work_alloc(wlop_work *wk, size_t n, size_t m, dp_error *err)
{
	memset(wk, 0, sizeof *wk);
	wk->inv_v = dp_alloc_array(n, sizeof(float));
	int ok = wk->inv_v != NULL;
	float **bufs[] = {&wk->w, &wk->ax, &wk->ay, &wk->az, &wk->aw, &wk->rx, &wk->ry, &wk->rz, &wk->rw};
	for (size_t b = 0; b < sizeof bufs / sizeof bufs[0]; b++) {
		*bufs[b] = dp_alloc_array(m, sizeof(float));
		ok = ok && *bufs[b];
	}
	if (!ok)
		return dp_fail(err, DP_ERR_NOMEM, "wlop: out of memory for %zu input points and %zu samples", n, m);
	return DP_OK;
}

static dp_status support_radius(const dp_wlop_params *p, const dp_cloud *s, double *h, dp_error *err)
{
	*h = p->h;
	if (p->h > 0.0)
		return DP_OK;
	double spacing;
	dp_status st = dp_mean_spacing(s->n, s->x, s->y, s->z, &spacing, err);
	if (st != DP_OK)
		return st;
	*h = p->h_factor * spacing;
	if (!(*h > 0.0) || !isfinite(*h) || !isfinite((float)*h))
		return dp_fail(err, DP_ERR_ARG,
			       "wlop: no support radius from the spacing of %zu samples (%g); give h explicitly",
			       s->n, spacing);
	return DP_OK;
}

/* v_j of every input point, stored as 1/v_j in the input grid's order. */
static dp_status input_density(dp_context *ctx, wlop_work *wk, const dp_wlop_params *p, float h, dp_error *err)
{
	const dp_grid *g = &wk->input;
	dp_density_args a = {
		.data = g, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = h,
		.theta_k = (float)p->theta_k, .min_d2 = (DP_PAIR_EPS * h) * (DP_PAIR_EPS * h), .sqrt_density = 0,
		.out = wk->inv_v,
	};
	dp_status st = dp_op_density(ctx, &a, err);
	if (st != DP_OK)
		return st;
	for (size_t k = 0; k < g->n; k++)
		wk->inv_v[k] = 1.0f / wk->inv_v[k];
	return DP_OK;
}

/* One Jacobi iteration: every operator reads the sample grid's copy of the
 * positions, the update writes s in the caller's order. The queries are the
 * grid's sorted positions, so neighbouring work-items scan the same cells
 * (measured: the attraction of 47K samples over 484K points runs 1.7x faster
 * than with the samples in their random order). Returns the largest and the
 * mean move. */
static dp_status iterate(dp_context *ctx, wlop_work *wk, const dp_wlop_params *p, float h, dp_cloud *s,
			 dp_wlop_stats *stats, double *max_move, double *mean_move, dp_error *err)
{
	double t0 = dp_seconds();
	dp_status st = dp_grid_build(&wk->sample, s->n, s->x, s->y, s->z, h, err);
	if (st != DP_OK)
		return st;
	const dp_grid *g = &wk->sample;
	float theta_k = (float)p->theta_k, min_d2 = (DP_PAIR_EPS * h) * (DP_PAIR_EPS * h);
	double t1 = dp_seconds();
	dp_density_args da = {
		.data = g, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = h, .theta_k = theta_k,
		.min_d2 = min_d2, .sqrt_density = p->sqrt_density, .out = wk->w,
	};
	if ((st = dp_op_density(ctx, &da, err)) != DP_OK)
		return st;
	double t2 = dp_seconds();
	/* The Gaussian mean keeps the input point a sample sits on: skipping it,
	 * a sample near two isolated input points jumps between them for ever. */
	int gaussian = p->weight == DP_WLOP_GAUSSIAN;
	dp_attraction_args aa = {
		.data = &wk->input, .inv_v = wk->inv_v, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = h,
		.theta_k = theta_k, .min_d2 = gaussian ? 0.0f : min_d2, .gaussian = gaussian,
		.out_x = wk->ax, .out_y = wk->ay, .out_z = wk->az, .out_w = wk->aw,
	};
	if ((st = dp_op_attraction(ctx, &aa, err)) != DP_OK)
		return st;
	double t3 = dp_seconds();
	dp_repulsion_args ra = {
		.data = g, .w = wk->w, .nq = g->n, .qx = g->x, .qy = g->y, .qz = g->z, .h = h, .theta_k = theta_k,
		.min_d2 = min_d2, .out_x = wk->rx, .out_y = wk->ry, .out_z = wk->rz, .out_w = wk->rw,
	};
	if ((st = dp_op_repulsion(ctx, &ra, err)) != DP_OK)
		return st;
	double t4 = dp_seconds();

	/* x ← Σ c α/v / Σ α/v + μ Σ (x - x') w β / Σ w β, with the data term as an
	 * offset from x; a term without neighbours contributes nothing. */
	double mu = p->mu, worst2 = 0.0, total = 0.0;
	for (size_t k = 0; k < g->n; k++) {
		double mx = 0.0, my = 0.0, mz = 0.0;
		if (wk->aw[k] > 0.0f) {
			mx = (double)wk->ax[k] / wk->aw[k];
			my = (double)wk->ay[k] / wk->aw[k];
			mz = (double)wk->az[k] / wk->aw[k];
		}
		if (wk->rw[k] > 0.0f) {
			mx += mu * wk->rx[k] / wk->rw[k];
			my += mu * wk->ry[k] / wk->rw[k];
			mz += mu * wk->rz[k] / wk->rw[k];
		}
		uint32_t i = g->perm[k];
		s->x[i] = (float)(g->x[k] + mx);
		s->y[i] = (float)(g->y[k] + my);
		s->z[i] = (float)(g->z[k] + mz);
		double move2 = mx * mx + my * my + mz * mz;
		total += sqrt(move2);
		if (move2 > worst2)
			worst2 = move2;
	}
	*max_move = sqrt(worst2);
	*mean_move = g->n ? total / (double)g->n : 0.0;
	stats->seconds_grid += t1 - t0;
	stats->seconds_sample_density += t2 - t1;
	stats->seconds_attraction += t3 - t2;
	stats->seconds_repulsion += t4 - t3;
	return DP_OK;
}

dp_status dp_wlop(dp_context *ctx, const dp_cloud *input, const dp_wlop_params *params, dp_cloud *samples,
		  dp_wlop_stats *stats, dp_error *err)
{
	return dp_wlop_as(ctx, "wlop", input, params, samples, stats, err);
}

dp_status dp_wlop_as(dp_context *ctx, const char *stage, const dp_cloud *input, const dp_wlop_params *params,
		     dp_cloud *samples, dp_wlop_stats *stats, dp_error *err)
{
	double t_start = dp_seconds();
	dp_wlop_params defaults;
	dp_wlop_stats local;
	if (!params) {
		dp_wlop_params_default(&defaults);
		params = &defaults;
	}
	if (!stats)
		stats = &local;
	memset(stats, 0, sizeof *stats);
	if (!ctx || !input || !samples)
		return dp_fail(err, DP_ERR_ARG, "wlop: NULL context, input or output");
	if (samples == input)
		return dp_fail(err, DP_ERR_ARG, "wlop: the output cloud must not be the input");
	memset(samples, 0, sizeof *samples);
	dp_status st = check_params(params, err);
	if (st == DP_OK)
		st = check_input(input, err);
	if (st != DP_OK)
		return st;
	size_t m = params->samples ? params->samples : (size_t)llround(params->ratio * (double)input->n);
	if (m == 0)
		return dp_fail(err, DP_ERR_ARG, "wlop: no samples requested (ratio %g of %zu points)", params->ratio,
			       input->n);
	if (m > input->n)
		return dp_fail(err, DP_ERR_ARG, "wlop: %zu samples requested from only %zu input points", m,
			       input->n);
	if (input->n > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "wlop: %zu points exceed the 32-bit index range", input->n);
	size_t ndistinct = 0;
	if ((st = dp_distinct_upto(input, m, &ndistinct, err)) != DP_OK)
		return st;
	if (ndistinct < m)
		return dp_fail(err, DP_ERR_ARG, "wlop: the input has %zu distinct position%s, fewer than %zu samples",
			       ndistinct, ndistinct == 1 ? "" : "s", m);

	wlop_work wk;
	double h = 0.0, *moves = NULL;
	if ((st = work_alloc(&wk, input->n, m, err)) != DP_OK || (st = dp_cloud_alloc(samples, m, 0, err)) != DP_OK ||
	    (st = choose_samples(input, m, params->seed, samples, err)) != DP_OK ||
	    (st = support_radius(params, samples, &h, err)) != DP_OK ||
	    (st = dp_grid_build(&wk.input, input->n, input->x, input->y, input->z, (float)h, err)) != DP_OK)
		goto done;
	stats->samples = m;
	stats->h = h;
	double pairs0 = ctx->pair_evaluations, t_density = dp_seconds();
	stats->seconds_setup = t_density - t_start;
	if ((st = input_density(ctx, &wk, params, (float)h, err)) != DP_OK)
		goto done;
	double t_iter = dp_seconds();
	stats->seconds_density = t_iter - t_density;
	/* the last window + 1 mean moves, a ring indexed by iteration */
	size_t ring = (size_t)params->window + 1;
	if (!(moves = dp_alloc_array(ring, sizeof(double)))) {
		st = dp_fail(err, DP_ERR_NOMEM, "wlop: out of memory");
		goto done;
	}
	for (int it = 0; it < params->max_iters; it++) {
		double max_move, mean_move;
		if ((st = iterate(ctx, &wk, params, (float)h, samples, stats, &max_move, &mean_move, err)) != DP_OK)
			goto done;
		stats->iterations = it + 1;
		stats->last_max_move = max_move / h;
		stats->last_mean_move = mean_move / h;
		if ((st = dp_progress(ctx, stage, it + 1, stats->last_mean_move, err)) != DP_OK)
			goto done;
		moves[(size_t)it % ring] = stats->last_mean_move;
		if (stats->last_mean_move < params->tol) {
			stats->converged = 1;
			break;
		}
		if (it >= params->window && stats->last_mean_move < params->stall_tol &&
		    stats->last_mean_move > (1.0 - params->min_drop) * moves[(size_t)(it - params->window) % ring]) {
			stats->converged = 1;
			stats->stalled = 1;
			break;
		}
	}
	stats->seconds_iterations = dp_seconds() - t_iter;
	stats->pair_evaluations = ctx->pair_evaluations - pairs0;
done:
	free(moves);
	work_free(&wk);
	if (st != DP_OK)
		dp_cloud_free(samples);
	stats->seconds = dp_seconds() - t_start;
	return st;
}
