/* The WLOP operators (DESIGN 4.0). Each is one pass over query points that
 * sums over grid neighbours within h; each exists as a scalar reference
 * (host/ref/wlop_ref.c, the specification) and an OpenCL kernel
 * (kernels/wlop.cl), and dp_op_* runs the one the context chooses.
 * θ(d) = exp(-theta_k d²/h²); pairs with d² < min_d2 are skipped. Per-neighbour
 * attributes (inv_v, w) are in the data grid's sorted order. */
#ifndef DP_BACKEND_WLOP_OPS_H
#define DP_BACKEND_WLOP_OPS_H

#include "backend/context.h"
#include "grid/grid.h"

/* out[i] = 1 + Σ_{d<h} θ(|q_i - p|) over the grid's points p; its square root
 * when sqrt_density. The input density v_j and the sample density w_i. The
 * skipped pairs are the query itself (and its exact duplicates). */
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

/* The data term at each query x_i (a sample), over the grid's points c_j (the
 * input) with d = |c_j - x_i| < h:
 *   out_x,y,z[i] = Σ_j (c_j - x_i) α_ij inv_v[j],   out_w[i] = Σ_j α_ij inv_v[j],
 * α = θ(d)/d (the L1 weight) or θ(d) when gaussian; inv_v[j] = 1/v_j. The
 * stage adds out_xyz/out_w to x_i: offsets rather than Σ c_j α/v keep float
 * precision when coordinates are large compared with h. Pairs with d² < min_d2
 * are skipped: the L1 weight needs min_d2 > 0 because 1/d is infinite there
 * (an initial sample sits on its input point); the Gaussian weight is finite
 * everywhere and the stage passes min_d2 = 0 for it. */
typedef struct dp_attraction_args {
	const dp_grid *data;
	const float *inv_v;
	size_t nq;
	const float *qx, *qy, *qz;
	float h, theta_k, min_d2;
	int gaussian;
	float *out_x, *out_y, *out_z, *out_w;
} dp_attraction_args;

void dp_ref_attraction(const dp_attraction_args *a);
dp_status dp_op_attraction(dp_context *ctx, const dp_attraction_args *a, dp_error *err);

/* The repulsion term at each query x_i, over the grid's points x_i' (the
 * samples) with d = |x_i - x_i'| < h:
 *   out_x,y,z[i] = Σ_i' (x_i - x_i') w[i'] β,   out_w[i] = Σ_i' w[i'] β,
 * β = θ(d)/d (Huang et al. 2009: θ(r)|η'(r)|/r with η(r) = -r). Pairs with
 * d² < min_d2 are skipped: the query itself, and 1/d is infinite there. */
typedef struct dp_repulsion_args {
	const dp_grid *data;
	const float *w;
	size_t nq;
	const float *qx, *qy, *qz;
	float h, theta_k, min_d2;
	float *out_x, *out_y, *out_z, *out_w;
} dp_repulsion_args;

void dp_ref_repulsion(const dp_repulsion_args *a);
dp_status dp_op_repulsion(dp_context *ctx, const dp_repulsion_args *a, dp_error *err);

#endif
