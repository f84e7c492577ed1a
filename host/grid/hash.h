/* An incremental spatial hash of cubes of side `cell`, for sets that grow one
 * point at a time while they are searched (a uniform grid, grid.h, is built
 * once over a fixed set). head[bucket] and next[point] chain the points of a
 * bucket; a bucket may also hold points of other cubes, so callers test
 * distances. Positions stay with the caller; points are indices. */
#ifndef DP_GRID_HASH_H
#define DP_GRID_HASH_H

#include "dpoints.h"

#include <math.h>

#define DP_HASH_NONE UINT32_MAX

typedef struct dp_hash {
	uint32_t *head; /* per bucket: the last point inserted, DP_HASH_NONE when empty */
	uint32_t *next; /* per point: the one inserted before it into its bucket */
	uint32_t mask;  /* buckets - 1, a power of two */
	float cell;
} dp_hash;

/* Room for points 0..capacity-1 and at least 2 × capacity buckets, empty.
 * `cell` must keep |coordinate| / cell well inside int64 (callers clamp it).
 * DP_ERR_ARG (2^31 points or more), DP_ERR_NOMEM; h zeroed on error. */
dp_status dp_hash_alloc(dp_hash *h, size_t capacity, float cell, dp_error *err);
void dp_hash_free(dp_hash *h);

static inline int64_t dp_hash_cell(const dp_hash *h, float v)
{
	return (int64_t)floorf(v / h->cell);
}

static inline uint32_t dp_hash_bucket(const dp_hash *h, int64_t i, int64_t j, int64_t k)
{
	uint64_t v = (uint64_t)i * 73856093u ^ (uint64_t)j * 19349663u ^ (uint64_t)k * 83492791u;
	return (uint32_t)(v & h->mask);
}

/* Adds point i (< capacity) at (x, y, z). */
static inline void dp_hash_insert(dp_hash *h, uint32_t i, float x, float y, float z)
{
	uint32_t b = dp_hash_bucket(h, dp_hash_cell(h, x), dp_hash_cell(h, y), dp_hash_cell(h, z));
	h->next[i] = h->head[b];
	h->head[b] = i;
}

#endif
