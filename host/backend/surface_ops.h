/* The surface consolidation operators (DESIGN 4.3). Each is one pass over query
 * points summing over grid neighbours; each exists as a scalar reference
 * (host/ref/surface_ref.c, the specification) and an OpenCL kernel
 * (kernels/surface.cl), and dp_op_* runs the one the context chooses.
 * θ(d) = exp(-(d/r)²) throughout; lengths are divided by r before they enter a
 * weight, so the balance of the terms does not depend on the units of the
 * input. Per-neighbour attributes are in the grid's sorted order
 * (dp_grid_gather); per-query arrays are in the caller's order. */
#ifndef DP_BACKEND_SURFACE_OPS_H
#define DP_BACKEND_SURFACE_OPS_H

#include "backend/context.h"
#include "grid/grid.h"

/* The data term over the input C. For each query p_i, over the input points
 * c_j of the grid with d = |p_i - c_j| < radius and on the query's own side,
 * (c_j - p_i)·s_i + depth_i > 0 (the set C_i; with s_i the dpoint orientation
 * m_i and depth_i its length, input behind the inner end q_i, the far side of
 * a part thinner than the radius, does not count; s = 0, depth > 0 admits all):
 *   eta[i]       = 1 + Σ θ(d)                 every pair (η, input support)
 *   sum_alpha[i] = Σ α_ij, α_ij = θ(d)/(d/r)  pairs with d² >= min_d2 only
 *   o[i]         = Σ α_ij (c_j - p_i) / Σ α_ij, or 0 when Σ α_ij = 0:
 *                  the weighted L1-median step c̄_i - p_i, as an offset so
 *                  that float precision does not depend on where p_i is. */
typedef struct dp_surface_data_args {
	const dp_grid *input;
	size_t nq;
	const float *px, *py, *pz, *sx, *sy, *sz, *depth;
	float radius, r, min_d2;
	float *eta, *sum_alpha, *ox, *oy, *oz;
} dp_surface_data_args;

void dp_ref_surface_data(const dp_surface_data_args *a);
dp_status dp_op_surface_data(dp_context *ctx, const dp_surface_data_args *a, dp_error *err);

/* The surface neighbourhood P_i. For each query p_i with unit normal n_i and
 * dpoint length len_i, over the surface points p_k of the grid (dpoint
 * lengths glen[k] and normals gn[k], sorted order) with d = |p_i - p_k| <
 * radius and n_i·gn_k > side_cos (same-sided: -2 admits every neighbour, 0
 * drops the far side of a thin part, whose normals face away):
 *   L[i]   = Σ θ(d) glen_k / Σ θ(d)                     every pair (P_i holds p_i)
 *   var[i] = variance of {glen_k / r} over the same pairs (unweighted, in r²;
 *            summed as differences to len_i so the float sums stay exact)
 *   rep[i] = Σ β̂ T_i(p_i - p_k) / Σ β̂, T_i = I - n_i n_iᵀ,
 *            β̂ = θ(d) / max(|T_i(p_i - p_k)|/r, tfloor)⁵,  pairs with d² >= min_d2;
 *            0 when there is none. tfloor keeps β̂ finite for a neighbour
 *            straight above or below p_i.
 *   nn[i]  = the smallest d over pairs with d² >= min_d2, radius when none.
 *   mem[i] = Σ θ(d) (p_k - p_i) / Σ θ(d): offset of the θ-weighted centroid of
 *            P_i (the membrane pull of the minimal-volume prior)   every pair */
typedef struct dp_surface_neighbour_args {
	const dp_grid *surface;
	const float *glen, *gnx, *gny, *gnz;
	size_t nq;
	const float *px, *py, *pz, *nx, *ny, *nz, *len;
	float radius, r, min_d2, tfloor, side_cos;
	float *L, *var, *rx, *ry, *rz, *nn, *mx, *my, *mz;
} dp_surface_neighbour_args;

void dp_ref_surface_neighbour(const dp_surface_neighbour_args *a);
dp_status dp_op_surface_neighbour(dp_context *ctx, const dp_surface_neighbour_args *a, dp_error *err);

/* The covariance of the surface points around each query p_i for its PCA
 * normal: over the grid points p_k with d = |p_i - p_k| < radius and
 * n_i·gn_k > side_cos as above (p_i itself included, uniform weights), with
 * offsets e_k = (p_k - p_i)/r,
 *   cov[6*i + ...] = Σ e eᵀ/N - ē ēᵀ as (xx, xy, xz, yy, yz, zz), in r²;
 * all zero when N = 0. */
typedef struct dp_surface_covariance_args {
	const dp_grid *surface;
	const float *gnx, *gny, *gnz;
	size_t nq;
	const float *px, *py, *pz, *nx, *ny, *nz;
	float radius, r, side_cos;
	float *cov;
} dp_surface_covariance_args;

void dp_ref_surface_covariance(const dp_surface_covariance_args *a);
dp_status dp_op_surface_covariance(dp_context *ctx, const dp_surface_covariance_args *a, dp_error *err);

/* Re-attachment of inner ends. For each query i (inner end q_i, surface point
 * p_i, unit normal n_i), over the skeleton points s_k of the grid with
 * |s_k - q_i| < radius that lie behind p_i (depth t = n_i·(p_i - s_k) > 0):
 *   best[i]  = the sorted grid index k with the smallest squared distance
 *              from s_k to the line through p_i along n_i, |(p_i - s_k) - t n_i|²
 *              (the first in grid order on ties), or -1 when there is none;
 *   dist2[i] = that squared distance divided by r² (0 when best is -1). */
typedef struct dp_surface_reattach_args {
	const dp_grid *skeleton;
	size_t nq;
	const float *qx, *qy, *qz, *px, *py, *pz, *nx, *ny, *nz;
	float radius, r;
	int32_t *best;
	float *dist2;
} dp_surface_reattach_args;

void dp_ref_surface_reattach(const dp_surface_reattach_args *a);
dp_status dp_op_surface_reattach(dp_context *ctx, const dp_surface_reattach_args *a, dp_error *err);

#endif
