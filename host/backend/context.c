#include "backend/context.h"

#include "backend/ops.h"

#include "core/common.h"
#include "core/parallel.h"

#include <stdlib.h>

dp_status dp_context_create(dp_context **out, dp_backend_kind kind, const char *device, dp_error *err)
{
	*out = NULL;
	if (kind != DP_BACKEND_CL && kind != DP_BACKEND_REF)
		return dp_fail(err, DP_ERR_ARG, "unknown backend %d", (int)kind);
	dp_context *ctx = calloc(1, sizeof *ctx);
	if (!ctx)
		return dp_fail(err, DP_ERR_NOMEM, "out of memory creating a context");
	ctx->kind = kind;
	ctx->started = dp_seconds();
	ctx->threads = dp_parallel_cpus();
	if (kind == DP_BACKEND_CL) {
		dp_status st = dp_cl_open(&ctx->cl, device, err);
		if (st == DP_OK && (st = dp_ops_check_kernels(&ctx->cl, err)) != DP_OK)
			dp_cl_close(&ctx->cl);
		if (st != DP_OK) {
			free(ctx);
			return st;
		}
		ctx->cl.pair_counter = &ctx->pair_evaluations;
	}
	*out = ctx;
	return DP_OK;
}

void dp_context_free(dp_context *ctx)
{
	if (!ctx)
		return;
	if (ctx->kind == DP_BACKEND_CL)
		dp_cl_close(&ctx->cl);
	free(ctx);
}

const char *dp_context_device_name(const dp_context *ctx)
{
	return ctx->kind == DP_BACKEND_CL ? ctx->cl.name : "reference (scalar C)";
}

dp_backend_kind dp_context_backend(const dp_context *ctx)
{
	return ctx->kind;
}

void dp_context_set_progress(dp_context *ctx, dp_progress_fn fn, void *user)
{
	ctx->progress = fn;
	ctx->progress_user = user;
}

void dp_context_set_threads(dp_context *ctx, int threads)
{
	ctx->threads = threads < 1 ? dp_parallel_cpus() : threads > DP_PARALLEL_MAX ? DP_PARALLEL_MAX : threads;
}

int dp_context_threads(const dp_context *ctx)
{
	return ctx->threads;
}

dp_status dp_progress(dp_context *ctx, const char *stage, int iteration, double value, dp_error *err)
{
	if (ctx->progress && ctx->progress(ctx->progress_user, stage, iteration, value, dp_seconds() - ctx->started))
		return dp_fail(err, DP_ERR_CANCELLED, "%s: cancelled by the progress callback at iteration %d", stage,
			       iteration);
	return DP_OK;
}
