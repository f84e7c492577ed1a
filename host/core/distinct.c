#include "core/distinct.h"

#include "core/common.h"

#include <stdlib.h>

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
