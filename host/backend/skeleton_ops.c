#include "backend/skeleton_ops.h"

dp_status dp_op_skeleton_cov(dp_context *ctx, const dp_skeleton_cov_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_skeleton_cov(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[3 + DP_CL_GRID_NARGS + 3];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->qx, qbytes);
	args[1] = DP_CL_IN(a->qy, qbytes);
	args[2] = DP_CL_IN(a->qz, qbytes);
	dp_cl_grid_args(a->data, &gs, args + 3);
	size_t k = 3 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_OUT(a->count, qbytes);
	args[k++] = DP_CL_OUT(a->cov, 6 * qbytes);
	return dp_cl_launch(&ctx->cl, "skeleton_cov", a->nq, args, k, err);
}

dp_status dp_op_skeleton_semiaxes(dp_context *ctx, const dp_skeleton_semiaxes_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_skeleton_semiaxes(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[3 + DP_CL_GRID_NARGS + 7];
	size_t qbytes = a->nq * sizeof(float), gbytes = a->data->n * sizeof(float);
	args[0] = DP_CL_IN(a->qx, qbytes);
	args[1] = DP_CL_IN(a->qy, qbytes);
	args[2] = DP_CL_IN(a->qz, qbytes);
	dp_cl_grid_args(a->data, &gs, args + 3);
	size_t k = 3 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_IN(a->nx, gbytes);
	args[k++] = DP_CL_IN(a->ny, gbytes);
	args[k++] = DP_CL_IN(a->nz, gbytes);
	args[k++] = DP_CL_IN(a->frames, 9 * qbytes);
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->eps);
	args[k++] = DP_CL_OUT(a->semi, 3 * qbytes);
	return dp_cl_launch(&ctx->cl, "skeleton_semiaxes", a->nq, args, k, err);
}

/* skeleton_median and skeleton_repulse share one argument list. */
static dp_status launch_weighted(dp_context *ctx, const char *kernel, const dp_grid *data, size_t nq,
				 const float *qx, const float *qy, const float *qz, const float *metric,
				 const float *cutoff, const float *min_d2, float *out, dp_error *err)
{
	dp_cl_grid_storage gs;
	dp_cl_arg args[4 + DP_CL_GRID_NARGS + 3];
	size_t qbytes = nq * sizeof(float);
	args[0] = DP_CL_IN(qx, qbytes);
	args[1] = DP_CL_IN(qy, qbytes);
	args[2] = DP_CL_IN(qz, qbytes);
	args[3] = DP_CL_IN(metric, 9 * qbytes);
	dp_cl_grid_args(data, &gs, args + 4);
	size_t k = 4 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_VALUE(*cutoff);
	args[k++] = DP_CL_VALUE(*min_d2);
	args[k++] = DP_CL_OUT(out, 3 * qbytes);
	return dp_cl_launch(&ctx->cl, kernel, nq, args, k, err);
}

dp_status dp_op_skeleton_median(dp_context *ctx, const dp_skeleton_median_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_skeleton_median(a);
		return DP_OK;
	}
	return launch_weighted(ctx, "skeleton_median", a->data, a->nq, a->qx, a->qy, a->qz, a->metric, &a->cutoff,
			       &a->min_d2, a->median, err);
}

dp_status dp_op_skeleton_repulse(dp_context *ctx, const dp_skeleton_repulse_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_skeleton_repulse(a);
		return DP_OK;
	}
	return launch_weighted(ctx, "skeleton_repulse", a->data, a->nq, a->qx, a->qy, a->qz, a->metric,
			       &a->cutoff, &a->min_d2, a->repulse, err);
}
