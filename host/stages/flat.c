/* The depth of flat faces scanned from one side: see flat.h. */
#include "stages/flat.h"

#include "core/common.h"
#include "core/parallel.h"
#include "knn/kdtree.h"
#include "knn/knn.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* The upper median of v[0..m), m > 0; sorts v. */
static float median(float *v, size_t m)
{
	qsort(v, m, sizeof *v, by_value);
	return v[m / 2];
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

/* Moves q_i along its line from p_i, now `from` deep, to `to` deep. */
static void lift(const float *const p[3], float *const q[3], size_t i, float from, float to)
{
	float s = to / from;
	for (int c = 0; c < 3; c++)
		q[c][i] = p[c][i] + (q[c][i] - p[c][i]) * s;
}

static float cosine(const float *const normal[3], size_t i, size_t o)
{
	return normal[0][i] * normal[0][o] + normal[1][i] * normal[1][o] + normal[2][i] * normal[2][o];
}

/* Search buffers of one range. */
typedef struct buffers {
	uint32_t *idx;
	float *d2, *value;
} buffers;

static buffers part_buffers(const dp_flat *f, int part, size_t count)
{
	size_t off = (size_t)part * count;
	return (buffers){f->sidx + off, f->sd2 + off, f->svalue + off};
}

/* The samples within DP_FLAT_RIM_R of sample i, at most DP_FLAT_RIM_COUNT. */
static size_t rim(const dp_flat *f, size_t i, buffers b)
{
	return dp_kdtree_nearest_within(&f->tree, f->p[0][i], f->p[1][i], f->p[2][i], f->rim2, DP_FLAT_RIM_COUNT, b.idx,
					b.d2);
}

/* The edge band beside each sample (flat.h): half the height it shows below
 * the sample's plane plus DP_FLAT_BAND_END_R, or INFINITY where there is
 * none. Geometry alone, so the context computes it once. Each range writes
 * only its own samples' slots. */
static void band_range(void *arg, size_t begin, size_t end, int part)
{
	dp_flat *f = arg;
	const float *const *p = f->p, *const *normal = f->normal;
	buffers b = part_buffers(f, part, DP_FLAT_BAND_COUNT);
	for (size_t i = begin; i < end; i++) {
		f->half[i] = INFINITY;
		/* only a flat face has an edge band: around a rounded part's point
		 * the samples facing its way are few, and the ones turned away by
		 * a right angle are no plate's edge */
		size_t found = rim(f, i, b);
		size_t facing = 0;
		for (size_t j = 0; j < found; j++)
			facing += cosine(normal, i, b.idx[j]) >= f->min_cos;
		if (facing < DP_FLAT_FACE_FRACTION * found)
			continue;
		found = dp_kdtree_nearest_within(&f->tree, p[0][i], p[1][i], p[2][i], f->band2, DP_FLAT_BAND_COUNT, b.idx,
						 b.d2);
		size_t band = 0;
		float reach = 0.0f, aside2 = INFINITY;
		for (size_t j = 0; j < found; j++) {
			uint32_t o = b.idx[j];
			if (!(fabsf(cosine(normal, i, o)) <= f->sin_a))
				continue;
			float d[3] = {p[0][o] - p[0][i], p[1][o] - p[1][i], p[2][o] - p[2][i]};
			float below = -(normal[0][i] * d[0] + normal[1][i] * d[1] + normal[2][i] * d[2]);
			if (!(below > f->below_min))
				continue; /* beside or above the face: no edge of it */
			reach = fmaxf(reach, below);
			aside2 = fminf(aside2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - below * below);
			band++;
		}
		/* the search ball shows a band as far down as its radius allows
		 * beside the point: a band that ends well above that is a plate's */
		if (band >= DP_FLAT_BAND_MIN && reach < DP_FLAT_BAND_TALL * sqrtf(fmaxf(f->band2 - aside2, 0.0f)))
			f->half[i] = 0.5f * (reach + f->band_end);
	}
}

/* Like the depths, the band's half thickness is the median over the samples
 * around that face the same way: one short band does not set a face. */
static void band_median_range(void *arg, size_t begin, size_t end, int part)
{
	dp_flat *f = arg;
	buffers b = part_buffers(f, part, DP_FLAT_BAND_COUNT);
	for (size_t i = begin; i < end; i++) {
		f->face_half[i] = INFINITY;
		size_t found = rim(f, i, b);
		size_t m = 0;
		for (size_t j = 0; j < found; j++) {
			uint32_t o = b.idx[j];
			if (isfinite(f->half[o]) && cosine(f->normal, i, o) >= f->min_cos)
				b.value[m++] = f->half[o];
		}
		if (m > 0)
			f->face_half[i] = median(b.value, m);
	}
}

/* What one update reads besides the context. */
typedef struct update_job {
	dp_flat *f;
	float *const *q;
	const unsigned char *settled_by;
} update_job;

/* An evidence point's depth says how far its own ball reaches, which near a
 * rim runs from 0 at the crease to the full thickness a thickness in; the
 * face's is the median over the evidence around it that faces the same way,
 * and at most the face's band half height (flat.h). Any other sample beside
 * a band offers the face's band half height alone. */
static void origin_range(void *arg, size_t begin, size_t end, int part)
{
	update_job *job = arg;
	dp_flat *f = job->f;
	const float *const *p = f->p;
	buffers b = part_buffers(f, part, DP_FLAT_BAND_COUNT);
	for (size_t i = begin; i < end; i++) {
		float cap = isfinite(f->half[i]) ? f->face_half[i] : INFINITY;
		if (job->settled_by && evidence(job->settled_by[i])) {
			cap = f->face_half[i];
			size_t found = rim(f, i, b);
			size_t m = 0;
			for (size_t j = 0; j < found; j++) {
				uint32_t o = b.idx[j];
				if (evidence(job->settled_by[o]) && cosine(f->normal, i, o) >= f->min_cos)
					b.value[m++] = depth(p, job->q, o);
			}
			if (m > 0) /* 0 only if the search missed the point itself: NaN, checked before */
				cap = fminf(cap, median(b.value, m));
		}
		f->cap[i] = cap;
		f->origin[i] = isfinite(cap) ? (uint32_t)i : NO_ORIGIN;
	}
}

void dp_flat_update(dp_flat *f, int threads, float *const q[3], const unsigned char *settled_by)
{
	size_t n = f->n;
	if (n < 2)
		return;
	update_job job = {f, q, settled_by};
	dp_parallel_for(threads, n, FLAT_MIN_ITEMS, origin_range, &job);
	/* Best first, smallest depth first: each sample takes the first depth
	 * that reaches it and passes on only that one, so the outcome does not
	 * depend on the samples' order. */
	const float *const *normal = f->normal;
	int k = f->k;
	size_t top = 0;
	memset(f->done, 0, n);
	for (size_t i = 0; i < n; i++)
		if (f->origin[i] != NO_ORIGIN)
			heap_push(f->heap, &top, (entry){f->cap[i], f->origin[i], (uint32_t)i});
	while (top > 0) {
		entry e = heap_pop(f->heap, &top);
		if (f->done[e.point] || e.cap != f->cap[e.point] || e.origin != f->origin[e.point])
			continue; /* a stale entry: the point was reached by a smaller depth */
		f->done[e.point] = 1;
		const float *on[3] = {&normal[0][e.origin], &normal[1][e.origin], &normal[2][e.origin]};
		for (int j = 0; j < k; j++) {
			size_t slot = e.point * (size_t)k + (size_t)j;
			int nb = f->idx[slot];
			if (nb < 0 || !(f->d2[slot] <= f->link2))
				break; /* ascending: the rest are farther */
			if (f->done[nb] || !(e.cap < f->cap[nb] || (e.cap == f->cap[nb] && e.origin < f->origin[nb])))
				continue;
			if (normal[0][nb] * *on[0] + normal[1][nb] * *on[1] + normal[2][nb] * *on[2] < f->min_cos)
				continue;
			f->cap[nb] = e.cap;
			f->origin[nb] = e.origin;
			heap_push(f->heap, &top, (entry){e.cap, e.origin, (uint32_t)nb});
		}
	}
}

int dp_flat_too_deep(const dp_flat *f, float *const q[3], size_t i, float past)
{
	if (f->n < 2 || !isfinite(f->cap[i]))
		return 0;
	float d = depth(f->p, q, i);
	if (!(d > past * f->cap[i]))
		return 0;
	lift(f->p, q, i, d, f->cap[i]);
	return 1;
}

typedef struct cross_job {
	dp_flat *f;
	float *const *q;
	const unsigned char *settled_by;
} cross_job;

static void cross_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	const cross_job *job = arg;
	dp_flat *f = job->f;
	const float *const *p = f->p, *const *normal = f->normal;
	float *const *q = job->q;
	int k = f->k;
	float t[DP_FLAT_NEIGHBOURS];
	for (size_t i = begin; i < end; i++) {
		f->cross[i] = INFINITY;
		unsigned char why = job->settled_by[i];
		if (why != DP_SETTLE_SLOW && why != DP_SETTLE_WIDTH)
			continue;
		/* the point moves along its own line from p_i through q_i, which
		 * the smoothing has turned a little off -n_i */
		float dq = depth(p, q, i);
		if (!(dq > 0.0f))
			continue;
		float u[3] = {(q[0][i] - p[0][i]) / dq, (q[1][i] - p[1][i]) / dq, (q[2][i] - p[2][i]) / dq};
		int nt = 0;
		for (int m = 0; m < k; m++) {
			size_t slot = i * (size_t)k + (size_t)m;
			int j = f->idx[slot];
			if (j < 0 || !(f->d2[slot] <= f->link2))
				break; /* ascending: the rest are farther */
			unsigned char wj = job->settled_by[j];
			if (!evidence(wj) && wj != DP_SETTLE_FLAT)
				continue;
			/* a face turned from i's normal by more than the angle (one
			 * within it would have passed its depth on) and at most
			 * about 60 degrees */
			float c = cosine(normal, i, (size_t)j);
			if (!(c >= DP_FLAT_CROSS_COS && c < f->min_cos))
				continue;
			/* where the line meets the plane through j's inner point
			 * across n_j, crossing it no more obliquely than the faces
			 * are turned */
			float ahead = 0.0f, along = 0.0f;
			for (int d = 0; d < 3; d++) {
				ahead += (p[d][i] - q[d][j]) * normal[d][j];
				along -= u[d] * normal[d][j];
			}
			if (ahead > 0.0f && along >= DP_FLAT_CROSS_COS)
				t[nt++] = ahead / along;
		}
		if (nt >= DP_FLAT_CROSS_MIN)
			f->cross[i] = median(t, (size_t)nt);
	}
}

size_t dp_flat_cross(dp_flat *f, int threads, float *const q[3], unsigned char *settled_by)
{
	if (f->n < 2)
		return 0;
	cross_job job = {f, q, settled_by};
	dp_parallel_for(threads, f->n, FLAT_MIN_ITEMS, cross_range, &job);
	size_t moved = 0;
	for (size_t i = 0; i < f->n; i++) {
		float d = depth(f->p, q, i);
		if (!(f->cross[i] < d))
			continue; /* never deeper */
		lift(f->p, q, i, d, f->cross[i]);
		settled_by[i] = DP_SETTLE_FLAT;
		moved++;
	}
	return moved;
}

void dp_flat_free(dp_flat *f)
{
	dp_kdtree_free(&f->tree);
	free(f->idx);
	free(f->d2);
	free(f->half);
	free(f->face_half);
	free(f->cap);
	free(f->cross);
	free(f->origin);
	free(f->done);
	free(f->heap);
	free(f->sidx);
	free(f->sd2);
	free(f->svalue);
	memset(f, 0, sizeof *f);
}

dp_status dp_flat_init(dp_flat *f, int threads, size_t n, const float *const p[3], const float *const normal[3],
		       double r, double angle_deg, dp_error *err)
{
	memset(f, 0, sizeof *f);
	f->n = n;
	for (int c = 0; c < 3; c++) {
		f->p[c] = p[c];
		f->normal[c] = normal[c];
	}
	if (n < 2)
		return DP_OK;
	int k = n - 1 < DP_FLAT_NEIGHBOURS ? (int)(n - 1) : DP_FLAT_NEIGHBOURS;
	f->k = k;
	f->idx = dp_alloc_array(n, (size_t)k * sizeof(int));
	f->d2 = dp_alloc_array(n, (size_t)k * sizeof(float));
	f->half = dp_alloc_array(n, sizeof(float));
	f->face_half = dp_alloc_array(n, sizeof(float));
	f->cap = dp_alloc_array(n, sizeof(float));
	f->cross = dp_alloc_array(n, sizeof(float));
	f->origin = dp_alloc_array(n, sizeof(uint32_t));
	f->done = malloc(n);
	/* every sample enters once as an origin or once per link that lowers it */
	f->heap = dp_alloc_array(n, ((size_t)k + 1) * sizeof(entry));
	/* search buffers, one set per range (a few hundred kB at most) */
	f->sidx = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_BAND_COUNT * sizeof(uint32_t));
	f->sd2 = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_BAND_COUNT * sizeof(float));
	f->svalue = dp_alloc_array(DP_PARALLEL_MAX, DP_FLAT_BAND_COUNT * sizeof(float));
	dp_knn knn = {0};
	dp_status st = DP_OK;
	if (!f->idx || !f->d2 || !f->half || !f->face_half || !f->cap || !f->cross || !f->origin || !f->done || !f->heap ||
	    !f->sidx || !f->sd2 || !f->svalue) {
		st = dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for the flat-face depths of %zu points", n);
		goto out;
	}
	if ((st = dp_knn_build(&knn, n, p[0], p[1], p[2], err)) != DP_OK ||
	    (st = dp_knn_self(&knn, k, f->idx, f->d2, err)) != DP_OK ||
	    (st = dp_kdtree_build(&f->tree, n, p[0], p[1], p[2], err)) != DP_OK)
		goto out;
	f->min_cos = (float)cos(angle_deg * M_PI / 180.0);
	f->sin_a = (float)sin(angle_deg * M_PI / 180.0);
	f->band_end = (float)(DP_FLAT_BAND_END_R * r);
	f->rim2 = (float)(DP_FLAT_RIM_R * r * DP_FLAT_RIM_R * r);
	f->band2 = (float)(DP_FLAT_BAND_R * r * DP_FLAT_BAND_R * r);
	f->link2 = (float)(DP_FLAT_LINK_R * r * DP_FLAT_LINK_R * r);
	f->below_min = (float)(DP_FLAT_BAND_BELOW_R * r);
	dp_parallel_for(threads, n, FLAT_MIN_ITEMS, band_range, f);
	dp_parallel_for(threads, n, FLAT_MIN_ITEMS, band_median_range, f);
	for (size_t i = 0; i < n; i++)
		f->cap[i] = INFINITY;
out:
	dp_knn_free(&knn);
	if (st != DP_OK)
		dp_flat_free(f);
	return st;
}

dp_status dp_flat_cap(int threads, size_t n, const float *const p[3], const float *const normal[3], float *const q[3],
		      unsigned char *settled_by, double r, double angle_deg, size_t *capped, dp_error *err)
{
	*capped = 0;
	dp_flat f;
	dp_status st = dp_flat_init(&f, threads, n, p, normal, r, angle_deg, err);
	if (st != DP_OK)
		return st;
	dp_flat_update(&f, threads, q, settled_by);
	for (size_t i = 0; i < n; i++)
		if ((settled_by[i] == DP_SETTLE_SLOW || settled_by[i] == DP_SETTLE_WIDTH) && dp_flat_too_deep(&f, q, i, 1.0f)) {
			settled_by[i] = DP_SETTLE_FLAT;
			(*capped)++;
		}
	*capped += dp_flat_cross(&f, threads, q, settled_by);
	dp_flat_free(&f);
	return DP_OK;
}
