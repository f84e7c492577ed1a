/* The whole pipeline (DESIGN 2): raw C -> WLOP S -> normals -> sinking H ->
 * meso-skeleton Q -> surface P. */
#include "core/common.h"
#include "core/distinct.h"
#include "knn/knn.h"
#include "stages/refine.h"
#include "stages/scanner.h"
#include "stages/silhouette.h"
#include "stages/input_check.h"
#include "stages/surface.h"
#include "stages/width.h"
#include "stages/wlop.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void dp_params_default(dp_params *p)
{
	dp_wlop_params_default(&p->wlop);
	dp_normal_params_default(&p->normals);
	dp_sink_params_default(&p->sink);
	dp_skeleton_params_default(&p->skeleton);
	dp_surface_params_default(&p->surface);
	dp_refine_params_default(&p->refine);
}

/* Upsampling grows a coarse level of the input's distinct positions; below
 * this many there is no surface to grow from (sinking and the skeleton need
 * neighbourhoods of a few dozen points). */
#define MIN_COARSE_SAMPLES 32

void dp_refine_params_default(dp_refine_params *p)
{
	p->coarse_samples = 4000;
	p->coarse_min = 1000;
	p->level_factor = 4.0;
	p->level_iters = 15;
	p->samples_floor = 4000;
	p->even_rounds = 0;
	p->even_iters = 3;
	p->fill_samples = 2000;
}

/* The pipeline's own parameters (each stage checks its own). */
static dp_status check_params(const dp_params *p, dp_error *err)
{
	if (!(p->refine.level_factor > 1.0 && isfinite(p->refine.level_factor)) || p->refine.level_iters < 1)
		return dp_fail(err, DP_ERR_ARG, "level factor %g (must be > 1) or level iterations %d (must be >= 1) "
			       "out of range", p->refine.level_factor, p->refine.level_iters);
	if (p->refine.coarse_min && p->refine.coarse_min < MIN_COARSE_SAMPLES)
		return dp_fail(err, DP_ERR_ARG, "coarsest coarse level %zu: 0 or at least %d", p->refine.coarse_min,
			       MIN_COARSE_SAMPLES);
	if (p->refine.fill_samples && p->refine.fill_samples < MIN_COARSE_SAMPLES)
		return dp_fail(err, DP_ERR_ARG, "fill level %zu: 0 or at least %d", p->refine.fill_samples,
			       MIN_COARSE_SAMPLES);
	if (p->refine.even_rounds < 0 || p->refine.even_iters < 1)
		return dp_fail(err, DP_ERR_ARG, "even-spacing rounds %d (must be >= 0) or iterations %d (must be >= 1) "
			       "out of range", p->refine.even_rounds, p->refine.even_iters);
	const dp_surface_params *s = &p->surface;
	const double *g = s->silhouette_axis;
	float unit[3];
	if (!(s->silhouette_margin_r >= 0.0 && isfinite(s->silhouette_margin_r)))
		return dp_fail(err, DP_ERR_ARG, "silhouette margin %g r is not a finite number >= 0",
			       s->silhouette_margin_r);
	if (!(s->silhouette_edge_margin_r >= 0.0 && isfinite(s->silhouette_edge_margin_r)))
		return dp_fail(err, DP_ERR_ARG, "silhouette edge margin %g r is not a finite number >= 0",
			       s->silhouette_edge_margin_r);
	if (!(s->silhouette_grazing >= 0.0 && s->silhouette_grazing <= 1.0))
		return dp_fail(err, DP_ERR_ARG, "silhouette grazing fraction %g is not in [0, 1]", s->silhouette_grazing);
	if (dp_scanner_check(s, "", err) != DP_OK)
		return DP_ERR_ARG;
	if ((g[0] != 0.0 || g[1] != 0.0 || g[2] != 0.0) && !dp_silhouette_unit(g, unit))
		return dp_fail(err, DP_ERR_ARG, "view axis (%g, %g, %g) has no direction", g[0], g[1], g[2]);
	return DP_OK;
}

/* The deep-point count: wlop.samples, or the default rule of
 * dp_refine_params. */
static dp_status target_count(const dp_cloud *input, const dp_params *p, size_t *m, dp_error *err)
{
	if (p->wlop.samples) {
		if (p->wlop.samples > UINT32_MAX)
			return dp_fail(err, DP_ERR_ARG, "%zu deep points: more than 32-bit indices reach",
				       p->wlop.samples);
		*m = p->wlop.samples;
		return DP_OK;
	}
	if (!(p->wlop.ratio > 0.0 && p->wlop.ratio <= 1.0))
		return dp_fail(err, DP_ERR_ARG, "sample ratio %g is not in (0, 1]", p->wlop.ratio);
	size_t want = (size_t)llround(p->wlop.ratio * (double)input->n), distinct = 0;
	if (want < p->refine.samples_floor)
		want = p->refine.samples_floor;
	if (want > input->n)
		want = input->n;
	dp_status st = dp_distinct_upto(input, want, &distinct, err);
	if (st != DP_OK)
		return st;
	*m = want < distinct ? want : distinct;
	return DP_OK;
}

/* Adds one run of the surface stage to the whole stage's counts. */
static void add_run(dp_result *res, const dp_surface_stats *st)
{
	dp_surface_stats *all = &res->surface_stats;
	all->iterations += st->iterations;
	all->seconds += st->seconds;
	all->pair_evaluations += st->pair_evaluations;
	all->reattached += st->reattached;
	all->escaped += st->escaped;
	all->sheet_points += st->sheet_points;
	all->silhouette_held += st->silhouette_held;
	all->scanner_turned += st->scanner_turned;
	all->normals_disagreeing = st->normals_disagreeing;
	all->last_mean_move = st->last_mean_move;
}

static void add_level(dp_result *res, size_t points, double r, const dp_surface_stats *st)
{
	dp_level_stats *l = &res->level[res->levels++];
	l->points = points;
	l->r = r;
	l->iterations = st->iterations;
	l->seconds = st->seconds;
	l->pair_evaluations = st->pair_evaluations;
	add_run(res, st);
}

/* Copies the first n rows of src into dst, which has room for them. */
static void copy_rows(dp_cloud *dst, const dp_cloud *src, size_t n)
{
	size_t bytes = n * sizeof(float);
	memcpy(dst->x, src->x, bytes);
	memcpy(dst->y, src->y, bytes);
	memcpy(dst->z, src->z, bytes);
	if (dst->nx && src->nx) {
		memcpy(dst->nx, src->nx, bytes);
		memcpy(dst->ny, src->ny, bytes);
		memcpy(dst->nz, src->nz, bytes);
	}
	dst->n = n;
}

/* The inside test's balls (dp_balls): an anchor settled on evidence is the
 * centre, and the radius its depth below its sample, cut to its distance
 * from the nearest input point; other anchors have none. The settle tests
 * stop an anchor a little off the medial axis, and a ball off the axis
 * reaches out of the body on its far side by as much: a point moved to its
 * sphere would land outside, beyond the data that would pull it back. */
static dp_status sinking_balls(const dp_cloud *input, const dp_result *res, float *radius, dp_error *err)
{
	size_t n = res->wlop.n;
	dp_knn knn = {0};
	int *idx = dp_alloc_array(n, sizeof(int));
	float *d2 = dp_alloc_array(n, sizeof(float));
	dp_status st = DP_OK;
	if (!idx || !d2)
		st = dp_fail(err, DP_ERR_NOMEM, "out of memory for %zu balls", n);
	if (st == DP_OK)
		st = dp_knn_build(&knn, input->n, input->x, input->y, input->z, err);
	if (st == DP_OK)
		st = dp_knn_query(&knn, n, res->anchors.x, res->anchors.y, res->anchors.z, 1, idx, d2, err);
	for (size_t i = 0; st == DP_OK && i < n; i++) {
		dp_settle why = (dp_settle)res->settled_by[i];
		float d[3] = {res->wlop.x[i] - res->anchors.x[i], res->wlop.y[i] - res->anchors.y[i],
			      res->wlop.z[i] - res->anchors.z[i]};
		radius[i] = why == DP_SETTLE_FRONT || why == DP_SETTLE_MEDIAL
				    ? fminf(sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), sqrtf(d2[i]))
				    : 0.0f;
	}
	dp_knn_free(&knn);
	free(idx);
	free(d2);
	return st;
}

/* A one-sided scan's coarse level may be coarser than coarse_samples where
 * nothing is thin: no WLOP sample's width bound (width.h, at the sinking's
 * factor; 2, 4, 8, 16 or 32 r, or none) within this many r. At 1000 samples
 * the demo chair's legs, the bunny's ears and feet and a one-view torus's
 * tube (4 r across) all bound at 16 r or less, and completing the torus
 * from there left its surface 0.032-0.045 of the tube's radius off against
 * 0.012-0.040 from 4000 (bench_quality_sizes); a one-view sphere 13 to 16 r
 * in radius there bounds at 32 r or nowhere and fills its far side from
 * 1000 (README (42)). */
#define COARSE_THIN_R 16.0

/* Whether any of the samples `s` lies in a part thinner than COARSE_THIN_R r. */
static dp_status any_thin(const dp_cloud *s, double factor, int *thin, dp_error *err)
{
	double r = 0.0;
	float *bound = dp_alloc_array(s->n, sizeof *bound);
	if (!bound)
		return dp_fail(err, DP_ERR_NOMEM, "out of memory for %zu width bounds", s->n);
	dp_status st = dp_mean_spacing(s->n, s->x, s->y, s->z, &r, err);
	if (st == DP_OK)
		st = dp_width_bound(s->n, s->x, s->y, s->z, r, factor, bound, err);
	*thin = 0;
	/* the bounds are scale / 2 exactly: 2 r, 4 r, ... */
	for (size_t i = 0; st == DP_OK && i < s->n && !*thin; i++)
		*thin = bound[i] <= (float)(COARSE_THIN_R * r) * 1.001f;
	free(bound);
	return st;
}

/* Whether the samples `s` (with normals) are a scan taken from one side
 * (scanner.h): a whole side to complete. */
static dp_status one_sided(const dp_cloud *s, const dp_surface_params *p, int *side, dp_error *err)
{
	float axis[3];
	int found = 0;
	double grazing = 0.0, r = 0.0;
	*side = 0;
	dp_silhouette_pick(p->silhouette_axis, s->n, s->nx, s->ny, s->nz, p->silhouette_grazing, &found, axis, &grazing);
	if (!found)
		return DP_OK;
	dp_status st = dp_mean_spacing(s->n, s->x, s->y, s->z, &r, err);
	if (st == DP_OK)
		st = dp_scanner_side(s->n, s->x, s->y, s->z, s->nx, s->ny, s->nz, axis, p->face_scanner_cos, r, side, err);
	return st;
}

/* A coarser coarse level for a scan taken from one side, whose whole far
 * side is to be completed: WLOP at coarse_min, doubling while below
 * `count`, until no sample lies in a part thinner than COARSE_THIN_R r. The
 * first such samples go to `coarser` (zeroed when there are none) and their
 * count to *chosen (0: none). Complete shapes keep the coarse level they
 * had: with nothing to fill, a coarser one only loses detail (a slab 3.6 r
 * thick at 1000, a plate, which the width bound does not see: 0.69 of its
 * mid-plane against all of it). */
static dp_status coarser_level(dp_context *ctx, const dp_cloud *input, const dp_params *params, size_t count,
			       dp_cloud *coarser, dp_wlop_stats *ws, size_t *chosen, dp_error *err)
{
	*chosen = 0;
	double factor = params->sink.width_factor > 0.0 ? params->sink.width_factor : 2.0;
	dp_wlop_params wp = params->wlop;
	for (size_t c = params->refine.coarse_min; c && c < count; c *= 2) {
		int thin = 1;
		wp.samples = c;
		dp_status st = dp_wlop_as(ctx, "coarser", input, &wp, coarser, ws, err);
		if (st == DP_OK)
			st = any_thin(coarser, factor, &thin, err);
		if (st != DP_OK || !thin) {
			*chosen = st == DP_OK ? c : 0;
			return st;
		}
		dp_cloud_free(coarser);
	}
	return DP_OK;
}

/* Moves rows keep[0..m) (ascending) of the cloud's arrays to the front; an
 * empty cloud stays empty. */
static void keep_rows(dp_cloud *c, const uint32_t *keep, size_t m)
{
	if (!c->n)
		return;
	float *a[] = {c->x, c->y, c->z, c->nx, c->ny, c->nz, c->intensity};
	for (size_t k = 0; k < sizeof a / sizeof a[0]; k++)
		for (size_t i = 0; a[k] && i < m; i++)
			a[k][i] = a[k][keep[i]];
	for (size_t i = 0; c->rgb && i < m; i++)
		memmove(c->rgb + 3 * i, c->rgb + 3 * (size_t)keep[i], 3);
	c->n = m;
}

/* An even subset of m of the deep points, picked over `by` (the surface,
 * or the WLOP samples before there is one) by dp_refine_subset: the same
 * rows of every array (those not yet made stay empty). The samples and
 * anchors hold the first rows only, those of the surface stage's first
 * level (dp_result), so they keep the picks among those rows. */
static dp_status keep_subset(dp_result *res, const dp_cloud *by, size_t m, dp_error *err)
{
	uint32_t *keep = dp_alloc_array(m, sizeof *keep);
	if (!keep)
		return dp_fail(err, DP_ERR_NOMEM, "out of memory choosing %zu deep points", m);
	dp_status st = dp_refine_subset(by->n, by->x, by->y, by->z, m, keep, err);
	if (st == DP_OK) {
		size_t first = 0; /* picks among the samples' rows: keep is ascending */
		while (first < m && keep[first] < res->wlop.n)
			first++;
		keep_rows(&res->surface, keep, m);
		keep_rows(&res->skeleton, keep, m);
		keep_rows(&res->wlop, keep, first);
		keep_rows(&res->anchors, keep, first);
		for (size_t i = 0; res->eta && i < m; i++) {
			res->eta[i] = res->eta[keep[i]];
			res->length[i] = res->length[keep[i]];
		}
		/* the settle counts describe the anchors kept, as anchors.ply does */
		dp_sink_stats *ss = &res->sink_stats;
		ss->settled_front = ss->settled_medial = ss->settled_width = ss->settled_slow = ss->settled_flat =
			ss->unsettled = 0;
		for (size_t i = 0; i < first; i++) {
			unsigned char why = res->settled_by[i] = res->settled_by[keep[i]];
			ss->settled_front += why == DP_SETTLE_FRONT;
			ss->settled_medial += why == DP_SETTLE_MEDIAL;
			ss->settled_width += why == DP_SETTLE_WIDTH;
			ss->settled_slow += why == DP_SETTLE_SLOW;
			ss->settled_flat += why == DP_SETTLE_FLAT;
			ss->unsettled += why == DP_SETTLE_NONE;
		}
	}
	free(keep);
	return st;
}

/* Levels 1.. of the coarse-to-fine surface: insert, then relax at the new
 * spacing. `surface`, `skeleton` and `eta` have room for counts[levels-1]
 * rows and hold the coarse level. */
static dp_status refine(dp_context *ctx, const dp_cloud *input, const dp_params *params, const size_t *counts,
			int levels, const dp_balls *balls, dp_result *res, dp_error *err)
{
	dp_surface_params relax = params->surface;
	relax.max_iters = params->refine.level_iters;
	/* a fixed number of iterations: with the window as long as the run,
	 * neither stop test can fire before its last iteration */
	relax.window = params->refine.level_iters;
	dp_cloud out = {0};
	for (int l = 1; l < levels; l++) {
		size_t added = 0;
		dp_status st = dp_refine_insert(&res->surface, &res->skeleton, counts[l], &added, err);
		if (st == DP_OK && res->surface.n < counts[l])
			st = dp_fail(err, DP_ERR_ARG, "refine: insertion found places for only %zu of %zu points",
				     res->surface.n, counts[l]);
		if (st == DP_OK)
			st = dp_mean_spacing(res->surface.n, res->surface.x, res->surface.y, res->surface.z, &res->r,
					     err);
		dp_surface_stats sst = {0};
		relax.sheet_points = params->surface.sheet_points && l == levels - 1 && params->refine.even_rounds == 0;
		if (st == DP_OK)
			st = dp_surface_as(ctx, "surface", input, &res->surface, &res->wlop, &res->skeleton, balls, res->r,
					   &relax, &out, res->eta, &sst, err);
		if (st != DP_OK)
			return st;
		copy_rows(&res->surface, &out, out.n);
		dp_cloud_free(&out);
		add_level(res, res->surface.n, res->r, &sst);
	}
	return DP_OK;
}

/* The even-spacing rounds (dp_refine_params.even_rounds) after the last
 * level, at its spacing r: the step they even out is between regions many r
 * apart, which the spacing of neither measures. A ball of the inside test
 * hands an escaping point the inner end of the deep point in its sample's
 * row; a round puts a new point, elsewhere, into that row when it removes
 * the old one, so the ball is dropped (its radius in `radius`, which `balls`
 * reads, set to 0). */
static dp_status even_out(dp_context *ctx, const dp_cloud *input, const dp_params *params, const dp_balls *balls,
			  float *radius, dp_result *res, dp_error *err)
{
	int rounds = params->refine.even_rounds;
	if (rounds == 0)
		return DP_OK;
	dp_surface_params relax = params->surface;
	relax.max_iters = params->refine.even_iters;
	relax.window = params->refine.even_iters;
	unsigned char *replaced = calloc(res->surface.n, 1);
	if (!replaced)
		return dp_fail(err, DP_ERR_NOMEM, "refine: out of memory for %zu points", res->surface.n);
	dp_status st = DP_OK;
	for (int round = 0; st == DP_OK && round < rounds; round++) {
		size_t moved = 0;
		dp_cloud out = {0};
		dp_surface_stats sst = {0};
		st = dp_refine_even(&res->surface, &res->skeleton, replaced, &moved, err);
		for (size_t i = 0; balls && i < balls->n; i++)
			if (replaced[i])
				radius[i] = 0.0f;
		relax.sheet_points = params->surface.sheet_points && round == rounds - 1;
		if (st == DP_OK)
			st = dp_surface_as(ctx, "even", input, &res->surface, &res->wlop, &res->skeleton, balls, res->r,
					   &relax, &out, res->eta, &sst, err);
		if (st == DP_OK) {
			copy_rows(&res->surface, &out, out.n);
			res->even_moved += moved;
			add_run(res, &sst);
		}
		dp_cloud_free(&out);
	}
	free(replaced);
	return st;
}

/* The scan's view axis, given or found from the WLOP samples' normals
 * (silhouette.h; all zero: none), and the side it was taken from
 * (scanner.h; 0: both or unknown), whose samples' normals then face it; or,
 * with the scanner's eye given, the samples face the eye and no side is
 * read. Every surface run gets the same: the levels' samples are the
 * completed surface, whose normals face every way. DP_ERR_NOMEM. */
static dp_status view_of_scan(const dp_surface_params *p, dp_result *res, double axis_out[3], int *side,
			      dp_error *err)
{
	axis_out[0] = axis_out[1] = axis_out[2] = 0.0;
	*side = 0;
	dp_cloud *w = &res->wlop;
	/* a scanner's eye given: the samples face it (those the normals stage
	 * oriented towards it already do), and no side is needed */
	if (p->face_scanner && p->use_viewpoint)
		res->samples_turned = dp_scanner_face_eye(w->n, w->x, w->y, w->z, w->nx, w->ny, w->nz, p->viewpoint,
							  p->face_scanner_cos);
	if (!p->silhouette && !p->face_scanner)
		return DP_OK;
	float axis[3];
	int found = 0;
	dp_silhouette_pick(p->silhouette_axis, w->n, w->nx, w->ny, w->nz, p->silhouette_grazing, &found, axis,
			   &res->surface_stats.silhouette_grazing);
	if (!found)
		return DP_OK;
	for (int c = 0; c < 3; c++)
		axis_out[c] = axis[c];
	if (!p->face_scanner || p->use_viewpoint)
		return DP_OK;
	*side = p->scanner_side;
	dp_status st = DP_OK;
	if (!*side)
		st = dp_scanner_side(w->n, w->x, w->y, w->z, w->nx, w->ny, w->nz, axis, p->face_scanner_cos, res->r, side,
				     err);
	float toward[3] = {(float)*side * axis[0], (float)*side * axis[1], (float)*side * axis[2]};
	if (*side)
		res->samples_turned = dp_scanner_face(w->n, w->nx, w->ny, w->nz, toward, p->face_scanner_cos);
	return st;
}

/* Each anchor sunk out of the scan's own outline seen along `axis` (all
 * zero: none) comes back into it along its line (dp_silhouette_cap). */
static dp_status outline_anchors(const dp_cloud *input, const dp_surface_params *p, const double axis_in[3],
				 dp_result *res, dp_error *err)
{
	float axis[3];
	if (!p->silhouette || !dp_silhouette_unit(axis_in, axis))
		return DP_OK;
	dp_silhouette outline = {0};
	dp_status st = dp_silhouette_build(&outline, input, axis, res->r, p->silhouette_margin_r * res->r, &res->wlop,
					   p->silhouette_edge_margin_r * res->r, err);
	for (size_t i = 0; st == DP_OK && i < res->anchors.n; i++) {
		float at[3] = {res->wlop.x[i], res->wlop.y[i], res->wlop.z[i]};
		float q[3] = {res->anchors.x[i], res->anchors.y[i], res->anchors.z[i]};
		if (dp_silhouette_cap(&outline, at, q)) {
			res->anchors.x[i] = q[0], res->anchors.y[i] = q[1], res->anchors.z[i] = q[2];
			res->silhouette_capped++;
		}
	}
	dp_silhouette_free(&outline);
	return st;
}

void dp_result_free(dp_result *r)
{
	if (!r)
		return;
	dp_cloud_free(&r->wlop);
	dp_cloud_free(&r->anchors);
	free(r->settled_by);
	dp_cloud_free(&r->skeleton);
	dp_cloud_free(&r->surface);
	free(r->eta);
	free(r->length);
	memset(r, 0, sizeof *r);
}

/* Prefixes err's message with the stage that failed, unless the stage
 * already named itself. */
static dp_status in_stage(dp_error *err, dp_status st, const char *stage)
{
	size_t len = strlen(stage);
	if (err && st != DP_OK && strncmp(err->message, stage, len) != 0) {
		char msg[DP_ERROR_MESSAGE_MAX];
		snprintf(msg, sizeof msg, "%s", err->message);
		dp_fail(err, st, "%s: %s", stage, msg);
	}
	return st;
}

dp_status dp_consolidate(dp_context *ctx, const dp_cloud *input, const dp_params *params, dp_result *res,
			 dp_error *err)
{
	if (!ctx || !input || !res)
		return dp_fail(err, DP_ERR_ARG, "consolidate: NULL context, input or result");
	dp_params defaults;
	if (!params) {
		dp_params_default(&defaults);
		params = &defaults;
	}
	memset(res, 0, sizeof *res);
	if (dp_check_volume(input, err) != DP_OK)
		return DP_ERR_ARG;
	double t_start = dp_seconds();
	res->points_in = input->n;
	res->params = *params;
	res->backend = dp_context_backend(ctx);
	snprintf(res->device, sizeof res->device, "%s", dp_context_device_name(ctx));
	size_t target = 0, counts[DP_MAX_LEVELS];
	float *ball_radius = NULL;
	dp_status st = check_params(params, err);
	if (st != DP_OK)
		goto fail;
	st = target_count(input, params, &target, err);
	if (st != DP_OK) {
		in_stage(err, st, "deep-point count");
		goto fail;
	}
	/* The coarse level comes from WLOP, so it can hold at most the input's
	 * distinct positions; the levels above it may exceed them (upsampling). */
	size_t coarse_count = params->refine.coarse_samples, distinct = 0;
	if (coarse_count && (st = dp_distinct_upto(input, coarse_count, &distinct, err)) != DP_OK) {
		in_stage(err, st, "deep-point count");
		goto fail;
	}
	if (coarse_count && distinct < coarse_count)
		coarse_count = distinct;
	if (coarse_count && coarse_count < target && coarse_count < MIN_COARSE_SAMPLES) {
		st = dp_fail(err, DP_ERR_ARG, "wlop: the input has %zu distinct position%s, fewer than %zu samples",
			     distinct, distinct == 1 ? "" : "s", target);
		goto fail;
	}
	/* Fewer deep points than the coarse level are a subset of it: run at
	 * fewer, parts a sample or two thick (the demo chair's legs and back at
	 * 1000 samples) have no normal of their own (dp_refine_params). */
	size_t run = coarse_count > target ? coarse_count : target;
	int levels = dp_refine_levels(coarse_count, run, params->refine.level_factor, counts, DP_MAX_LEVELS);
	dp_wlop_params wp = params->wlop;
	wp.samples = counts[0];
	st = dp_wlop(ctx, input, &wp, &res->wlop, &res->wlop_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "wlop");
		goto fail;
	}

	double t0 = dp_seconds();
	st = dp_estimate_normals(&res->wlop, &params->normals, err);
	res->seconds_normals = dp_seconds() - t0;
	if (st != DP_OK)
		goto fail_normals;
	int coarser_ok = coarse_count && params->refine.coarse_min && params->refine.coarse_min < coarse_count;
	int fill_ok = coarse_count && params->refine.fill_samples && params->refine.fill_samples < res->wlop.n;
	int one_side = params->surface.scanner_side;
	if ((coarser_ok || fill_ok) && !one_side &&
	    (st = one_sided(&res->wlop, &params->surface, &one_side, err)) != DP_OK)
		goto fail_normals;
	if (coarser_ok && one_side) {
		dp_cloud coarser = {0};
		dp_wlop_stats ws = {0};
		size_t chosen = 0;
		st = coarser_level(ctx, input, params, coarse_count, &coarser, &ws, &chosen, err);
		if (st == DP_OK && chosen) {
			t0 = dp_seconds();
			st = dp_estimate_normals(&coarser, &params->normals, err);
			res->seconds_normals += dp_seconds() - t0;
		}
		if (st != DP_OK) {
			dp_cloud_free(&coarser);
			in_stage(err, st, "coarse level");
			goto fail;
		}
		if (chosen) {
			dp_cloud_free(&res->wlop);
			res->wlop = coarser;
			res->wlop_stats = ws;
			coarse_count = chosen;
			run = coarse_count > target ? coarse_count : target;
			levels = dp_refine_levels(coarse_count, run, params->refine.level_factor, counts, DP_MAX_LEVELS);
		}
	}
	res->ran_with = run;
	st = dp_mean_spacing(res->wlop.n, res->wlop.x, res->wlop.y, res->wlop.z, &res->r, err);
	if (st == DP_OK && !(res->r > 0.0))
		st = dp_fail(err, DP_ERR_EMPTY, "%zu WLOP sample%s: no spacing r to work in", res->wlop.n,
			     res->wlop.n == 1 ? "" : "s that coincide");
	if (st != DP_OK) {
		in_stage(err, st, "spacing r");
		goto fail;
	}

	/* the scanner's eye, the surface's own or else the normals' (unless a
	 * side was given: that says where the scanner was) */
	dp_surface_params seen = params->surface;
	if (!seen.use_viewpoint && !seen.scanner_side && params->normals.use_viewpoint) {
		seen.use_viewpoint = 1;
		memcpy(seen.viewpoint, params->normals.viewpoint, sizeof seen.viewpoint);
	}
	double axis[3];
	int side;
	if ((st = view_of_scan(&seen, res, axis, &side, err)) != DP_OK) {
		in_stage(err, st, "view axis");
		goto fail;
	}
	if (!(res->settled_by = dp_alloc_array(res->wlop.n, 1))) {
		st = dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for %zu points", res->wlop.n);
		goto fail;
	}
	res->sink_r = res->r;
	st = dp_sink(ctx, &res->wlop, res->r, &params->sink, &res->anchors, res->settled_by, &res->sink_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "sink");
		goto fail;
	}
	st = outline_anchors(input, &params->surface, axis, res, err);
	if (st != DP_OK)
		goto fail; /* its errors name the silhouette */
	st = dp_skeleton(ctx, &res->anchors, res->r, &params->skeleton, &res->skeleton, &res->skeleton_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "skeleton");
		goto fail;
	}
	/* A one-sided scan's far side fills from an even subset of the deep
	 * points: sinking and the skeleton need the coarse level's spacing for
	 * its thin parts, completion a coarser one (dp_refine_params). */
	if (fill_ok && one_side && res->wlop.n > params->refine.fill_samples) {
		res->filled_from = res->wlop.n;
		st = keep_subset(res, &res->wlop, params->refine.fill_samples, err);
		if (st == DP_OK)
			st = dp_mean_spacing(res->wlop.n, res->wlop.x, res->wlop.y, res->wlop.z, &res->r, err);
		if (st != DP_OK) {
			in_stage(err, st, "fill level");
			goto fail;
		}
		levels = dp_refine_levels(res->wlop.n, run, params->refine.level_factor, counts, DP_MAX_LEVELS);
	}
	size_t n = run, n0 = res->wlop.n;
	dp_cloud coarse = {0}, inner = {0};
	dp_surface_stats sst = {0};
	res->eta = dp_alloc_array(n, sizeof(float));
	res->length = dp_alloc_array(n, sizeof(float));
	if (!res->eta || !res->length || dp_cloud_alloc(&res->surface, n, 1, err) != DP_OK ||
	    dp_cloud_alloc(&inner, n, 1, err) != DP_OK) {
		dp_cloud_free(&inner);
		st = dp_fail(err, DP_ERR_NOMEM, "out of memory for %zu deep points", n);
		goto fail;
	}
	int escaping = params->surface.escape_margin_r > 0.0;
	if (escaping && !(ball_radius = dp_alloc_array(n0, sizeof(float))))
		st = dp_fail(err, DP_ERR_NOMEM, "out of memory for %zu deep points", n0);
	if (escaping && st == DP_OK)
		st = sinking_balls(input, res, ball_radius, err);
	dp_balls sunk = {n0, res->anchors.x, res->anchors.y, res->anchors.z, ball_radius}, *balls = escaping ? &sunk : NULL;
	/* points stranded in a sheet move once, after the last level: moved
	 * earlier, insertion and relaxing take them back into it */
	/* every surface run holds its points in the outline found above and
	 * faces the scanner's side found there: the levels' samples are the
	 * completed surface, whose normals face every way */
	dp_params later = *params;
	later.surface = seen;
	memcpy(later.surface.silhouette_axis, axis, sizeof axis);
	later.surface.silhouette = params->surface.silhouette && (axis[0] != 0.0 || axis[1] != 0.0 || axis[2] != 0.0);
	later.surface.face_scanner = params->surface.face_scanner && (side != 0 || seen.use_viewpoint);
	later.surface.scanner_side = side;
	dp_surface_params coarse_params = later.surface;
	coarse_params.sheet_points = params->surface.sheet_points && levels == 1 && params->refine.even_rounds == 0;
	if (st == DP_OK)
		st = dp_surface_as(ctx, "surface", input, &res->wlop, &res->wlop, &res->skeleton, balls, res->r,
				   &coarse_params, &coarse, res->eta, &sst, err);
	if (st == DP_OK) {
		copy_rows(&res->surface, &coarse, n0);
		copy_rows(&inner, &res->skeleton, n0);
		add_level(res, n0, res->r, &sst);
		res->surface_stats.converged = sst.converged;
		res->surface_stats.spacing_growth = sst.spacing_growth;
		memcpy(res->surface_stats.silhouette_axis, sst.silhouette_axis, sizeof sst.silhouette_axis);
		memcpy(res->surface_stats.scanner, sst.scanner, sizeof sst.scanner);
		res->surface_stats.scanner_at_eye = sst.scanner_at_eye;
	}
	dp_cloud_free(&coarse);
	dp_cloud_free(&res->skeleton);
	res->skeleton = inner;
	if (st != DP_OK) {
		in_stage(err, st, "surface");
		goto fail;
	}
	st = refine(ctx, input, &later, counts, levels, balls, res, err);
	if (st == DP_OK)
		st = even_out(ctx, input, &later, balls, ball_radius, res, err);
	if (st != DP_OK) {
		in_stage(err, st, "refine");
		goto fail;
	}
	for (size_t i = 0; i < n; i++) {
		double dx = res->surface.x[i] - res->skeleton.x[i], dy = res->surface.y[i] - res->skeleton.y[i],
		       dz = res->surface.z[i] - res->skeleton.z[i];
		res->length[i] = (float)sqrt(dx * dx + dy * dy + dz * dz);
	}
	if (run > target && (st = keep_subset(res, &res->surface, target, err)) != DP_OK) {
		in_stage(err, st, "refine");
		goto fail;
	}
	if ((st = dp_check_result_bounds(input, res, err)) != DP_OK)
		goto fail;
	res->seconds_total = dp_seconds() - t_start;
	free(ball_radius);
	return DP_OK;
fail_normals:
	in_stage(err, st, "normals");
fail:
	free(ball_radius);
	dp_result_free(res);
	return st;
}
