/* The whole pipeline (DESIGN 2): raw C -> WLOP S -> normals -> sinking H ->
 * meso-skeleton Q -> surface P. */
#include "core/common.h"
#include "knn/knn.h"
#include "stages/input_check.h"

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
}

void dp_result_free(dp_result *r)
{
	if (!r)
		return;
	dp_cloud_free(&r->wlop);
	dp_cloud_free(&r->anchors);
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
	dp_status st = dp_wlop(ctx, input, &params->wlop, &res->wlop, &res->wlop_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "wlop");
		goto fail;
	}

	double t0 = dp_seconds();
	st = dp_estimate_normals(&res->wlop, &params->normals, err);
	res->seconds_normals = dp_seconds() - t0;
	if (st != DP_OK)
		goto fail_normals;
	st = dp_mean_spacing(res->wlop.n, res->wlop.x, res->wlop.y, res->wlop.z, &res->r, err);
	if (st == DP_OK && !(res->r > 0.0))
		st = dp_fail(err, DP_ERR_EMPTY, "%zu WLOP sample%s: no spacing r to work in", res->wlop.n,
			     res->wlop.n == 1 ? "" : "s that coincide");
	if (st != DP_OK) {
		in_stage(err, st, "spacing r");
		goto fail;
	}

	st = dp_sink(ctx, &res->wlop, res->r, &params->sink, &res->anchors, &res->sink_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "sink");
		goto fail;
	}
	st = dp_skeleton(ctx, &res->anchors, res->r, &params->skeleton, &res->skeleton, &res->skeleton_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "skeleton");
		goto fail;
	}
	size_t n = res->wlop.n;
	res->eta = dp_alloc_array(n, sizeof(float));
	res->length = dp_alloc_array(n, sizeof(float));
	if (!res->eta || !res->length) {
		st = dp_fail(err, DP_ERR_NOMEM, "out of memory for %zu deep points", n);
		goto fail;
	}
	st = dp_surface(ctx, input, &res->wlop, &res->skeleton, res->r, &params->surface, &res->surface, res->eta,
			&res->surface_stats, err);
	if (st != DP_OK) {
		in_stage(err, st, "surface");
		goto fail;
	}
	for (size_t i = 0; i < n; i++) {
		double dx = res->surface.x[i] - res->skeleton.x[i], dy = res->surface.y[i] - res->skeleton.y[i],
		       dz = res->surface.z[i] - res->skeleton.z[i];
		res->length[i] = (float)sqrt(dx * dx + dy * dy + dz * dz);
	}
	if ((st = dp_check_result_bounds(input, res, err)) != DP_OK)
		goto fail;
	res->seconds_total = dp_seconds() - t_start;
	return DP_OK;
fail_normals:
	in_stage(err, st, "normals");
fail:
	dp_result_free(res);
	return st;
}
