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

#endif
