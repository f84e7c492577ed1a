#include "backend/sink_ops.h"

/* Argument arrays below are sized for the largest kernel (sink_smooth). */
#define SINK_MAX_ARGS (9 + DP_CL_GRID_NARGS + 6 + 3 + 4)

dp_status dp_op_sink_front(dp_context *ctx, const dp_sink_front_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->inner, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_sink_front(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[SINK_MAX_ARGS];
	size_t qbytes = a->nq * sizeof(float), gbytes = a->inner->n * sizeof(float), k = 0;
	const float *queries[9] = {a->qx, a->qy, a->qz, a->px, a->py, a->pz, a->qnx, a->qny, a->qnz};
	for (int q = 0; q < 9; q++)
		args[k++] = DP_CL_IN(queries[q], qbytes);
	dp_cl_grid_args(a->inner, &gs, args + k);
	k += DP_CL_GRID_NARGS;
	const float *attrs[6] = {a->sx, a->sy, a->sz, a->nx, a->ny, a->nz};
	for (int q = 0; q < 6; q++)
		args[k++] = DP_CL_IN(attrs[q], gbytes);
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->far_d2);
	args[k++] = DP_CL_OUT(a->min_dot, qbytes);
	return dp_cl_launch(&ctx->cl, "sink_front", a->nq, args, k, err);
}

dp_status dp_op_sink_step(dp_context *ctx, const dp_sink_step_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->surface, a->nq, a->px, a->py, a->pz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_sink_step(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[SINK_MAX_ARGS];
	size_t qbytes = a->nq * sizeof(float), k = 0;
	args[k++] = DP_CL_IN(a->px, qbytes);
	args[k++] = DP_CL_IN(a->py, qbytes);
	args[k++] = DP_CL_IN(a->pz, qbytes);
	dp_cl_grid_args(a->surface, &gs, args + k);
	k += DP_CL_GRID_NARGS;
	args[k++] = DP_CL_IN(a->move, a->surface->n * sizeof(float));
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_OUT(a->mean, qbytes);
	return dp_cl_launch(&ctx->cl, "sink_step", a->nq, args, k, err);
}

dp_status dp_op_sink_smooth(dp_context *ctx, const dp_sink_smooth_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->surface, a->nq, a->px, a->py, a->pz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_sink_smooth(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[SINK_MAX_ARGS];
	size_t qbytes = a->nq * sizeof(float), gbytes = a->surface->n * sizeof(float), k = 0;
	const float *queries[9] = {a->px, a->py, a->pz, a->qnx, a->qny, a->qnz, a->qx, a->qy, a->qz};
	for (int q = 0; q < 9; q++)
		args[k++] = DP_CL_IN(queries[q], qbytes);
	dp_cl_grid_args(a->surface, &gs, args + k);
	k += DP_CL_GRID_NARGS;
	const float *attrs[6] = {a->nx, a->ny, a->nz, a->ix, a->iy, a->iz};
	for (int q = 0; q < 6; q++)
		args[k++] = DP_CL_IN(attrs[q], gbytes);
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->inv_r2);
	args[k++] = DP_CL_VALUE(a->phi_scale);
	args[k++] = DP_CL_OUT(a->out_x, qbytes);
	args[k++] = DP_CL_OUT(a->out_y, qbytes);
	args[k++] = DP_CL_OUT(a->out_z, qbytes);
	args[k++] = DP_CL_OUT(a->out_w, qbytes);
	return dp_cl_launch(&ctx->cl, "sink_smooth", a->nq, args, k, err);
}
