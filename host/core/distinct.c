#include "core/distinct.h"


#include "core/common.h"

#include <stdlib.h>
#include <string.h>

typedef struct keyed_point {
	float x, y, z;
	uint32_t index;
} keyed_point;

static int compare_position(const void *pa, const void *pb)
{
	const keyed_point *a = pa, *b = pb;
	if (a->x != b->x)
		return a->x < b->x ? -1 : 1;
	if (a->y != b->y)
		return a->y < b->y ? -1 : 1;
	if (a->z != b->z)
		return a->z < b->z ? -1 : 1;
	return a->index < b->index ? -1 : a->index > b->index;
}

static int same_position(const keyed_point *a, const keyed_point *b)
{
	return a->x == b->x && a->y == b->y && a->z == b->z;
}

dp_status dp_distinct(size_t n, const float *x, const float *y, const float *z, uint32_t *of, size_t *ndistinct,
		      dp_error *err)
{
	*ndistinct = 0;
	if (n > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "%zu points exceed the 32-bit index range", n);
	keyed_point *key = dp_alloc_array(n, sizeof *key);
	if (!key)
		return dp_fail(err, DP_ERR_NOMEM, "out of memory sorting %zu points", n);
	for (size_t i = 0; i < n; i++)
		key[i] = (keyed_point){x[i], y[i], z[i], (uint32_t)i};
	/* ties sort by index, so the first of each run is the smallest index */
	qsort(key, n, sizeof *key, compare_position);
	uint32_t first = 0;
	for (size_t s = 0; s < n; s++) {
		if (s == 0 || !same_position(&key[s], &key[s - 1])) {
			first = key[s].index;
			(*ndistinct)++;
		}
		of[key[s].index] = first;
	}
	free(key);
	return DP_OK;
}

/* A position's bits, with -0 as 0 since dp_distinct compares with ==. */
static uint32_t position_hash(float x, float y, float z)
{
	float v[3] = {x == 0.0f ? 0.0f : x, y == 0.0f ? 0.0f : y, z == 0.0f ? 0.0f : z};
	uint32_t b[3];
	memcpy(b, v, sizeof b);
	uint64_t h = (b[0] * 0x9E3779B97F4A7C15ull) ^ (b[1] * 0xC2B2AE3D27D4EB4Full) ^ (b[2] * 0x165667B19E3779F9ull);
	return (uint32_t)(h ^ (h >> 29) ^ (h >> 41));
}

/* Counts distinct input positions, stopping at m: *found = min(m, distinct).
 * A hash set of at most m positions, so an input of millions of copies of a
 * few points (a well-formed file whose body is zeros) is refused after one
 * pass in O(m) memory, before the buffers of the run and the O(n log n) sort
 * and ~40 bytes a point of choose_samples. */
dp_status dp_distinct_upto(const dp_cloud *in, size_t m, size_t *found, dp_error *err)
{
	if (m > in->n)
		m = in->n; /* no more to find, and 2 m cannot wrap */
	size_t cap = 16;
	while (cap < 2 * m)
		cap *= 2;
	uint32_t *slot = dp_alloc_array(cap, sizeof *slot);
	if (!slot)
		return dp_fail(err, DP_ERR_NOMEM, "out of memory counting distinct positions");
	memset(slot, 0xff, cap * sizeof *slot);
	size_t count = 0;
	for (size_t i = 0; i < in->n && count < m; i++) {
		size_t k = position_hash(in->x[i], in->y[i], in->z[i]) & (cap - 1);
		for (;; k = (k + 1) & (cap - 1)) {
			uint32_t j = slot[k];
			if (j == UINT32_MAX) {
				slot[k] = (uint32_t)i;
				count++;
				break;
			}
			if (in->x[j] == in->x[i] && in->y[j] == in->y[i] && in->z[j] == in->z[i])
				break;
		}
	}
	free(slot);
	*found = count;
	return DP_OK;
}
