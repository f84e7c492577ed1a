/* Every neighbour operator, declared once (DESIGN §3). An operator is one
 * pass over query points summing over the points of one grid; it exists as a
 * scalar reference (host/ref/, the specification: dp_ref_<op>) and an OpenCL
 * kernel (kernels/), and dp_op_<op> (backend/ops.h) runs the one the context
 * chooses. From the rows below come the argument struct dp_<op>_args, the
 * reference's declaration, the kernel launch and the check, when the program
 * is built, that the kernel's argument list is the row's.
 *
 * A row lists its fields in the kernel's argument order (after the item count
 * n), each as F(kind, type, name, width):
 *   POS    query coordinate array (nq), x, y then z: where the grid is scanned
 *   QUERY  per-query input array, width values per query
 *   REACH  per-query scan reach along x, y, z (width 3): the query scans the
 *          cells its reach touches instead of the 3x3x3 block (kernels/grid.cl
 *          GRID_PAIRS_REACH), and every reach must lie within the grid margin
 *   GRID   the grid scanned (kernels/grid.cl GRID_ARGS); before any ATTR
 *   ATTR   per-grid-point input array in the grid's sorted order
 *          (dp_grid_gather), width values per point
 *   CELLS  an int passed by value: the query scans this many cells on each
 *          side on every axis instead of one (GRID_PAIRS_REACH), for grids
 *          of several cells per radius; it must lie in 1..the grid's margin
 *   PARAM  a scalar passed by value
 *   RADIUS a PARAM that bounds the sum: its pairs are those with d < radius
 *          or, in a row with a METRIC, u = |M_i (q_i - x)| <= radius; one per
 *          row (the benchmarks' true-neighbour counts, backend/neighbours.h)
 *   METRIC per-query 3x3 metric rows M_i (a QUERY of width 9)
 *   OUT    per-query output array, width values per query
 * The kernel's argument names are the field names. type is float, int or
 * int32_t (one token: the kernel's type name is derived from it).
 *
 * Adding an operator: one row here (and in DP_OPERATORS), one kernel, one
 * dp_ref_<op> in host/ref/. */
#ifndef DP_OPS_OPERATORS_H
#define DP_OPS_OPERATORS_H

#include "grid/grid.h"

#include <stddef.h>
#include <stdint.h>

/* ---- WLOP (DESIGN 4.0) ----------------------------------------------------
 * θ(d) = exp(-theta_k d²/h²); pairs with d² < min_d2 are skipped. */

/* out[i] = 1 + Σ_{d<h} θ(|q_i - p|) over the grid's points p; its square root
 * when sqrt_density. The input density v_j and the sample density w_i. The
 * skipped pairs are the query itself (and its exact duplicates). */
#define DP_OP_DENSITY(F)                                                                         \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(GRID, dp_grid, data, 1) \
	F(RADIUS, float, h, 1) F(PARAM, float, theta_k, 1) F(PARAM, float, min_d2, 1)              \
	F(PARAM, int, sqrt_density, 1) F(OUT, float, out, 1)

/* The data term at each query x_i (a sample), over the grid's points c_j (the
 * input) with d = |c_j - x_i| < h:
 *   out_x,y,z[i] = Σ_j (c_j - x_i) α_ij inv_v[j],   out_w[i] = Σ_j α_ij inv_v[j],
 * α = θ(d)/d (the L1 weight) or θ(d) when gaussian; inv_v[j] = 1/v_j. The
 * stage adds out_xyz/out_w to x_i: offsets rather than Σ c_j α/v keep float
 * precision when coordinates are large compared with h. Pairs with d² < min_d2
 * are skipped: the L1 weight needs min_d2 > 0 because 1/d is infinite there
 * (an initial sample sits on its input point); the Gaussian weight is finite
 * everywhere and the stage passes min_d2 = 0 for it. */
#define DP_OP_ATTRACTION(F)                                                                      \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(GRID, dp_grid, data, 1) \
	F(ATTR, float, inv_v, 1) F(RADIUS, float, h, 1) F(PARAM, float, theta_k, 1)                \
	F(PARAM, float, min_d2, 1) F(PARAM, int, gaussian, 1) F(OUT, float, out_x, 1)             \
	F(OUT, float, out_y, 1) F(OUT, float, out_z, 1) F(OUT, float, out_w, 1)

/* The repulsion term at each query x_i, over the grid's points x_i' (the
 * samples) with d = |x_i - x_i'| < h:
 *   out_x,y,z[i] = Σ_i' (x_i - x_i') w[i'] β,   out_w[i] = Σ_i' w[i'] β,
 * β = θ(d)/d (Huang et al. 2009: θ(r)|η'(r)|/r with η(r) = -r). Pairs with
 * d² < min_d2 are skipped: the query itself, and 1/d is infinite there. */
#define DP_OP_REPULSION(F)                                                                       \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(GRID, dp_grid, data, 1) \
	F(ATTR, float, w, 1) F(RADIUS, float, h, 1) F(PARAM, float, theta_k, 1)                    \
	F(PARAM, float, min_d2, 1) F(OUT, float, out_x, 1) F(OUT, float, out_y, 1)                \
	F(OUT, float, out_z, 1) F(OUT, float, out_w, 1)

/* ---- Sinking (DESIGN 4.1) -------------------------------------------------
 * The queries are the unsettled dpoints. No pair is skipped for being too
 * close: none of these sums has a 1/d weight, and a query's own pair either
 * belongs in the sum (the static neighbourhood P_i contains p_i) or is
 * rejected by the sum's own test. The grid cell must be >= radius. */

/* What dp_sink_front writes when no neighbour qualifies: larger than any dot
 * product of unit normals, so it never passes a settle test cos ω < 1. */
#define DP_SINK_NO_FRONT 2.0f
/* A partner whose normal is this near the opposite one (cos 135°) faces back
 * across a wall (sinking's thin-wall rule; meet.c's ball uses the same cut). */
#define DP_SINK_OPPOSITE_COS -0.70710678f

/* Whether a partner passes the settle test's far or thin-wall test (the
 * definition below): dist2 = |p_i - p_i'|², dot = n_i · n_i', behind =
 * n_i' · (p_i' - p_i). The reference and the meeting step share it; the
 * kernel spells it out in vector form. */
static inline int dp_sink_partner(float dist2, float far_d2, float dot, float behind, float wall_min)
{
	return dist2 > far_d2 || (wall_min > 0.0f && dot < DP_SINK_OPPOSITE_COS && behind > wall_min);
}

/* The settle test's evidence (Eq. 2 as DESIGN 4.1 reads it). The grid holds the
 * inner points q_i' (all of them, settled or not); sx..nz are the surface
 * point p_i' and normal n_i' of each. For query i (inner point q, surface
 * point p, normal qn):
 *   min_dot[i] = min n_i · n_i' over i' with |q_i - q_i'| < radius and
 *                either |p_i - p_i'|² > far_d2 (an opposing front, not a
 *                crease) or, when wall_min > 0, n_i · n_i' < DP_SINK_OPPOSITE_COS
 *                and n_i' · (p_i' - p_i) > wall_min (the far face of a wall,
 *                however thin, p_i behind its tangent plane),
 * or DP_SINK_NO_FRONT when there is none. The query itself and duplicates of
 * its surface point fail both tests. */
#define DP_OP_SINK_FRONT(F)                                                                       \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(QUERY, float, px, 1)     \
	F(QUERY, float, py, 1) F(QUERY, float, pz, 1) F(QUERY, float, qnx, 1)                     \
	F(QUERY, float, qny, 1) F(QUERY, float, qnz, 1) F(GRID, dp_grid, inner, 1)                \
	F(ATTR, float, sx, 1) F(ATTR, float, sy, 1) F(ATTR, float, sz, 1) F(ATTR, float, nx, 1)   \
	F(ATTR, float, ny, 1) F(ATTR, float, nz, 1) F(RADIUS, float, radius, 1)                   \
	F(PARAM, float, far_d2, 1) F(PARAM, float, wall_min, 1) F(OUT, float, min_dot, 1)

/* The adaptive step: the grid holds the surface points p_i' and `move` the
 * distance their inner points moved in the previous iteration (0 for settled
 * ones), `stop` the depth a settled point stopped at (+inf while it moves).
 * For query i (a surface point p_i whose inner point is at `depth`):
 *   mean[i] = mean of move[i'] over i' with |p_i - p_i'| < radius (P_i, p_i
 *             itself included) and stop[i'] >= depth[i] - margin, or 0 when
 *             that set is empty. */
#define DP_OP_SINK_STEP(F)                                                                        \
	F(POS, float, px, 1) F(POS, float, py, 1) F(POS, float, pz, 1) F(QUERY, float, depth, 1)  \
	F(GRID, dp_grid, surface, 1) F(ATTR, float, move, 1) F(ATTR, float, stop, 1)              \
	F(RADIUS, float, radius, 1) F(PARAM, float, margin, 1) F(OUT, float, mean, 1)

/* Cross-bilateral smoothing sums (Eq. 3). The grid holds the surface points
 * p_i'; nx..nz their normals and ix..iz their inner points q_i' (after this
 * iteration's sinking step). For query i (surface point p, normal qn, inner
 * point q), over i' with |p_i - p_i'| < radius (P_i, i itself included):
 *   w    = θ(|p_i - p_i'|) φ(n_i, n_i'),
 *   θ(d) = exp(-d² inv_r2),  φ = exp(-((1 - n_i·n_i') phi_scale)²),
 *   out_x,y,z[i] = Σ w (q_i' - q_i),   out_w[i] = Σ w,
 * with inv_r2 = 1/r² and phi_scale = 1/(1 - cos ω). The stage adds
 * out_xyz/out_w to q_i: offsets rather than Σ w q_i' keep float precision
 * when coordinates are large compared with r. */
#define DP_OP_SINK_SMOOTH(F)                                                                      \
	F(POS, float, px, 1) F(POS, float, py, 1) F(POS, float, pz, 1) F(QUERY, float, qnx, 1)    \
	F(QUERY, float, qny, 1) F(QUERY, float, qnz, 1) F(QUERY, float, qx, 1)                    \
	F(QUERY, float, qy, 1) F(QUERY, float, qz, 1) F(GRID, dp_grid, surface, 1)                \
	F(ATTR, float, nx, 1) F(ATTR, float, ny, 1) F(ATTR, float, nz, 1) F(ATTR, float, ix, 1)   \
	F(ATTR, float, iy, 1) F(ATTR, float, iz, 1) F(RADIUS, float, radius, 1)                   \
	F(PARAM, float, inv_r2, 1) F(PARAM, float, phi_scale, 1) F(OUT, float, out_x, 1)          \
	F(OUT, float, out_y, 1) F(OUT, float, out_z, 1) F(OUT, float, out_w, 1)

/* ---- Meso-skeleton (DESIGN 4.2) -------------------------------------------
 * The queries are the inner points q_i. Per-query frames and metrics are
 * interleaved: frames[9*i + 3*m + c] is component c of axis v_i^m; a 3-vector
 * output out[3*i + c]. */

/* PCA input of Q_i: over the grid's points p with |p - q_i| < radius (q_i
 * itself and duplicates included: there is no 1/d weight), count[i] = their
 * number and cov[6*i + {0..5}] = {xx, xy, xz, yy, yz, zz} of their covariance
 * (normalised by the count), accumulated relative to q_i so float keeps the
 * digits. An empty neighbourhood gives count 0 and a zero covariance. The grid
 * cell must be >= radius. */
#define DP_OP_SKELETON_COV(F)                                                                    \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(GRID, dp_grid, data, 1) \
	F(RADIUS, float, radius, 1) F(OUT, float, count, 1) F(OUT, float, cov, 6)

/* Semi-axis lengths (dimensionless, in units of r), gn the normals of the
 * grid's points:
 * semi[3*i + m] = 1 / (mean_{p: |p - q_i| < radius} |gn_p · v_i^m| + eps)
 * over the same neighbourhood as skeleton_cov (self included). An empty
 * neighbourhood counts as mean 0, so semi = 1/eps: nothing constrains it. */
#define DP_OP_SKELETON_SEMIAXES(F)                                                               \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(GRID, dp_grid, data, 1) \
	F(ATTR, float, gnx, 1) F(ATTR, float, gny, 1) F(ATTR, float, gnz, 1)                      \
	F(QUERY, float, frames, 9) F(RADIUS, float, radius, 1) F(PARAM, float, eps, 1)             \
	F(OUT, float, semi, 3)

/* The ellipsoid distance in units of r is u = |A_i^T (q_i - x)| with metric
 * rows metric[9*i + 3*m + c] = v_i^m_c / (l_i^m r), and ϑ = exp(-u²). Both
 * sums below take the grid's points x with u <= cutoff and |q_i - x|² >=
 * min_d2: the second test skips q_i itself and exact duplicates, where 1/d and
 * 1/u⁵ are infinite. Reaches vary a lot between queries (l from about 1 to
 * 1/eps), so each scans only the cells its ellipsoid's bounding box touches
 * (REACH, from dp_skeleton_reach); any cell size works. */

/* Anisotropic L1-median step over the anchors H:
 * median[3*i + c] = Σ α_k h_k / Σ α_k, α_k = ϑ(q_i, h_k) / |q_i - h_k|;
 * q_i itself when no anchor is within reach (the point stays put). */
#define DP_OP_SKELETON_MEDIAN(F)                                                                  \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(METRIC, float, metric, 9) \
	F(REACH, float, reach, 3) F(GRID, dp_grid, data, 1) F(RADIUS, float, cutoff, 1)           \
	F(PARAM, float, min_d2, 1) F(OUT, float, median, 3)

/* Anisotropic repulsion over the inner points Q (before projection):
 * repulse[3*i + c] = Σ β (q_i - q') / Σ β, β = ϑ(q_i, q') / u(q_i, q')⁵;
 * zero when no inner point is within reach. */
#define DP_OP_SKELETON_REPULSE(F)                                                                 \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(METRIC, float, metric, 9) \
	F(REACH, float, reach, 3) F(GRID, dp_grid, data, 1) F(RADIUS, float, cutoff, 1)           \
	F(PARAM, float, min_d2, 1) F(OUT, float, repulse, 3)

/* ---- Surface consolidation (DESIGN 4.3) -----------------------------------
 * θ(d) = exp(-(d/r)²) throughout; lengths are divided by r before they enter
 * a weight, so the balance of the terms does not depend on the units of the
 * input. The grid cell must be >= radius. */

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
#define DP_OP_SURFACE_DATA(F)                                                                     \
	F(POS, float, px, 1) F(POS, float, py, 1) F(POS, float, pz, 1) F(QUERY, float, sx, 1)     \
	F(QUERY, float, sy, 1) F(QUERY, float, sz, 1) F(QUERY, float, depth, 1)                   \
	F(GRID, dp_grid, input, 1) F(RADIUS, float, radius, 1) F(PARAM, float, r, 1)               \
	F(PARAM, float, min_d2, 1) F(OUT, float, eta, 1) F(OUT, float, sum_alpha, 1)              \
	F(OUT, float, ox, 1) F(OUT, float, oy, 1) F(OUT, float, oz, 1)

/* The surface neighbourhood P_i. For each query p_i with unit normal n_i and
 * dpoint length len_i, over the surface points p_k of the grid (dpoint
 * lengths glen[k] and normals gn[k]) with d = |p_i - p_k| < radius and
 * n_i·gn_k > side_cos (same-sided: -2 admits every neighbour, 0 drops the far
 * side of a thin part, whose normals face away):
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
#define DP_OP_SURFACE_NEIGHBOUR(F)                                                                \
	F(POS, float, px, 1) F(POS, float, py, 1) F(POS, float, pz, 1) F(QUERY, float, nx, 1)     \
	F(QUERY, float, ny, 1) F(QUERY, float, nz, 1) F(QUERY, float, len, 1)                     \
	F(GRID, dp_grid, surface, 1) F(ATTR, float, glen, 1) F(ATTR, float, gnx, 1)               \
	F(ATTR, float, gny, 1) F(ATTR, float, gnz, 1) F(RADIUS, float, radius, 1)                 \
	F(PARAM, float, r, 1) F(PARAM, float, min_d2, 1) F(PARAM, float, tfloor, 1)               \
	F(PARAM, float, side_cos, 1) F(OUT, float, L, 1) F(OUT, float, var, 1)                    \
	F(OUT, float, rx, 1) F(OUT, float, ry, 1) F(OUT, float, rz, 1) F(OUT, float, nn, 1)       \
	F(OUT, float, mx, 1) F(OUT, float, my, 1) F(OUT, float, mz, 1)

/* The covariance of the surface points around each query p_i for its PCA
 * normal: over the grid points p_k with d = |p_i - p_k| < radius and
 * n_i·gn_k > side_cos as above (p_i itself included, uniform weights), with
 * offsets e_k = (p_k - p_i)/r,
 *   cov[6*i + ...] = Σ e eᵀ/N - ē ēᵀ as (xx, xy, xz, yy, yz, zz), in r²;
 * all zero when N = 0. */
#define DP_OP_SURFACE_COVARIANCE(F)                                                               \
	F(POS, float, px, 1) F(POS, float, py, 1) F(POS, float, pz, 1) F(QUERY, float, nx, 1)     \
	F(QUERY, float, ny, 1) F(QUERY, float, nz, 1) F(GRID, dp_grid, surface, 1)                \
	F(ATTR, float, gnx, 1) F(ATTR, float, gny, 1) F(ATTR, float, gnz, 1)                      \
	F(RADIUS, float, radius, 1) F(PARAM, float, r, 1) F(PARAM, float, side_cos, 1)             \
	F(OUT, float, cov, 6)

/* Where the skeleton under each query lies, for the lateral smoothing of
 * inner ends (dpoints.h, end_smoothing_r). For each query p_i with unit
 * normal n_i, over the surface points p_k of the grid with d = |p_i - p_k| <
 * radius and n_i·gn_k > side_cos (same-sided as above; p_i's own grid point
 * included), with w(d) = exp(-(d/sigma)²) and gs_k the skeleton point that
 * neighbour k's inner end hangs on (grid order):
 *   wsum[i] = Σ w(d)
 *   o[i]    = Σ w(d) (gs_k - p_i) / Σ w(d), or 0 when wsum is 0: the mean of
 *             those skeleton points, as an offset from p_i. */
#define DP_OP_SURFACE_ENDS(F)                                                                     \
	F(POS, float, px, 1) F(POS, float, py, 1) F(POS, float, pz, 1) F(QUERY, float, nx, 1)     \
	F(QUERY, float, ny, 1) F(QUERY, float, nz, 1) F(GRID, dp_grid, surface, 1)                \
	F(ATTR, float, gnx, 1) F(ATTR, float, gny, 1) F(ATTR, float, gnz, 1)                      \
	F(ATTR, float, gsx, 1) F(ATTR, float, gsy, 1) F(ATTR, float, gsz, 1)                      \
	F(RADIUS, float, radius, 1) F(PARAM, float, sigma, 1) F(PARAM, float, side_cos, 1)         \
	F(OUT, float, wsum, 1) F(OUT, float, ox, 1) F(OUT, float, oy, 1) F(OUT, float, oz, 1)

/* Re-attachment of inner ends. For each query i (inner end q_i, surface point
 * p_i, unit normal n_i), over the skeleton points s_k of the grid with
 * |s_k - q_i| < radius that lie behind p_i (depth t = n_i·(p_i - s_k) > 0):
 *   best[i]  = the sorted grid index k with the smallest squared distance
 *              from s_k to the line through p_i along n_i, |(p_i - s_k) - t n_i|²
 *              (the first in grid order on ties), or -1 when there is none;
 *   dist2[i] = that squared distance divided by r² (0 when best is -1). */
#define DP_OP_SURFACE_REATTACH(F)                                                                 \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(QUERY, float, px, 1)     \
	F(QUERY, float, py, 1) F(QUERY, float, pz, 1) F(QUERY, float, nx, 1)                      \
	F(QUERY, float, ny, 1) F(QUERY, float, nz, 1) F(GRID, dp_grid, skeleton, 1)               \
	F(RADIUS, float, radius, 1) F(PARAM, float, r, 1) F(OUT, int32_t, best, 1)                 \
	F(OUT, float, dist2, 1)

/* ---- The peak (bench/bench_peak.c) ---------------------------------------
 * The bare pair loop of every kernel (kernels/peak.cl), measured to give the
 * ceiling each operator's pair rate is printed beside. Over the grid's points
 * p scanned within `reach` cells of q_i on each axis, with d = |q_i - p| <
 * radius (q_i itself included):
 *   count[i] = their number,   sum[i] = Σ exp(-d²/radius²).
 * The grid's cell times reach must cover the radius: dp_peak_grid builds such
 * a grid, cells of radius / reach. */
#define DP_OP_PEAK(F)                                                                            \
	F(POS, float, qx, 1) F(POS, float, qy, 1) F(POS, float, qz, 1) F(GRID, dp_grid, data, 1) \
	F(RADIUS, float, radius, 1) F(CELLS, int, reach, 1) F(OUT, float, count, 1)                \
	F(OUT, float, sum, 1)

/* The table: OP(operator, kernel, fields). */
#define DP_OPERATORS(OP)                                                 \
	OP(density, wlop_density, DP_OP_DENSITY)                         \
	OP(attraction, wlop_attraction, DP_OP_ATTRACTION)                \
	OP(repulsion, wlop_repulsion, DP_OP_REPULSION)                   \
	OP(sink_front, sink_front, DP_OP_SINK_FRONT)                     \
	OP(sink_step, sink_step, DP_OP_SINK_STEP)                        \
	OP(sink_smooth, sink_smooth, DP_OP_SINK_SMOOTH)                  \
	OP(skeleton_cov, skeleton_cov, DP_OP_SKELETON_COV)               \
	OP(skeleton_semiaxes, skeleton_semiaxes, DP_OP_SKELETON_SEMIAXES) \
	OP(skeleton_median, skeleton_median, DP_OP_SKELETON_MEDIAN)      \
	OP(skeleton_repulse, skeleton_repulse, DP_OP_SKELETON_REPULSE)   \
	OP(surface_data, surface_data, DP_OP_SURFACE_DATA)               \
	OP(surface_neighbour, surface_neighbour, DP_OP_SURFACE_NEIGHBOUR) \
	OP(surface_covariance, surface_covariance, DP_OP_SURFACE_COVARIANCE) \
	OP(surface_ends, surface_ends, DP_OP_SURFACE_ENDS)                 \
	OP(surface_reattach, surface_reattach, DP_OP_SURFACE_REATTACH)     \
	OP(peak, peak_pairs, DP_OP_PEAK)

/* dp_<op>_args: nq queries, then the row's fields (inputs const). */
#define DP_OP_MEMBER(kind, type, name, width) DP_OP_MEMBER_##kind(type, name)
#define DP_OP_MEMBER_POS(type, name) const type *name;
#define DP_OP_MEMBER_QUERY(type, name) const type *name;
#define DP_OP_MEMBER_REACH(type, name) const type *name;
#define DP_OP_MEMBER_GRID(type, name) const type *name;
#define DP_OP_MEMBER_ATTR(type, name) const type *name;
#define DP_OP_MEMBER_CELLS(type, name) type name;
#define DP_OP_MEMBER_PARAM(type, name) type name;
#define DP_OP_MEMBER_RADIUS(type, name) type name;
#define DP_OP_MEMBER_METRIC(type, name) const type *name;
#define DP_OP_MEMBER_OUT(type, name) type *name;
#define DP_OP_DECLARE(op, kernel, FIELDS)                  \
	typedef struct dp_##op##_args {                    \
		size_t nq;                                 \
		FIELDS(DP_OP_MEMBER)                       \
	} dp_##op##_args;                                  \
	void dp_ref_##op(const dp_##op##_args *a);
DP_OPERATORS(DP_OP_DECLARE)

/* Half-extents of each query's ellipsoid {x : u <= cutoff} along x, y, z:
 * reach[3*i + a] = cutoff · |row a of M_i^-1| for the 3x3 metric M_i, with a
 * little slack for float rounding (computed in double). Returns the longest
 * (ignoring NaN); a singular or non-finite metric gives an infinite or NaN
 * reach, which the dispatchers reject. The grid of a REACH operator is built
 * with a margin that covers the longest reach (dp_grid_build_margin). */
float dp_skeleton_reach(size_t nq, const float *metric, float cutoff, float *reach);

/* A grid for the peak over n points, for scans of `reach` cells
 * (1..DP_GRID_MAX_MARGIN) of side radius / reach; *cells_reach is the reach in
 * cells that covers the radius on the grid actually built (its cell may have
 * grown past the cap on cells), the peak's `reach` on it. */
dp_status dp_peak_grid(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float radius,
		       int reach, int *cells_reach, dp_error *err);

#endif
