/* The sinking operators (DESIGN 4.1). Each is one pass over query points (the
 * unsettled dpoints) summing over the points of one grid; each exists as a
 * scalar reference (host/ref/sink_ref.c, the specification) and an OpenCL
 * kernel (kernels/sink.cl), and dp_op_* runs the one the context chooses.
 * Per-neighbour attributes are in the grid's sorted order (dp_grid_gather).
 * No pair is skipped for being too close: none of these sums has a 1/d
 * weight, and a query's own pair either belongs in the sum (the static
 * neighbourhood P_i contains p_i) or is rejected by the sum's own test. */
#ifndef DP_BACKEND_SINK_OPS_H
#define DP_BACKEND_SINK_OPS_H

#include "backend/context.h"
#include "grid/grid.h"

/* What dp_sink_front writes when no neighbour qualifies: larger than any dot
 * product of unit normals, so it never passes a settle test cos ω < 1. */
#define DP_SINK_NO_FRONT 2.0f

/* The settle test's evidence (Eq. 2 as DESIGN 4.1 reads it). The grid holds the
 * inner points q_i' (all of them, settled or not); sx..nz are the surface
 * point p_i' and normal n_i' of each, in the grid's order. For query i:
 *   min_dot[i] = min n_i · n_i' over i' with |q_i - q_i'| < radius and
 *                |p_i - p_i'|² > far_d2 (an opposing front, not a crease),
 * or DP_SINK_NO_FRONT when there is none. The query itself and duplicates of
 * its surface point fail the far test. The grid cell must be >= radius. */
typedef struct dp_sink_front_args {
	const dp_grid *inner;
	const float *sx, *sy, *sz;    /* surface points of the grid's points */
	const float *nx, *ny, *nz;    /* their normals */
	size_t nq;
	const float *qx, *qy, *qz;    /* query inner points */
	const float *px, *py, *pz;    /* their surface points */
	const float *qnx, *qny, *qnz; /* their normals */
	float radius, far_d2;
	float *min_dot;               /* nq */
} dp_sink_front_args;

void dp_ref_sink_front(const dp_sink_front_args *a);
dp_status dp_op_sink_front(dp_context *ctx, const dp_sink_front_args *a, dp_error *err);

/* The adaptive step: the grid holds the surface points p_i' and `move` the
 * distance their inner points moved in the previous iteration (0 for settled
 * ones), in the grid's order. For query i (a surface point p_i):
 *   mean[i] = mean of move[i'] over i' with |p_i - p_i'| < radius (P_i, p_i
 *             itself included), or 0 when that set is empty.
 * The grid cell must be >= radius. */
typedef struct dp_sink_step_args {
	const dp_grid *surface;
	const float *move;
	size_t nq;
	const float *px, *py, *pz;
	float radius;
	float *mean;                  /* nq */
} dp_sink_step_args;

void dp_ref_sink_step(const dp_sink_step_args *a);
dp_status dp_op_sink_step(dp_context *ctx, const dp_sink_step_args *a, dp_error *err);

/* Cross-bilateral smoothing sums (Eq. 3). The grid holds the surface points
 * p_i'; nx..nz their normals and ix..iz their inner points q_i' (after this
 * iteration's sinking step), in the grid's order. For query i, over i' with
 * |p_i - p_i'| < radius (P_i, i itself included):
 *   w    = θ(|p_i - p_i'|) φ(n_i, n_i'),
 *   θ(d) = exp(-d² inv_r2),  φ = exp(-((1 - n_i·n_i') phi_scale)²),
 *   out_x,y,z[i] = Σ w (q_i' - q_i),   out_w[i] = Σ w,
 * with inv_r2 = 1/r² and phi_scale = 1/(1 - cos ω). The stage adds
 * out_xyz/out_w to q_i: offsets rather than Σ w q_i' keep float precision
 * when coordinates are large compared with r. */
typedef struct dp_sink_smooth_args {
	const dp_grid *surface;
	const float *nx, *ny, *nz;    /* normals of the grid's points */
	const float *ix, *iy, *iz;    /* inner points of the grid's points */
	size_t nq;
	const float *px, *py, *pz;    /* query surface points */
	const float *qnx, *qny, *qnz; /* their normals */
	const float *qx, *qy, *qz;    /* their inner points */
	float radius, inv_r2, phi_scale;
	float *out_x, *out_y, *out_z, *out_w; /* nq each */
} dp_sink_smooth_args;

void dp_ref_sink_smooth(const dp_sink_smooth_args *a);
dp_status dp_op_sink_smooth(dp_context *ctx, const dp_sink_smooth_args *a, dp_error *err);

#endif
