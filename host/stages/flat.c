/* The depth of flat faces scanned from one side: see flat.h. */
#include "stages/flat.h"

#include "core/common.h"
#include "core/parallel.h"
#include "knn/kdtree.h"
#include "knn/knn.h"

#include <math.h>
#include <stdlib.h>

#define NO_ORIGIN UINT32_MAX
/* A thread of the evidence passes gets at least this many samples (two
 * radius searches each, tens of microseconds). */
#define FLAT_MIN_ITEMS 512

static int by_value(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/* A depth on offer: from evidence sample `origin`, to `point`. */
typedef struct entry {
	float cap;
	uint32_t origin, point;
} entry;

static int before(entry a, entry b)
{
	if (a.cap != b.cap)
		return a.cap < b.cap;
	if (a.origin != b.origin)
		return a.origin < b.origin;
	return a.point < b.point;
}

/* A binary min-heap of entries in h[0..*top). */
static void heap_push(entry *h, size_t *top, entry e)
{
	size_t i = (*top)++;
	while (i > 0 && before(e, h[(i - 1) / 2])) {
		h[i] = h[(i - 1) / 2];
		i = (i - 1) / 2;
	}
	h[i] = e;
}

static entry heap_pop(entry *h, size_t *top)
{
	entry first = h[0], last = h[--(*top)];
	size_t i = 0;
	for (;;) {
		size_t c = 2 * i + 1;
		if (c >= *top)
			break;
		if (c + 1 < *top && before(h[c + 1], h[c]))
			c++;
		if (!before(h[c], last))
			break;
		h[i] = h[c];
		i = c;
	}
	if (*top > 0)
		h[i] = last;
	return first;
}

static int evidence(unsigned char why)
{
	return why == DP_SETTLE_FRONT || why == DP_SETTLE_MEDIAL;
}

static float depth(const float *const p[3], float *const q[3], size_t i)
{
	float d[3] = {q[0][i] - p[0][i], q[1][i] - p[1][i], q[2][i] - p[2][i]};
	return sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* What the per-evidence passes share; each range writes only its own
 * samples' slots and has its own search buffers. */
typedef struct flat_job {
	const float *const *p, *const *normal;
	const unsigned char *settled_by;
	const dp_kdtree *tree;
	const float *own;
	float *cap, *half;
	uint32_t *origin;
	float rim2, band2, min_cos, sin_a, band_end;
	double below_min;
	uint32_t *ridx, *bidx;   /* DP_FLAT_RIM_COUNT, DP_FLAT_BAND_COUNT per part */
	float *rd2, *rdepth, *bd2;
} flat_job;

static float cosine(const float *const normal[3], size_t i, size_t o)
{
	return normal[0][i] * normal[0][o] + normal[1][i] * normal[1][o] + normal[2][i] * normal[2][o];
}

/* An evidence point's depth says how far its own ball reaches, which near a
 * rim runs from 0 at the crease to the full thickness a thickness in; the
 * face's is the median over the evidence around it that faces the same way,
 * and at most half the height of the edge band beside it (flat.h). A sample
 * that stopped without evidence offers its edge band's half height alone. */
static void evidence_range(void *arg, size_t begin, size_t end, int part)
{
	flat_job *job = arg;
	const float *const *p = job->p, *const *normal = job->normal;
	uint32_t *ridx = job->ridx + (size_t)part * DP_FLAT_RIM_COUNT, *bidx = job->bidx + (size_t)part * DP_FLAT_BAND_COUNT;
	float *rd2 = job->rd2 + (size_t)part * DP_FLAT_RIM_COUNT, *rdepth = job->rdepth + (size_t)part * DP_FLAT_RIM_COUNT;
	float *bd2 = job->bd2 + (size_t)part * DP_FLAT_BAND_COUNT;
	for (size_t i = begin; i < end; i++) {
		job->origin[i] = NO_ORIGIN;
		job->cap[i] = INFINITY;
		int ev = evidence(job->settled_by[i]);
		if (!ev && job->settled_by[i] != DP_SETTLE_SLOW && job->settled_by[i] != DP_SETTLE_WIDTH)
			continue;
		size_t found = dp_kdtree_nearest_within(job->tree, p[0][i], p[1][i], p[2][i], job->rim2, DP_FLAT_RIM_COUNT, ridx, rd2);
		size_t m = 0, facing = 0, all = 0;
		for (size_t j = 0; j < found; j++) {
			uint32_t o = ridx[j];
			all++;
			if (cosine(normal, i, o) < job->min_cos)
				continue;
			facing++;
			if (ev && evidence(job->settled_by[o]))
				rdepth[m++] = job->own[o];
		}
		if (ev) {
			if (m == 0)
				continue; /* the radius search missed the point itself: NaN coordinates, checked before */
			qsort(rdepth, m, sizeof *rdepth, by_value);
			job->cap[i] = rdepth[m / 2];
			job->origin[i] = (uint32_t)i;
		}
		/* only a flat face has an edge band: around a rounded part's point
		 * the samples facing its way are few, and the ones turned away by
		 * a right angle are no plate's edge */
		if (facing < DP_FLAT_FACE_FRACTION * all)
			continue;
		found = dp_kdtree_nearest_within(job->tree, p[0][i], p[1][i], p[2][i], job->band2, DP_FLAT_BAND_COUNT, bidx, bd2);
		size_t band = 0;
		float reach = 0.0f, aside2 = INFINITY;
		for (size_t j = 0; j < found; j++) {
			uint32_t o = bidx[j];
			if (!(fabsf(cosine(normal, i, o)) <= job->sin_a))
				continue;
			float d[3] = {p[0][o] - p[0][i], p[1][o] - p[1][i], p[2][o] - p[2][i]};
			float below = -(normal[0][i] * d[0] + normal[1][i] * d[1] + normal[2][i] * d[2]);
			if (!(below > job->below_min))
				continue; /* beside or above the face: no edge of it */
			reach = fmaxf(reach, below);
			aside2 = fminf(aside2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - below * below);
			band++;
		}
		/* the search ball shows a band as far down as its radius allows
		 * beside the point: a band that ends well above that is a plate's */
		if (band >= DP_FLAT_BAND_MIN && reach < DP_FLAT_BAND_TALL * sqrtf(fmaxf(job->band2 - aside2, 0.0f))) {
			job->half[i] = 0.5f * (reach + job->band_end);
			job->origin[i] = (uint32_t)i;
		}
	}
}

/* Like the depths, the band's half thickness is the median over the samples
 * around that faces the same way: one short band does not set a face. */
static void band_median_range(void *arg, size_t begin, size_t end, int part)
{
	flat_job *job = arg;
	const float *const *p = job->p;
	uint32_t *ridx = job->ridx + (size_t)part * DP_FLAT_RIM_COUNT;
	float *rd2 = job->rd2 + (size_t)part * DP_FLAT_RIM_COUNT, *rdepth = job->rdepth + (size_t)part * DP_FLAT_RIM_COUNT;
	for (size_t i = begin; i < end; i++) {
		if (job->origin[i] == NO_ORIGIN)
			continue;
		size_t found = dp_kdtree_nearest_within(job->tree, p[0][i], p[1][i], p[2][i], job->rim2, DP_FLAT_RIM_COUNT, ridx, rd2);
		size_t m = 0;
		for (size_t j = 0; j < found; j++) {
			uint32_t o = ridx[j];
			if (isfinite(job->half[o]) && cosine(job->normal, i, o) >= job->min_cos)
				rdepth[m++] = job->half[o];
		}
		if (m == 0)
			continue;
		qsort(rdepth, m, sizeof *rdepth, by_value);
		if (rdepth[m / 2] < job->cap[i])
			job->cap[i] = rdepth[m / 2];
	}
}

dp_status dp_flat_cap(int threads, size_t n, const float *const p[3], const float *const normal[3], float *const q[3],
		      unsigned char *settled_by, double r, double angle_deg, size_t *capped, dp_error *err)
{
	*capped = 0;
	if (n < 2)
		return DP_OK;
	int k = n - 1 < DP_FLAT_NEIGHBOURS ? (int)(n - 1) : DP_FLAT_NEIGHBOURS;
	int *idx = dp_alloc_array(n, (size_t)k * sizeof(int));
	float *d2 = dp_alloc_array(n, (size_t)k * sizeof(float));
	float *cap = dp_alloc_array(n, sizeof(float)), *own = dp_alloc_array(n, sizeof(float));
	float *half = dp_alloc_array(n, sizeof(float));
	/* search buffers, one set per range (a few hundred kB at most) */
	uint32_t *ridx = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_RIM_COUNT * sizeof(uint32_t));
	float *rd2 = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_RIM_COUNT * sizeof(float));
	float *rdepth = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_RIM_COUNT * sizeof(float));
	uint32_t *bidx = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_BAND_COUNT * sizeof(uint32_t));
	float *bd2 = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_BAND_COUNT * sizeof(float));
	uint32_t *origin = dp_alloc_array(n, sizeof(uint32_t));
	unsigned char *done = calloc(n, 1);
	/* every sample enters once as evidence or once per link that lowers it */
	entry *heap = dp_alloc_array(n, ((size_t)k + 1) * sizeof(entry));
	dp_knn knn = {0};
	dp_kdtree tree = {0};
	dp_status st = DP_OK;
	if (!idx || !d2 || !cap || !own || !half || !origin || !ridx || !rd2 || !rdepth || !bidx || !bd2 || !done || !heap) {
		st = dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for the flat-face depths of %zu points", n);
		goto out;
	}
	if ((st = dp_knn_build(&knn, n, p[0], p[1], p[2], err)) != DP_OK ||
	    (st = dp_knn_self(&knn, k, idx, d2, err)) != DP_OK || (st = dp_kdtree_build(&tree, n, p[0], p[1], p[2], err)) != DP_OK)
		goto out;
	float min_cos = (float)cos(angle_deg * M_PI / 180.0), sin_a = (float)sin(angle_deg * M_PI / 180.0);
	for (size_t i = 0; i < n; i++) {
		own[i] = depth(p, q, i);
		half[i] = INFINITY;
	}
	flat_job job = {
		.p = p, .normal = normal, .settled_by = settled_by, .tree = &tree, .own = own, .cap = cap,
		.half = half, .origin = origin, .min_cos = min_cos, .sin_a = sin_a, .band_end = (float)(DP_FLAT_BAND_END_R * r),
		.rim2 = (float)(DP_FLAT_RIM_R * r * DP_FLAT_RIM_R * r), .band2 = (float)(DP_FLAT_BAND_R * r * DP_FLAT_BAND_R * r),
		.below_min = DP_FLAT_BAND_BELOW_R * r, .ridx = ridx, .bidx = bidx, .rd2 = rd2, .rdepth = rdepth,
		.bd2 = bd2,
	};
	dp_parallel_for(threads, n, FLAT_MIN_ITEMS, evidence_range, &job);
	dp_parallel_for(threads, n, FLAT_MIN_ITEMS, band_median_range, &job);
	/* Best first, smallest depth first: each sample takes the first depth
	 * that reaches it and passes on only that one, so the outcome does not
	 * depend on the samples' order. */
	float link2 = (float)(DP_FLAT_LINK_R * r * DP_FLAT_LINK_R * r);
	size_t top = 0;
	for (size_t i = 0; i < n; i++)
		if (origin[i] != NO_ORIGIN)
			heap_push(heap, &top, (entry){cap[i], origin[i], (uint32_t)i});
	while (top > 0) {
		entry e = heap_pop(heap, &top);
		if (done[e.point] || e.cap != cap[e.point] || e.origin != origin[e.point])
			continue; /* a stale entry: the point was reached by a smaller depth */
		done[e.point] = 1;
		const float *on[3] = {&normal[0][e.origin], &normal[1][e.origin], &normal[2][e.origin]};
		for (int j = 0; j < k; j++) {
			size_t slot = e.point * (size_t)k + (size_t)j;
			int nb = idx[slot];
			if (nb < 0 || !(d2[slot] <= link2))
				break; /* ascending: the rest are farther */
			if (done[nb] || !(e.cap < cap[nb] || (e.cap == cap[nb] && e.origin < origin[nb])))
				continue;
			if (normal[0][nb] * *on[0] + normal[1][nb] * *on[1] + normal[2][nb] * *on[2] < min_cos)
				continue;
			cap[nb] = e.cap;
			origin[nb] = e.origin;
			heap_push(heap, &top, (entry){e.cap, e.origin, (uint32_t)nb});
		}
	}
	for (size_t i = 0; i < n; i++) {
		if ((settled_by[i] != DP_SETTLE_SLOW && settled_by[i] != DP_SETTLE_WIDTH) || !isfinite(cap[i]))
			continue;
		float d = own[i];
		if (!(d > cap[i]))
			continue;
		float f = cap[i] / d;
		for (int c = 0; c < 3; c++)
			q[c][i] = p[c][i] + (q[c][i] - p[c][i]) * f;
		settled_by[i] = DP_SETTLE_FLAT;
		(*capped)++;
	}
out:
	dp_knn_free(&knn);
	dp_kdtree_free(&tree);
	free(idx);
	free(d2);
	free(cap);
	free(own);
	free(half);
	free(origin);
	free(done);
	free(heap);
	free(ridx);
	free(rd2);
	free(rdepth);
	free(bidx);
	free(bd2);
	return st;
}
