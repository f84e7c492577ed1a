/* The WLOP operators (DESIGN 4.0). Each is one pass over query points that
 * sums over grid neighbours within h; each exists as a scalar reference
 * (host/ref/wlop_ref.c, the specification) and an OpenCL kernel
 * (kernels/wlop.cl), and dp_op_* runs the one the context chooses.
 * θ(d) = exp(-theta_k d²/h²); pairs with d² < min_d2 are skipped. */
#ifndef DP_BACKEND_WLOP_OPS_H
#define DP_BACKEND_WLOP_OPS_H

#include "backend/context.h"
#include "grid/grid.h"

/* out[i] = 1 + Σ_{d<h} θ(|q_i - p|) over the grid's points p; its square root
 * when sqrt_density. The input density v_j and the sample density w_i. */
typedef struct dp_density_args {
	const dp_grid *data;
	size_t nq;
	const float *qx, *qy, *qz;
	float h, theta_k, min_d2;
	int sqrt_density;
	float *out;
} dp_density_args;

void dp_ref_density(const dp_density_args *a);
dp_status dp_op_density(dp_context *ctx, const dp_density_args *a, dp_error *err);

#endif
