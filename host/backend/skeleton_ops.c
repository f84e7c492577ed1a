#include "backend/skeleton_ops.h"

#include "core/common.h"

#include <math.h>

/* Relative slack of a reach over the exact half-extent. The metric's rows are
 * orthogonal only to float rounding and the device divides by the cell with
 * unsafe math (about 1e-6 relative together); cell coordinates of queries and
 * points round by an ulp of their distance to the grid's origin. 1e-3 keeps a
 * point within reach on the scanned side of every rounded cell border, and
 * adds a layer of cells for well under 1% of the queries. */
#define SKELETON_REACH_SLACK 1e-3

float dp_skeleton_reach(size_t nq, const float *metric, float cutoff, float *reach)
{
	float longest = 0.0f;
	for (size_t i = 0; i < nq; i++) {
		const float *m = metric + 9 * i;
		double a[3][3];
		for (int r = 0; r < 3; r++)
			for (int c = 0; c < 3; c++)
				a[r][c] = m[3 * r + c];
		/* M^-1 = adj(M) / det(M); row j of M^-1 is column j of the cofactors. */
		double cof[3][3];
		for (int r = 0; r < 3; r++)
			for (int c = 0; c < 3; c++) {
				int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
				cof[r][c] = a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1];
			}
		double det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
		for (int j = 0; j < 3; j++) {
			double len = sqrt(cof[0][j] * cof[0][j] + cof[1][j] * cof[1][j] + cof[2][j] * cof[2][j]);
			float e = (float)(cutoff * len / fabs(det) * (1.0 + SKELETON_REACH_SLACK));
			reach[3 * i + j] = e;
			longest = fmaxf(longest, e);
		}
	}
	return longest;
}

/* Every query's reach must lie within the grid's margin (see the header). */
static dp_status check_reach(const char *op, const dp_grid *g, size_t nq, const float *reach, dp_error *err)
{
	double limit = (double)g->margin * (double)g->cell;
	for (size_t k = 0; k < 3 * nq; k++)
		if (!((double)reach[k] <= limit))
			return dp_fail(err, DP_ERR_ARG,
				       "%s: query %zu reaches %g, beyond the grid's margin of %d cells of %g", op,
				       k / 3, (double)reach[k], g->margin, (double)g->cell);
	return DP_OK;
}

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
				 const float *reach, const float *cutoff, const float *min_d2, float *out,
				 dp_error *err)
{
	dp_cl_grid_storage gs;
	dp_cl_arg args[5 + DP_CL_GRID_NARGS + 3];
	size_t qbytes = nq * sizeof(float);
	args[0] = DP_CL_IN(qx, qbytes);
	args[1] = DP_CL_IN(qy, qbytes);
	args[2] = DP_CL_IN(qz, qbytes);
	args[3] = DP_CL_IN(metric, 9 * qbytes);
	args[4] = DP_CL_IN(reach, 3 * qbytes);
	dp_cl_grid_args(data, &gs, args + 5);
	size_t k = 5 + DP_CL_GRID_NARGS;
	args[k++] = DP_CL_VALUE(*cutoff);
	args[k++] = DP_CL_VALUE(*min_d2);
	args[k++] = DP_CL_OUT(out, 3 * qbytes);
	return dp_cl_launch(&ctx->cl, kernel, nq, args, k, err);
}

dp_status dp_op_skeleton_median(dp_context *ctx, const dp_skeleton_median_args *a, dp_error *err)
{
	dp_status st = check_reach("skeleton_median", a->data, a->nq, a->reach, err);
	if (st != DP_OK)
		return st;
	ctx->pair_evaluations += dp_grid_candidates_reach(a->data, a->nq, a->qx, a->qy, a->qz, a->reach);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_skeleton_median(a);
		return DP_OK;
	}
	return launch_weighted(ctx, "skeleton_median", a->data, a->nq, a->qx, a->qy, a->qz, a->metric, a->reach,
			       &a->cutoff, &a->min_d2, a->median, err);
}

dp_status dp_op_skeleton_repulse(dp_context *ctx, const dp_skeleton_repulse_args *a, dp_error *err)
{
	dp_status st = check_reach("skeleton_repulse", a->data, a->nq, a->reach, err);
	if (st != DP_OK)
		return st;
	ctx->pair_evaluations += dp_grid_candidates_reach(a->data, a->nq, a->qx, a->qy, a->qz, a->reach);
	if (ctx->kind == DP_BACKEND_REF) {
		dp_ref_skeleton_repulse(a);
		return DP_OK;
	}
	return launch_weighted(ctx, "skeleton_repulse", a->data, a->nq, a->qx, a->qy, a->qz, a->metric, a->reach,
			       &a->cutoff, &a->min_d2, a->repulse, err);
}
