#include "backend/surface_ops.h"

dp_status dp_op_surface_data(dp_context *ctx, const dp_surface_data_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->input, a->nq, a->px, a->py, a->pz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_surface_data(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[7 + DP_CL_GRID_NARGS + 8];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->px, qbytes);
	args[1] = DP_CL_IN(a->py, qbytes);
	args[2] = DP_CL_IN(a->pz, qbytes);
	args[3] = DP_CL_IN(a->sx, qbytes);
	args[4] = DP_CL_IN(a->sy, qbytes);
	args[5] = DP_CL_IN(a->sz, qbytes);
	args[6] = DP_CL_IN(a->depth, qbytes);
	dp_cl_grid_args(a->input, &gs, args + 7);
	size_t k = 7 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->r);
	args[k++] = DP_CL_VALUE(a->min_d2);
	args[k++] = DP_CL_OUT(a->eta, qbytes);
	args[k++] = DP_CL_OUT(a->sum_alpha, qbytes);
	args[k++] = DP_CL_OUT(a->ox, qbytes);
	args[k++] = DP_CL_OUT(a->oy, qbytes);
	args[k++] = DP_CL_OUT(a->oz, qbytes);
	return dp_cl_launch(&ctx->cl, "surface_data", a->nq, args, k, err);
}

dp_status dp_op_surface_neighbour(dp_context *ctx, const dp_surface_neighbour_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->surface, a->nq, a->px, a->py, a->pz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_surface_neighbour(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[7 + DP_CL_GRID_NARGS + 19];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->px, qbytes);
	args[1] = DP_CL_IN(a->py, qbytes);
	args[2] = DP_CL_IN(a->pz, qbytes);
	args[3] = DP_CL_IN(a->nx, qbytes);
	args[4] = DP_CL_IN(a->ny, qbytes);
	args[5] = DP_CL_IN(a->nz, qbytes);
	args[6] = DP_CL_IN(a->len, qbytes);
	dp_cl_grid_args(a->surface, &gs, args + 7);
	size_t k = 7 + DP_CL_GRID_NARGS;
	size_t gbytes = a->surface->n * sizeof(float);
	args[k++] = DP_CL_IN(a->glen, gbytes);
	args[k++] = DP_CL_IN(a->gnx, gbytes);
	args[k++] = DP_CL_IN(a->gny, gbytes);
	args[k++] = DP_CL_IN(a->gnz, gbytes);
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->r);
	args[k++] = DP_CL_VALUE(a->min_d2);
	args[k++] = DP_CL_VALUE(a->tfloor);
	args[k++] = DP_CL_VALUE(a->side_cos);
	args[k++] = DP_CL_OUT(a->L, qbytes);
	args[k++] = DP_CL_OUT(a->var, qbytes);
	args[k++] = DP_CL_OUT(a->rx, qbytes);
	args[k++] = DP_CL_OUT(a->ry, qbytes);
	args[k++] = DP_CL_OUT(a->rz, qbytes);
	args[k++] = DP_CL_OUT(a->nn, qbytes);
	args[k++] = DP_CL_OUT(a->mx, qbytes);
	args[k++] = DP_CL_OUT(a->my, qbytes);
	args[k++] = DP_CL_OUT(a->mz, qbytes);
	return dp_cl_launch(&ctx->cl, "surface_neighbour", a->nq, args, k, err);
}

dp_status dp_op_surface_covariance(dp_context *ctx, const dp_surface_covariance_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->surface, a->nq, a->px, a->py, a->pz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_surface_covariance(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[6 + DP_CL_GRID_NARGS + 7];
	size_t qbytes = a->nq * sizeof(float), gbytes = a->surface->n * sizeof(float);
	args[0] = DP_CL_IN(a->px, qbytes);
	args[1] = DP_CL_IN(a->py, qbytes);
	args[2] = DP_CL_IN(a->pz, qbytes);
	args[3] = DP_CL_IN(a->nx, qbytes);
	args[4] = DP_CL_IN(a->ny, qbytes);
	args[5] = DP_CL_IN(a->nz, qbytes);
	dp_cl_grid_args(a->surface, &gs, args + 6);
	size_t k = 6 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_IN(a->gnx, gbytes);
	args[k++] = DP_CL_IN(a->gny, gbytes);
	args[k++] = DP_CL_IN(a->gnz, gbytes);
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->r);
	args[k++] = DP_CL_VALUE(a->side_cos);
	args[k++] = DP_CL_OUT(a->cov, 6 * qbytes);
	return dp_cl_launch(&ctx->cl, "surface_covariance", a->nq, args, k, err);
}

dp_status dp_op_surface_reattach(dp_context *ctx, const dp_surface_reattach_args *a, dp_error *err)
{
	ctx->pair_evaluations += dp_grid_candidates(a->skeleton, a->nq, a->qx, a->qy, a->qz);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_surface_reattach(a);
		return DP_OK;
	}
	dp_cl_grid_storage gs;
	dp_cl_arg args[9 + DP_CL_GRID_NARGS + 4];
	size_t qbytes = a->nq * sizeof(float);
	args[0] = DP_CL_IN(a->qx, qbytes);
	args[1] = DP_CL_IN(a->qy, qbytes);
	args[2] = DP_CL_IN(a->qz, qbytes);
	args[3] = DP_CL_IN(a->px, qbytes);
	args[4] = DP_CL_IN(a->py, qbytes);
	args[5] = DP_CL_IN(a->pz, qbytes);
	args[6] = DP_CL_IN(a->nx, qbytes);
	args[7] = DP_CL_IN(a->ny, qbytes);
	args[8] = DP_CL_IN(a->nz, qbytes);
	dp_cl_grid_args(a->skeleton, &gs, args + 9);
	size_t k = 9 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_VALUE(a->radius);
	args[k++] = DP_CL_VALUE(a->r);
	args[k++] = DP_CL_OUT(a->best, a->nq * sizeof(int32_t));
	args[k++] = DP_CL_OUT(a->dist2, qbytes);
	return dp_cl_launch(&ctx->cl, "surface_reattach", a->nq, args, k, err);
}
