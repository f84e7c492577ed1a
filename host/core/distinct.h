/* Exactly coincident points: merged scans repeat points, and both WLOP's
 * sample choice and the normal estimation must see each position once. */
#ifndef DP_CORE_DISTINCT_H
#define DP_CORE_DISTINCT_H

#include "dpoints.h"

/* of[i] = the smallest index j with exactly the position of point i (so
 * of[i] == i for the first of each position); *ndistinct = how many distinct
 * positions there are. O(n log n); `of` holds n entries. */
dp_status dp_distinct(size_t n, const float *x, const float *y, const float *z, uint32_t *of, size_t *ndistinct,
		      dp_error *err);

/* Counts distinct positions of `in`, stopping at m: *found = min(m, distinct).
 * O(m) memory and one pass, so a huge input of copies is answered at once. */
dp_status dp_distinct_upto(const dp_cloud *in, size_t m, size_t *found, dp_error *err);

#endif
