/* The incremental spatial hash: see hash.h. */
#include "grid/hash.h"

#include "core/common.h"

#include <stdlib.h>
#include <string.h>

dp_status dp_hash_alloc(dp_hash *h, size_t capacity, float cell, dp_error *err)
{
	memset(h, 0, sizeof *h);
	/* indices are uint32_t, DP_HASH_NONE excluded, and so are bucket masks */
	if (capacity >= (size_t)1 << 31)
		return dp_fail(err, DP_ERR_ARG, "a spatial hash holds fewer than 2^31 points, not %zu", capacity);
	size_t buckets = 1;
	while (buckets < 2 * capacity)
		buckets <<= 1;
	if (!(h->head = dp_alloc_array(buckets, sizeof(uint32_t))) ||
	    !(h->next = dp_alloc_array(capacity ? capacity : 1, sizeof(uint32_t)))) {
		dp_hash_free(h);
		return dp_fail(err, DP_ERR_NOMEM, "out of memory for a spatial hash of %zu points", capacity);
	}
	memset(h->head, 0xff, buckets * sizeof(uint32_t));
	h->mask = (uint32_t)(buckets - 1);
	h->cell = cell;
	return DP_OK;
}

void dp_hash_free(dp_hash *h)
{
	free(h->head);
	free(h->next);
	memset(h, 0, sizeof *h);
}
