#include "knn/kdtree.h"

#include "core/common.h"

#include <stdlib.h>
#include <string.h>

/* Nodes of at most this many points are scanned, not split: below it a split
 * test costs more than the distance tests it saves. */
#define KDTREE_LEAF 8

typedef struct keyed {
	float key;
	uint32_t index;
} keyed;

static int by_key(const void *a, const void *b)
{
	float ka = ((const keyed *)a)->key, kb = ((const keyed *)b)->key;
	return (ka > kb) - (ka < kb);
}

/* Orders order[lo, hi) (indices into the caller's arrays) as the subtree
 * over them: the median point at the middle, the points not above it along
 * the node's axis before it, the points not below it after. */
static void build_node(dp_kdtree *t, const float *const src[3], uint32_t *order, keyed *scratch, size_t lo,
		       size_t hi)
{
	if (hi == lo)
		return;
	float lo_v[3], hi_v[3];
	for (int a = 0; a < 3; a++)
		lo_v[a] = hi_v[a] = src[a][order[lo]];
	for (size_t k = lo + 1; k < hi; k++)
		for (int a = 0; a < 3; a++) {
			float v = src[a][order[k]];
			lo_v[a] = v < lo_v[a] ? v : lo_v[a];
			hi_v[a] = v > hi_v[a] ? v : hi_v[a];
		}
	float *box = t->box + 6 * (lo + (hi - lo) / 2);
	for (int a = 0; a < 3; a++) {
		box[a] = lo_v[a];
		box[3 + a] = hi_v[a];
	}
	if (hi - lo <= KDTREE_LEAF)
		return;
	int axis = 0;
	for (int a = 1; a < 3; a++)
		if (hi_v[a] - lo_v[a] > hi_v[axis] - lo_v[axis])
			axis = a;
	for (size_t k = lo; k < hi; k++)
		scratch[k - lo] = (keyed){src[axis][order[k]], order[k]};
	qsort(scratch, hi - lo, sizeof *scratch, by_key);
	for (size_t k = lo; k < hi; k++)
		order[k] = scratch[k - lo].index;
	size_t mid = lo + (hi - lo) / 2;
	t->axis[mid] = (unsigned char)axis;
	build_node(t, src, order, scratch, lo, mid);
	build_node(t, src, order, scratch, mid + 1, hi);
}

dp_status dp_kdtree_build(dp_kdtree *t, size_t n, const float *x, const float *y, const float *z, dp_error *err)
{
	memset(t, 0, sizeof *t);
	if (n > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "kd-tree: cannot index %zu points", n);
	uint32_t *order = dp_alloc_array(n, sizeof *order);
	keyed *scratch = dp_alloc_array(n, sizeof *scratch);
	t->index = dp_alloc_array(n, sizeof *t->index);
	t->x = dp_alloc_array(n, sizeof(float));
	t->y = dp_alloc_array(n, sizeof(float));
	t->z = dp_alloc_array(n, sizeof(float));
	t->axis = calloc(n ? n : 1, 1);
	t->box = dp_alloc_array(n, 6 * sizeof(float));
	if (!order || !scratch || !t->index || !t->x || !t->y || !t->z || !t->axis || !t->box) {
		free(order);
		free(scratch);
		dp_kdtree_free(t);
		return dp_fail(err, DP_ERR_NOMEM, "kd-tree: out of memory for %zu points", n);
	}
	for (size_t k = 0; k < n; k++)
		order[k] = (uint32_t)k;
	const float *src[3] = {x, y, z};
	build_node(t, src, order, scratch, 0, n);
	for (size_t k = 0; k < n; k++) {
		t->index[k] = order[k];
		t->x[k] = x[order[k]];
		t->y[k] = y[order[k]];
		t->z[k] = z[order[k]];
	}
	t->n = n;
	free(order);
	free(scratch);
	return DP_OK;
}

void dp_kdtree_free(dp_kdtree *t)
{
	free(t->index);
	free(t->x);
	free(t->y);
	free(t->z);
	free(t->axis);
	free(t->box);
	memset(t, 0, sizeof *t);
}

static int within(const dp_kdtree *t, const float q[3], float r2, size_t k)
{
	float dx = t->x[k] - q[0], dy = t->y[k] - q[1], dz = t->z[k] - q[2];
	return dx * dx + dy * dy + dz * dz < r2;
}

/* A lower bound of the squared distance from q to the points of the node
 * whose bounding box is `box`: along each axis |q_a - p_a| >= the gap e_a
 * between q_a and the box, and float subtraction, squaring and adding
 * non-negative terms round monotonically, so the bound holds for the rounded
 * distances `within` compares too: a node with a bound >= r2 holds no point
 * that passes. Real boxes, not the kd cells the splits bound: over a curved
 * surface a cell reaches far into the empty space where the balls are. */
static float box_d2(const float *box, const float q[3])
{
	float e[3];
	for (int a = 0; a < 3; a++)
		e[a] = q[a] < box[a] ? box[a] - q[a] : q[a] > box[3 + a] ? q[a] - box[3 + a] : 0.0f;
	return e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
}

/* The near side of a split is searched first: a ball that holds a point
 * mostly holds one there. */
static int any_in_node(const dp_kdtree *t, const float q[3], float r2, size_t lo, size_t hi)
{
	while (hi > lo) {
		size_t mid = lo + (hi - lo) / 2;
		if (!(box_d2(t->box + 6 * mid, q) < r2))
			return 0;
		if (hi - lo <= KDTREE_LEAF) {
			for (size_t k = lo; k < hi; k++)
				if (within(t, q, r2, k))
					return 1;
			return 0;
		}
		if (within(t, q, r2, mid))
			return 1;
		int a = t->axis[mid];
		const float *split = a == 0 ? t->x : a == 1 ? t->y : t->z;
		int low_is_near = q[a] < split[mid];
		if (any_in_node(t, q, r2, low_is_near ? lo : mid + 1, low_is_near ? mid : hi))
			return 1;
		if (low_is_near)
			lo = mid + 1;
		else
			hi = mid;
	}
	return 0;
}

int dp_kdtree_any_within(const dp_kdtree *t, float x, float y, float z, float r2)
{
	if (!(r2 > 0.0f))
		return 0;
	const float q[3] = {x, y, z};
	return any_in_node(t, q, r2, 0, t->n);
}

/* The nearest points found so far: a max-heap on d2 of at most cap entries,
 * so the farthest kept is replaced first. */
typedef struct nearest {
	uint32_t *idx;
	float *d2;
	size_t size, cap;
	float r2;
} nearest;

/* The squared distance a point must be below to be kept. */
static float bound(const nearest *h)
{
	return h->size < h->cap ? h->r2 : h->d2[0];
}

static void sift_down(nearest *h, size_t i)
{
	for (;;) {
		size_t c = 2 * i + 1, m = i;
		if (c < h->size && h->d2[c] > h->d2[m])
			m = c;
		if (c + 1 < h->size && h->d2[c + 1] > h->d2[m])
			m = c + 1;
		if (m == i)
			return;
		float d = h->d2[i];
		uint32_t k = h->idx[i];
		h->d2[i] = h->d2[m];
		h->idx[i] = h->idx[m];
		h->d2[m] = d;
		h->idx[m] = k;
		i = m;
	}
}

static void offer(nearest *h, const dp_kdtree *t, const float q[3], size_t k)
{
	float dx = t->x[k] - q[0], dy = t->y[k] - q[1], dz = t->z[k] - q[2];
	float d2 = dx * dx + dy * dy + dz * dz;
	if (!(d2 < bound(h)))
		return;
	if (h->size < h->cap) {
		size_t i = h->size++;
		while (i > 0 && h->d2[(i - 1) / 2] < d2) {
			h->d2[i] = h->d2[(i - 1) / 2];
			h->idx[i] = h->idx[(i - 1) / 2];
			i = (i - 1) / 2;
		}
		h->d2[i] = d2;
		h->idx[i] = t->index[k];
		return;
	}
	h->d2[0] = d2;
	h->idx[0] = t->index[k];
	sift_down(h, 0);
}

static void nearest_in_node(const dp_kdtree *t, const float q[3], nearest *h, size_t lo, size_t hi)
{
	while (hi > lo) {
		size_t mid = lo + (hi - lo) / 2;
		if (!(box_d2(t->box + 6 * mid, q) < bound(h)))
			return;
		if (hi - lo <= KDTREE_LEAF) {
			for (size_t k = lo; k < hi; k++)
				offer(h, t, q, k);
			return;
		}
		offer(h, t, q, mid);
		int a = t->axis[mid];
		const float *split = a == 0 ? t->x : a == 1 ? t->y : t->z;
		int low_is_near = q[a] < split[mid];
		nearest_in_node(t, q, h, low_is_near ? lo : mid + 1, low_is_near ? mid : hi);
		if (low_is_near)
			lo = mid + 1;
		else
			hi = mid;
	}
}

size_t dp_kdtree_nearest_within(const dp_kdtree *t, float x, float y, float z, float r2, size_t cap, uint32_t *idx,
				float *d2)
{
	if (!(r2 > 0.0f) || cap == 0)
		return 0;
	const float q[3] = {x, y, z};
	nearest h = {idx, d2, 0, cap, r2};
	nearest_in_node(t, q, &h, 0, t->n);
	return h.size;
}
