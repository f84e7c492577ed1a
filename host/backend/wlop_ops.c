#include "backend/wlop_ops.h"

dp_status dp_op_density(dp_context *ctx, const dp_density_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_density(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[3 + DP_CL_GRID_NARGS + 5];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->qx, qbytes);
	args[1] = DP_CL_IN(a->qy, qbytes);
	args[2] = DP_CL_IN(a->qz, qbytes);
	dp_cl_grid_args(a->data, &gs, args + 3);
	size_t k = 3 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_VALUE(a->h);
	args[k++] = DP_CL_VALUE(a->theta_k);
	args[k++] = DP_CL_VALUE(a->min_d2);
	args[k++] = DP_CL_VALUE(a->sqrt_density);
	args[k++] = DP_CL_OUT(a->out, qbytes);
	return dp_cl_launch(&ctx->cl, "wlop_density", a->nq, args, k, err);
}

dp_status dp_op_attraction(dp_context *ctx, const dp_attraction_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_attraction(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[3 + DP_CL_GRID_NARGS + 9];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->qx, qbytes);
	args[1] = DP_CL_IN(a->qy, qbytes);
	args[2] = DP_CL_IN(a->qz, qbytes);
	dp_cl_grid_args(a->data, &gs, args + 3);
	size_t k = 3 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_IN(a->inv_v, a->data->n * sizeof(float));
	args[k++] = DP_CL_VALUE(a->h);
	args[k++] = DP_CL_VALUE(a->theta_k);
	args[k++] = DP_CL_VALUE(a->min_d2);
	args[k++] = DP_CL_VALUE(a->gaussian);
	args[k++] = DP_CL_OUT(a->out_x, qbytes);
	args[k++] = DP_CL_OUT(a->out_y, qbytes);
	args[k++] = DP_CL_OUT(a->out_z, qbytes);
	args[k++] = DP_CL_OUT(a->out_w, qbytes);
	return dp_cl_launch(&ctx->cl, "wlop_attraction", a->nq, args, k, err);
}

dp_status dp_op_repulsion(dp_context *ctx, const dp_repulsion_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->data, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_repulsion(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[3 + DP_CL_GRID_NARGS + 8];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->qx, qbytes);
	args[1] = DP_CL_IN(a->qy, qbytes);
	args[2] = DP_CL_IN(a->qz, qbytes);
	dp_cl_grid_args(a->data, &gs, args + 3);
	size_t k = 3 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_IN(a->w, a->data->n * sizeof(float));
	args[k++] = DP_CL_VALUE(a->h);
	args[k++] = DP_CL_VALUE(a->theta_k);
	args[k++] = DP_CL_VALUE(a->min_d2);
	args[k++] = DP_CL_OUT(a->out_x, qbytes);
	args[k++] = DP_CL_OUT(a->out_y, qbytes);
	args[k++] = DP_CL_OUT(a->out_z, qbytes);
	args[k++] = DP_CL_OUT(a->out_w, qbytes);
	return dp_cl_launch(&ctx->cl, "wlop_repulsion", a->nq, args, k, err);
}
