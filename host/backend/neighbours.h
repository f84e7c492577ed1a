/* True-neighbour counts per operator, for benchmarks: how many of the pairs an
 * operator's grid scan visits lie within its radius (or, for the skeleton's
 * weighted sums, inside its ellipsoid). Rates per candidate fall when a finer
 * grid scans fewer candidates for the same work; rates per true neighbour do
 * not, so they compare operators, grids and the peak benchmark fairly.
 * Counting is off unless a benchmark sets ctx->neighbours; the dispatcher
 * (backend/ops.c) runs it for every operator by its row's RADIUS (and METRIC,
 * REACH), on the host before the launch, outside the kernel timings, and it
 * times itself so that a benchmark can take it out of a stage's wall time. */
#ifndef DP_BACKEND_NEIGHBOURS_H
#define DP_BACKEND_NEIGHBOURS_H

#include "backend/context.h"
#include "grid/grid.h"

#define DP_NEIGHBOUR_MAX_OPS 32

typedef struct dp_neighbour_op {
	char name[64];                        /* the operator's kernel name */
	double launches, pairs, radius_sum;   /* radius_sum / launches: its mean radius */
	double nq_sum;                        /* nq_sum / launches: its mean query count */
	size_t ndata;                         /* grid points of its last launch */
} dp_neighbour_op;

typedef struct dp_neighbour_counts {
	size_t nops;
	dp_neighbour_op ops[DP_NEIGHBOUR_MAX_OPS];
	double pairs;   /* over every operator */
	double seconds; /* spent counting */
} dp_neighbour_counts;

/* Pairs (query, grid point) with d² < radius², the query itself included. The
 * grid's margin must cover the radius (every operator's grid does). */
void dp_count_neighbours(dp_context *ctx, const char *op, const dp_grid *g, size_t nq, const float *qx,
			 const float *qy, const float *qz, float radius);

/* Pairs with u = |M_i (q_i - x)| <= cutoff for the 3x3 metric rows M_i =
 * metric[9i..9i+8], over the cells within reach[3i..3i+2] (the skeleton's
 * weighted sums, ops/operators.h); the radius recorded is the mean of
 * cbrt(reach_x reach_y reach_z), the radius of a ball as large as the box. */
void dp_count_neighbours_metric(dp_context *ctx, const char *op, const dp_grid *g, size_t nq, const float *qx,
				const float *qy, const float *qz, const float *metric, const float *reach,
				float cutoff);

#endif
