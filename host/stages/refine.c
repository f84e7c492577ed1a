/* Point insertion for the coarse-to-fine surface. Midpoints of the edges of
 * a nearest-neighbour graph are what subdivision of a triangulation inserts:
 * about three per point, each at least half an edge from the ends. Edges
 * much longer than the median span gaps, where the tangent-plane spacing is
 * largest, and are always split, as EAR (Huang et al. 2013) inserts into the
 * largest empty circle first; the rest are chosen evenly at random, so a
 * level that adds less than a full subdivision does not leave a density step
 * between regions. The surface stage then relaxes the set at the new
 * spacing. */
#include "stages/refine.h"

#include "core/common.h"
#include "grid/hash.h"
#include "knn/kdtree.h"
#include "knn/knn.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Neighbours per point whose edges are candidates: the Delaunay ring of an
 * even sampling has about six, two more catch uneven spots. */
#define EDGE_NEIGHBOURS 8
/* A midpoint nearer than this (in r) to a point or an accepted midpoint is
 * skipped: adjacent edge midpoints of an even sampling are 0.5 r apart,
 * while a non-Delaunay edge's midpoint coincides with a shorter edge's or
 * with a point. */
#define MIN_GAP_R 0.4
/* Edges this much longer than the median span a gap (a hole left by the
 * coarse level, a sparse patch): their midpoints are always kept. */
#define LONG_EDGE 1.5
/* Seed of the choice among ordinary edges, so runs repeat exactly. */
#define CHOICE_SEED 0x5eed

typedef struct edge {
	float len;    /* tangent-plane length */
	uint32_t a, b;
} edge;

static int longest_first(const void *pa, const void *pb)
{
	const edge *x = pa, *y = pb;
	if (x->len != y->len)
		return x->len < y->len ? 1 : -1;
	if (x->a != y->a)
		return x->a < y->a ? -1 : 1;
	return (x->b > y->b) - (x->b < y->b);
}

/* Whether any hashed point lies within h->cell of (x, y, z). */
static int hash_near(const dp_hash *h, const dp_cloud *c, float x, float y, float z)
{
	int64_t ci = dp_hash_cell(h, x), cj = dp_hash_cell(h, y), ck = dp_hash_cell(h, z);
	float gap2 = h->cell * h->cell;
	for (int64_t i = ci - 1; i <= ci + 1; i++)
		for (int64_t j = cj - 1; j <= cj + 1; j++)
			for (int64_t k = ck - 1; k <= ck + 1; k++)
				for (uint32_t p = h->head[dp_hash_bucket(h, i, j, k)]; p != DP_HASH_NONE; p = h->next[p]) {
					float dx = c->x[p] - x, dy = c->y[p] - y, dz = c->z[p] - z;
					if (dx * dx + dy * dy + dz * dz < gap2)
						return 1;
				}
	return 0;
}

/* Unit normal of the edge (the ends' mean) and its tangent-plane length;
 * 0 when the ends face away from each other (opposite sides of a thin part)
 * and the edge must not be split. */
static float edge_length(const dp_cloud *s, uint32_t a, uint32_t b, float nrm[3])
{
	float na[3] = {s->nx[a], s->ny[a], s->nz[a]}, nb[3] = {s->nx[b], s->ny[b], s->nz[b]};
	if (na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2] <= 0.0f)
		return 0.0f;
	float norm = 0.0f;
	for (int c = 0; c < 3; c++) {
		nrm[c] = na[c] + nb[c];
		norm += nrm[c] * nrm[c];
	}
	norm = sqrtf(norm);
	float d[3] = {s->x[b] - s->x[a], s->y[b] - s->y[a], s->z[b] - s->z[a]}, dn = 0.0f, t2 = 0.0f;
	for (int c = 0; c < 3; c++) {
		nrm[c] /= norm;
		dn += d[c] * nrm[c];
	}
	for (int c = 0; c < 3; c++)
		t2 += (d[c] - dn * nrm[c]) * (d[c] - dn * nrm[c]);
	return sqrtf(t2);
}

/* The midpoint of edge (a, b), lifted off the chord by the cubic Hermite
 * estimate from the two normals, ((n_b - n_a)·(p_b - p_a)) / 8 along the mean
 * normal: on a circle of radius R it is R sin²φ / 2 for a chord of half-angle
 * φ, close to the sagitta R (1 - cos φ). `nrm` (may be NULL) receives the
 * mean normal. */
static void midpoint(const dp_cloud *s, uint32_t a, uint32_t b, float mid[3], float *nrm_out)
{
	float nrm[3];
	edge_length(s, a, b, nrm);
	float d[3] = {s->x[b] - s->x[a], s->y[b] - s->y[a], s->z[b] - s->z[a]};
	float dn[3] = {s->nx[b] - s->nx[a], s->ny[b] - s->ny[a], s->nz[b] - s->nz[a]};
	float lift = (dn[0] * d[0] + dn[1] * d[1] + dn[2] * d[2]) / 8.0f;
	mid[0] = 0.5f * (s->x[a] + s->x[b]) + lift * nrm[0];
	mid[1] = 0.5f * (s->y[a] + s->y[b]) + lift * nrm[1];
	mid[2] = 0.5f * (s->z[a] + s->z[b]) + lift * nrm[2];
	if (nrm_out)
		memcpy(nrm_out, nrm, sizeof nrm);
}

/* Squared distance of inner end j from the line through `mid` along `nrm`. */
static float line_distance2(const dp_cloud *k, uint32_t j, const float mid[3], const float nrm[3])
{
	float v[3] = {mid[0] - k->x[j], mid[1] - k->y[j], mid[2] - k->z[j]};
	float t = v[0] * nrm[0] + v[1] * nrm[1] + v[2] * nrm[2];
	return fmaxf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - t * t, 0.0f);
}

/* Appends the midpoint of edge (a, b) as row i of both clouds, with the mean
 * normal. The inner end is one of the two ends' inner ends, the one nearer
 * the new point's normal line, as re-attachment would choose: never their
 * mean. The mean of two skeleton points lies off the skeleton wherever they
 * are far apart (a ball's skeleton is one spot with a few stragglers a few r
 * off), and every such mean is a new re-attachment target between them: on
 * one-view spheres at 8000 deep points the inner ends of a third of the
 * points walked out along such bridges within one level, and coverage ranged
 * 0.86-0.99 over the scan's noise seeds (0.991-0.999 with this choice). */
static void append_midpoint(dp_cloud *s, dp_cloud *k, uint32_t a, uint32_t b, size_t i)
{
	float mid[3], nrm[3];
	midpoint(s, a, b, mid, nrm);
	s->x[i] = mid[0], s->y[i] = mid[1], s->z[i] = mid[2];
	s->nx[i] = nrm[0], s->ny[i] = nrm[1], s->nz[i] = nrm[2];
	uint32_t end = line_distance2(k, b, mid, nrm) < line_distance2(k, a, mid, nrm) ? b : a;
	k->x[i] = k->x[end];
	k->y[i] = k->y[end];
	k->z[i] = k->z[end];
	if (k->nx) {
		k->nx[i] = nrm[0];
		k->ny[i] = nrm[1];
		k->nz[i] = nrm[2];
	}
}

static int ascending(const void *pa, const void *pb)
{
	uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
	return (a > b) - (a < b);
}

/* Chooses `keep` of the `count` accepted edges (ordered longest first, the
 * first `long_count` of them across gaps), compacting `chosen` in place:
 * every gap edge first, then an even random choice among the others.
 * Longest-first alone would subdivide whole regions fully and others not at
 * all, a density step that a few relaxing iterations do not even out
 * (measured: one-view sphere at 8000 points, coverage 0.87). */
static size_t choose(uint32_t *chosen, size_t count, size_t long_count, size_t keep, uint32_t *order)
{
	if (keep >= count)
		return count;
	if (keep <= long_count)
		return keep;
	size_t rest = count - long_count, want = keep - long_count;
	dp_rng rng;
	dp_rng_seed(&rng, CHOICE_SEED);
	for (size_t i = 0; i < rest; i++)
		order[i] = (uint32_t)i;
	for (size_t i = 0; i < want; i++) {
		size_t j = i + (size_t)(dp_rng_uniform(&rng) * (double)(rest - i));
		if (j >= rest)
			j = rest - 1;
		uint32_t t = order[i];
		order[i] = order[j];
		order[j] = t;
	}
	qsort(order, want, sizeof *order, ascending);
	for (size_t i = 0; i < want; i++)
		chosen[long_count + i] = chosen[long_count + order[i]];
	return keep;
}

/* One pass: inserts up to target - n midpoints, the gap test at the current
 * spacing (Eq. 1 from the pass's own nearest neighbours). */
static dp_status insert_pass(dp_cloud *s, dp_cloud *k, size_t target, size_t *added, dp_error *err)
{
	size_t n = s->n, ne = 0;
	*added = 0;
	if (n < 2)
		return DP_OK;
	int kk = n - 1 < EDGE_NEIGHBOURS ? (int)(n - 1) : EDGE_NEIGHBOURS;
	size_t cap = n * (size_t)kk, all = n + cap;
	dp_knn knn = {0};
	int *idx = dp_alloc_array(cap, sizeof(int));
	float *d2 = dp_alloc_array(cap, sizeof(float));
	edge *edges = dp_alloc_array(cap, sizeof(edge));
	uint32_t *chosen = dp_alloc_array(cap, sizeof(uint32_t)), *order = dp_alloc_array(cap, sizeof(uint32_t));
	/* the gap test's points: the existing ones, then the accepted midpoints */
	dp_cloud pts = {0};
	dp_hash h = {0};
	dp_status st = DP_OK;
	if (!idx || !d2 || !edges || !chosen || !order || dp_hash_alloc(&h, all, 0.0f, err) != DP_OK ||
	    dp_cloud_alloc(&pts, all, 0, err) != DP_OK) {
		st = dp_fail(err, DP_ERR_NOMEM, "refine: out of memory for %zu points", all);
		goto out;
	}
	if ((st = dp_knn_build(&knn, n, s->x, s->y, s->z, err)) != DP_OK ||
	    (st = dp_knn_self(&knn, kk, idx, d2, err)) != DP_OK)
		goto out;
	double spacing = 0.0;
	for (size_t i = 0; i < n; i++)
		spacing += idx[i * (size_t)kk] >= 0 ? sqrt((double)d2[i * (size_t)kk]) : 0.0;
	h.cell = (float)(MIN_GAP_R * spacing / (double)n);
	if (!(h.cell > 0.0f))
		goto out; /* every point coincides with another: nowhere to insert */
	for (size_t i = 0; i < n; i++)
		for (int j = 0; j < kk; j++) {
			int o = idx[i * (size_t)kk + (size_t)j];
			if (o < 0 || (size_t)o == i)
				continue;
			float nrm[3];
			uint32_t a = (uint32_t)(i < (size_t)o ? i : (size_t)o), b = (uint32_t)(i < (size_t)o ? (size_t)o : i);
			float len = edge_length(s, a, b, nrm);
			if (len > 0.0f)
				edges[ne++] = (edge){len, a, b};
		}
	if (ne == 0)
		goto out;
	qsort(edges, ne, sizeof *edges, longest_first);
	float long_len = (float)LONG_EDGE * edges[ne / 2].len;
	memcpy(pts.x, s->x, n * sizeof(float));
	memcpy(pts.y, s->y, n * sizeof(float));
	memcpy(pts.z, s->z, n * sizeof(float));
	for (size_t i = 0; i < n; i++)
		dp_hash_insert(&h, (uint32_t)i, pts.x[i], pts.y[i], pts.z[i]);
	size_t count = 0, long_count = 0;
	for (size_t e = 0; e < ne; e++) {
		if (e > 0 && edges[e].a == edges[e - 1].a && edges[e].b == edges[e - 1].b)
			continue; /* the same edge seen from its other end */
		size_t row = n + count;
		float mid[3];
		midpoint(s, edges[e].a, edges[e].b, mid, NULL);
		if (hash_near(&h, &pts, mid[0], mid[1], mid[2]))
			continue;
		pts.x[row] = mid[0], pts.y[row] = mid[1], pts.z[row] = mid[2];
		dp_hash_insert(&h, (uint32_t)row, mid[0], mid[1], mid[2]);
		chosen[count++] = (uint32_t)e;
		long_count += edges[e].len >= long_len;
	}
	size_t kept = choose(chosen, count, long_count, target - n, order);
	for (size_t c = 0; c < kept; c++)
		append_midpoint(s, k, edges[chosen[c]].a, edges[chosen[c]].b, n + c);
	*added = kept;
	s->n = k->n = n + kept;
out:
	dp_knn_free(&knn);
	dp_cloud_free(&pts);
	free(idx);
	free(d2);
	free(edges);
	free(chosen);
	free(order);
	dp_hash_free(&h);
	return st;
}

dp_status dp_refine_insert(dp_cloud *surface, dp_cloud *skeleton, size_t target, size_t *added, dp_error *err)
{
	*added = 0;
	if (!surface->nx || surface->n != skeleton->n)
		return dp_fail(err, DP_ERR_ARG, "refine: bad deep points (no normals, or the counts differ)");
	while (surface->n < target) {
		size_t pass = 0;
		dp_status st = insert_pass(surface, skeleton, target, &pass, err);
		if (st != DP_OK)
			return st;
		if (pass == 0)
			break;
		*added += pass;
	}
	return DP_OK;
}

int dp_refine_levels(size_t coarse, size_t target, double level_factor, size_t *counts, int max_levels)
{
	if (coarse == 0 || coarse >= target || !(level_factor > 1.0)) {
		counts[0] = target;
		return 1;
	}
	double ratio = (double)target / (double)coarse;
	int steps = (int)ceil(log(ratio) / log(level_factor) - 1e-9);
	if (steps < 1)
		steps = 1;
	if (steps > max_levels - 1)
		steps = max_levels - 1;
	double f = pow(ratio, 1.0 / steps);
	counts[0] = coarse;
	for (int l = 1; l < steps; l++)
		counts[l] = (size_t)llround((double)coarse * pow(f, l));
	counts[steps] = target;
	return steps + 1;
}

/* Share of the points one even-spacing round moves at most: 0.05 left the
 * one-view bunny's spacing variation at 0.44 after 3 rounds, 0.1 took it to
 * 0.35 (WLOP seeds 1-6, on a draft that relaxed 15 iterations per round and
 * counted the new midpoints in the density; README (33)). */
#define EVEN_MOVE_FRACTION 0.1
/* A point is removed only where its local spacing is below this fraction of
 * the even spacing the same points would have over the same area: the
 * one-view bunny's scanned side sits at about 0.73 of it, its completed side
 * above 1. At 0.7 the scanned side was barely thinned (spacing variation 0.38
 * against 0.35, the same draft). */
#define EVEN_DENSE 0.85

typedef struct spaced {
	float s;
	uint32_t i;
} spaced;

static int densest_first(const void *pa, const void *pb)
{
	const spaced *x = pa, *y = pb;
	if (x->s != y->s)
		return x->s < y->s ? -1 : 1;
	return (x->i > y->i) - (x->i < y->i);
}

static void copy_row(dp_cloud *dst, size_t di, const dp_cloud *src, size_t si)
{
	dst->x[di] = src->x[si], dst->y[di] = src->y[si], dst->z[di] = src->z[si];
	if (dst->nx && src->nx)
		dst->nx[di] = src->nx[si], dst->ny[di] = src->ny[si], dst->nz[di] = src->nz[si];
}

/* Lists in `order` up to `most` of the n points whose mean distance to their
 * kk nearest neighbours is below EVEN_DENSE times the even spacing, densest
 * first, never two neighbours in one round (so a dense patch thins evenly
 * instead of opening a hole); returns how many it listed. `blocked` has n
 * entries of scratch. */
static size_t list_densest(size_t n, int kk, const int *idx, const float *d2, size_t most, spaced *sp,
			   unsigned char *blocked, uint32_t *order)
{
	double area = 0.0;
	size_t measured = 0;
	for (size_t i = 0; i < n; i++) {
		double sum = 0.0;
		int c = 0;
		for (int j = 0; j < kk; j++)
			if (idx[i * (size_t)kk + (size_t)j] >= 0) {
				sum += sqrt((double)d2[i * (size_t)kk + (size_t)j]);
				c++;
			}
		sp[i] = (spaced){c ? (float)(sum / c) : INFINITY, (uint32_t)i};
		if (c) {
			area += (sum / c) * (sum / c);
			measured++;
		}
	}
	if (!measured)
		return 0;
	float limit = (float)(EVEN_DENSE * sqrt(area / (double)measured));
	qsort(sp, n, sizeof *sp, densest_first);
	memset(blocked, 0, n);
	size_t marked = 0;
	for (size_t o = 0; o < n && marked < most && sp[o].s < limit; o++) {
		uint32_t i = sp[o].i;
		if (blocked[i])
			continue;
		blocked[i] = 1;
		order[marked++] = i;
		for (int j = 0; j < kk; j++) {
			int nb = idx[i * (size_t)kk + (size_t)j];
			if (nb >= 0)
				blocked[nb] = 1;
		}
	}
	return marked;
}

dp_status dp_refine_even(dp_cloud *surface, dp_cloud *skeleton, unsigned char *replaced, size_t *moved,
			 dp_error *err)
{
	*moved = 0;
	size_t n = surface->n, moves = (size_t)(EVEN_MOVE_FRACTION * (double)n);
	if (!surface->nx || n != skeleton->n)
		return dp_fail(err, DP_ERR_ARG, "refine: bad deep points (no normals, or the counts differ)");
	int kk = EDGE_NEIGHBOURS;
	if (moves == 0 || n <= (size_t)kk)
		return DP_OK;
	dp_cloud ts = {0}, tk = {0};
	dp_knn knn = {0};
	int *idx = dp_alloc_array(n * (size_t)kk, sizeof(int));
	float *d2 = dp_alloc_array(n * (size_t)kk, sizeof(float));
	spaced *sp = dp_alloc_array(n, sizeof(spaced));
	unsigned char *blocked = dp_alloc_array(n, 1);
	uint32_t *order = dp_alloc_array(moves, sizeof(uint32_t));
	dp_status st = DP_OK;
	if (!idx || !d2 || !sp || !blocked || !order) {
		st = dp_fail(err, DP_ERR_NOMEM, "refine: out of memory for %zu points", n);
		goto out;
	}
	/* the density is the current points' own: the midpoints about to be
	 * inserted are dense spots of their own, and counting them would
	 * shuffle an even sampling instead of leaving it alone */
	if ((st = dp_knn_build(&knn, n, surface->x, surface->y, surface->z, err)) != DP_OK ||
	    (st = dp_knn_self(&knn, kk, idx, d2, err)) != DP_OK)
		goto out;
	size_t removing = list_densest(n, kk, idx, d2, moves, sp, blocked, order);
	if (removing == 0)
		goto out;
	if (dp_cloud_alloc(&ts, n + removing, 1, err) != DP_OK ||
	    dp_cloud_alloc(&tk, n + removing, skeleton->nx != NULL, err) != DP_OK) {
		st = dp_fail(err, DP_ERR_NOMEM, "refine: out of memory for %zu points", n + removing);
		goto out;
	}
	for (size_t i = 0; i < n; i++) {
		copy_row(&ts, i, surface, i);
		copy_row(&tk, i, skeleton, i);
	}
	ts.n = tk.n = n;
	/* inserted before the removals open holes in the dense regions, whose
	 * edges would compete with the sparse regions' */
	size_t added = 0;
	if ((st = dp_refine_insert(&ts, &tk, n + removing, &added, err)) != DP_OK)
		goto out;
	/* Each new point takes the row of a removed one, densest first, so every
	 * other row keeps its index: the inside test's balls name the rows of
	 * the deep points grown from their samples (dp_consolidate). Listed
	 * points beyond those inserted stay: there was nowhere to put them. */
	for (size_t o = 0; o < added; o++) {
		copy_row(surface, order[o], &ts, n + o);
		copy_row(skeleton, order[o], &tk, n + o);
		if (replaced)
			replaced[order[o]] = 1;
	}
	*moved = added;
out:
	dp_knn_free(&knn);
	dp_cloud_free(&ts);
	dp_cloud_free(&tk);
	free(idx);
	free(d2);
	free(sp);
	free(blocked);
	free(order);
	return st;
}

static int cmp_u32(const void *a, const void *b)
{
	uint32_t u = *(const uint32_t *)a, v = *(const uint32_t *)b;
	return (u > v) - (u < v);
}

/* The unpicked points of farthest-point sampling as a binary max-heap on
 * their squared distance to the subset, ties to the lower index: the order
 * in which the plain scan (refine.h) would take them. */
typedef struct far_heap {
	const double *key;
	uint32_t *item; /* heap order */
	uint32_t *pos;  /* per point: its place in item, or NOT_IN_HEAP */
	size_t n;
} far_heap;

#define NOT_IN_HEAP UINT32_MAX

static int ahead(const far_heap *h, uint32_t a, uint32_t b)
{
	return h->key[a] > h->key[b] || (h->key[a] == h->key[b] && a < b);
}

static void place(far_heap *h, size_t k, uint32_t i)
{
	h->item[k] = i;
	h->pos[i] = (uint32_t)k;
}

/* Moves the item at k down to its place: keys only fall. */
static void sift_down(far_heap *h, size_t k)
{
	uint32_t i = h->item[k];
	for (;;) {
		size_t c = 2 * k + 1;
		if (c >= h->n)
			break;
		if (c + 1 < h->n && ahead(h, h->item[c + 1], h->item[c]))
			c++;
		if (!ahead(h, h->item[c], i))
			break;
		place(h, k, h->item[c]);
		k = c;
	}
	place(h, k, i);
}

static uint32_t pop(far_heap *h)
{
	uint32_t top = h->item[0];
	h->pos[top] = NOT_IN_HEAP;
	if (--h->n > 0) {
		place(h, 0, h->item[h->n]);
		sift_down(h, 0);
	}
	return top;
}

/* A squared distance within this share of the subset's farthest is searched
 * for: the tree sums squares in float, a few units in the 7th digit off the
 * double sums here. */
#define SEARCH_SLACK 1e-5

dp_status dp_refine_subset(size_t n, const float *x, const float *y, const float *z, size_t m, uint32_t *keep,
			   dp_error *err)
{
	if (m == 0)
		return DP_OK;
	if (m > n || n >= UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "refine: a subset of %zu from %zu points", m, n);
	/* squared distance of every point to the nearest one picked */
	double *near = dp_alloc_array(n, sizeof *near);
	uint32_t *item = dp_alloc_array(n, sizeof *item), *pos = dp_alloc_array(n, sizeof *pos);
	uint32_t *found = dp_alloc_array(n, sizeof *found);
	float *d2 = dp_alloc_array(n, sizeof *d2);
	dp_kdtree tree = {0};
	dp_status st = DP_OK;
	if (!near || !item || !pos || !found || !d2) {
		st = dp_fail(err, DP_ERR_NOMEM, "refine: out of memory choosing %zu of %zu points", m, n);
		goto out;
	}
	if ((st = dp_kdtree_build(&tree, n, x, y, z, err)) != DP_OK)
		goto out;
	/* every key infinite: index order is heap order */
	far_heap h = {near, item, pos, n};
	for (size_t i = 0; i < n; i++) {
		near[i] = INFINITY;
		place(&h, i, (uint32_t)i);
	}
	for (size_t k = 0; k < m; k++) {
		uint32_t pick = pop(&h);
		keep[k] = pick;
		if (h.n == 0)
			break;
		/* only points nearer the pick than to the subset move, and none
		 * lies farther from the subset than the heap's top */
		double reach = near[h.item[0]] * (1.0 + SEARCH_SLACK);
		/* beyond a float's range (the first picks: infinite) every point */
		int all = !(reach < FLT_MAX);
		size_t count = all ? n
				   : dp_kdtree_nearest_within(&tree, x[pick], y[pick], z[pick], (float)reach + FLT_MIN, n,
							      found, d2);
		for (size_t j = 0; j < count; j++) {
			uint32_t i = all ? (uint32_t)j : found[j];
			if (pos[i] == NOT_IN_HEAP)
				continue;
			double dx = (double)x[i] - x[pick], dy = (double)y[i] - y[pick], dz = (double)z[i] - z[pick];
			double dd = dx * dx + dy * dy + dz * dz;
			if (dd < near[i]) {
				near[i] = dd;
				sift_down(&h, pos[i]);
			}
		}
	}
	qsort(keep, m, sizeof *keep, cmp_u32);
out:
	dp_kdtree_free(&tree);
	free(near);
	free(item);
	free(pos);
	free(found);
	free(d2);
	return st;
}
