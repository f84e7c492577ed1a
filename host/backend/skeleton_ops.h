/* The meso-skeleton operators (DESIGN 4.2). Each is one pass over query points
 * (the inner points q_i) summing over the points of one grid; each exists as a
 * scalar reference (host/ref/skeleton_ref.c, the specification) and an OpenCL
 * kernel (kernels/skeleton.cl), and dp_op_* runs the one the context chooses.
 *
 * Per-query frames and metrics are interleaved arrays: frames[9*i + 3*m + c]
 * is component c of axis v_i^m; a 3-vector output out[3*i + c]. Per-neighbour
 * attributes (normals) are in the grid's sorted order (dp_grid_gather). */
#ifndef DP_BACKEND_SKELETON_OPS_H
#define DP_BACKEND_SKELETON_OPS_H

#include "backend/context.h"
#include "grid/grid.h"

/* PCA input of Q_i: over the grid's points p with |p - q_i| < radius (q_i
 * itself and duplicates included: there is no 1/d weight), count[i] = their
 * number and cov[6*i + {0..5}] = {xx, xy, xz, yy, yz, zz} of their covariance
 * (normalised by the count), accumulated relative to q_i so float keeps the
 * digits. An empty neighbourhood gives count 0 and a zero covariance. The grid
 * cell must be >= radius. */
typedef struct dp_skeleton_cov_args {
	const dp_grid *data;
	size_t nq;
	const float *qx, *qy, *qz;
	float radius;
	float *count; /* nq */
	float *cov;   /* 6*nq */
} dp_skeleton_cov_args;

void dp_ref_skeleton_cov(const dp_skeleton_cov_args *a);
dp_status dp_op_skeleton_cov(dp_context *ctx, const dp_skeleton_cov_args *a, dp_error *err);

/* Semi-axis lengths (dimensionless, in units of r):
 * semi[3*i + m] = 1 / (mean_{p: |p - q_i| < radius} |n_p · v_i^m| + eps)
 * over the same neighbourhood as dp_skeleton_cov (self included). An empty
 * neighbourhood counts as mean 0, so semi = 1/eps: nothing constrains it. */
typedef struct dp_skeleton_semiaxes_args {
	const dp_grid *data;
	const float *nx, *ny, *nz; /* normals of the grid's points, sorted order */
	size_t nq;
	const float *qx, *qy, *qz;
	const float *frames;       /* 9*nq unit axes v_i^m */
	float radius, eps;
	float *semi;               /* 3*nq */
} dp_skeleton_semiaxes_args;

void dp_ref_skeleton_semiaxes(const dp_skeleton_semiaxes_args *a);
dp_status dp_op_skeleton_semiaxes(dp_context *ctx, const dp_skeleton_semiaxes_args *a, dp_error *err);

/* The ellipsoid distance in units of r is u = |A_i^T (q_i - x)| with metric
 * rows metric[9*i + 3*m + c] = v_i^m_c / (l_i^m r), and ϑ = exp(-u²). Both
 * sums below take the grid's points x with u <= cutoff and |q_i - x|² >=
 * min_d2: the second test skips q_i itself and exact duplicates, where 1/d and
 * 1/u⁵ are infinite.
 *
 * Reaches vary a lot between queries (l from about 1 to 1/eps), so each query
 * scans only the grid cells that its ellipsoid's axis-aligned bounding box
 * touches: reach[3*i + a] >= the box's half-extent along axis a
 * (dp_skeleton_reach), and the grid is built with a margin that covers the
 * longest reach (dp_grid_build_margin, margin * cell >= every reach; the
 * dispatchers check it). Any cell size works; the reach only bounds the scan,
 * the sums are those above. */

/* Half-extents of each query's ellipsoid {x : u <= cutoff} along x, y, z:
 * reach[3*i + a] = cutoff · |row a of M_i^-1| for the 3x3 metric M_i, with a
 * little slack for float rounding (computed in double). Returns the longest
 * (ignoring NaN); a singular or non-finite metric gives an infinite or NaN
 * reach, which the dispatchers reject. */
float dp_skeleton_reach(size_t nq, const float *metric, float cutoff, float *reach);

/* Anisotropic L1-median step over the anchors H:
 * median[3*i + c] = Σ α_k h_k / Σ α_k, α_k = ϑ(q_i, h_k) / |q_i - h_k|;
 * q_i itself when no anchor is within reach (the point stays put). */
typedef struct dp_skeleton_median_args {
	const dp_grid *data;  /* anchors */
	size_t nq;
	const float *qx, *qy, *qz;
	const float *metric;  /* 9*nq */
	const float *reach;   /* 3*nq, dp_skeleton_reach */
	float cutoff, min_d2;
	float *median;        /* 3*nq */
} dp_skeleton_median_args;

void dp_ref_skeleton_median(const dp_skeleton_median_args *a);
dp_status dp_op_skeleton_median(dp_context *ctx, const dp_skeleton_median_args *a, dp_error *err);

/* Anisotropic repulsion over the inner points Q (before projection):
 * repulse[3*i + c] = Σ β (q_i - q') / Σ β, β = ϑ(q_i, q') / u(q_i, q')⁵;
 * zero when no inner point is within reach. */
typedef struct dp_skeleton_repulse_args {
	const dp_grid *data;  /* inner points */
	size_t nq;
	const float *qx, *qy, *qz;
	const float *metric;  /* 9*nq */
	const float *reach;   /* 3*nq, dp_skeleton_reach */
	float cutoff, min_d2;
	float *repulse;       /* 3*nq */
} dp_skeleton_repulse_args;

void dp_ref_skeleton_repulse(const dp_skeleton_repulse_args *a);
dp_status dp_op_skeleton_repulse(dp_context *ctx, const dp_skeleton_repulse_args *a, dp_error *err);

#endif
