/* Point insertion of the coarse-to-fine surface (dpoints.h, dp_refine_params). */
#ifndef DP_STAGES_REFINE_H
#define DP_STAGES_REFINE_H

#include "dpoints.h"

#include <stdint.h>

/*
 * Grows the deep points (`surface` with normals, `skeleton` its inner ends,
 * both with room for `target` rows; their n is the count in use) towards
 * `target` by inserting points at midpoints of tangent-plane edges between
 * same-sided neighbours: every edge much longer than the median (a gap) and
 * an even random choice among the others, skipping midpoints nearer than a
 * fraction of the current spacing to a point already there. Existing rows
 * keep their index; new rows are appended. One pass adds at most about 3
 * points per point, so a larger growth takes several passes, each at its own
 * spacing; stops early only when a pass finds nowhere to insert. *added
 * receives how many were inserted.
 */
dp_status dp_refine_insert(dp_cloud *surface, dp_cloud *skeleton, size_t target, size_t *added, dp_error *err);

/*
 * One even-spacing round (dp_refine_params.even_rounds): inserts up to a
 * tenth of n midpoints of edges that span gaps (much longer than the median,
 * as dp_refine_insert takes first), longest first, then removes as many
 * points where the spacing is densest, none two neighbours,
 * each only where its spacing is well below the even spacing of the same
 * points over the same area. The count stays n and rows keep step: each new
 * point, with its inner end, takes the row of a removed one, and every other
 * row keeps its index and its contents. `replaced` (n entries, may be NULL)
 * gets 1 at each row that now holds a new point; its other entries are left
 * as they are. *moved receives how many points were removed (and so moved
 * elsewhere). The caller relaxes the result.
 */
dp_status dp_refine_even(dp_cloud *surface, dp_cloud *skeleton, unsigned char *replaced, size_t *moved,
			 dp_error *err);

/*
 * The fewer deep points of a count below the coarse level: picks `m` of the
 * n points (x, y, z) by farthest-point sampling, from point 0, each next the
 * one farthest from those picked, and writes their indices in ascending order
 * to keep (m entries; m <= n); of equally far points, the lowest index. The
 * same picks as that plain scan over all points for each pick (test_refine
 * has it), but each pick updates only the points within the farthest
 * point's distance of it (a kd-tree search) and the farthest is the top of
 * a heap: about n log m work instead of n m (coarse_samples 200000 with
 * 100000 kept was 2e10 distances). One thread. DP_ERR_ARG (m > n, n of 2^32 - 1
 * or more), DP_ERR_NOMEM.
 */
dp_status dp_refine_subset(size_t n, const float *x, const float *y, const float *z, size_t m, uint32_t *keep,
			   dp_error *err);

/* The count of each level: `levels` (>= 1) levels from coarse to target with
 * the same growth factor each, counts[levels - 1] = target. */
int dp_refine_levels(size_t coarse, size_t target, double level_factor, size_t *counts, int max_levels);

#endif
