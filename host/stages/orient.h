/* Consistent orientation of unoriented normals (DESIGN §4 "Normals"), the
 * second half of dp_estimate_normals: a minimum spanning tree over the
 * symmetric kNN graph (after Hoppe 1992, with a mirrored agreement test; see
 * edge_weight in orient.c), propagated from a seed of known direction in
 * every connected component, then a global outward check per component (a
 * fragment near the body: across the gap). Internal; split out of normals.c
 * so the two steps can be tested on their own. Reentrant. */
#ifndef DP_STAGES_ORIENT_H
#define DP_STAGES_ORIENT_H

#include "dpoints.h"

#include <stdint.h>

/*
 * Flips unit normals (nx, ny, nz; n each) so that neighbours along the MST
 * agree in sign by the mirrored test (n_v mirrored in the plane bisecting the
 * step from v to u, dotted with n_u: Hoppe's n_v·n_u between tangent
 * neighbours, its opposite across a plate or a gap between facing faces). The
 * graph has an edge i–j when j is among the first k_graph entries of i's
 * neighbour list nbr[i*stride .. i*stride+k_graph) or i among j's (entries <
 * 0 or equal to i are ignored). In every connected component the seed is, of
 * the six points with the largest coordinate along ±x, ±y, ±z, the one whose
 * normal is best aligned with that direction; its normal is turned to point
 * along it (on a closed surface the outward normal at an extreme point is the
 * direction itself). comp receives the component of every point (0 ..
 * *ncomp-1, numbered in order of their lowest point index). Errors:
 * DP_ERR_ARG (k_graph > stride, n above the 32-bit range), DP_ERR_NOMEM.
 */
dp_status dp_orient_mst(size_t n, const float *x, const float *y, const float *z, float *nx, float *ny,
			float *nz, const int *nbr, int stride, int k_graph, uint32_t *comp, size_t *ncomp,
			dp_error *err);

/*
 * The global outward check, per component: the point of the component that
 * lies farthest along a direction is on its outside, so its outward normal
 * points along that direction. Over 26 directions (axes and diagonals) the
 * normals of those extreme points vote; a component whose vote is negative is
 * flipped. This holds for any component that holds its shape's outside, open
 * one-sided scans and thin plates included. The area-weighted outward flux
 * F = Σ a_i n_i·(p_i - c) (3 × the volume for a closed surface with outward
 * normals, c the centroid) decides only when the vote is within VOTE_DECISIVE
 * of 0: on its own it inverted a two-view scan of the demo chair, whose thin
 * parts enclose almost no volume. A small fragment cut off from the body by a
 * gap holds no outside of its own: it votes by its curvature, and a concave
 * one votes itself inwards. With link_range > 0, a component that comes
 * within link_range of the largest (the body, which always votes) takes its
 * sign from it instead: the mirrored test summed over the links from its
 * points to their nearest points of the body (those at most LINK_SPREAD times
 * its shortest link), when that sum lies more than LINK_DECISIVE from 0;
 * otherwise its own vote decides. Returns the number of components flipped in
 * *flipped (may be NULL). Errors: DP_ERR_NOMEM, and those of the links'
 * kd-tree (DP_ERR_ARG, DP_ERR_INTERNAL); on error the normals are
 * unspecified.
 */
dp_status dp_orient_outward(size_t n, const float *x, const float *y, const float *z, float *nx, float *ny,
			    float *nz, const double *area, const uint32_t *comp, size_t ncomp, double link_range,
			    size_t *flipped, dp_error *err);

#endif
