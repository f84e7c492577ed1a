#include "tools/bvh.h"

#include "core/common.h"
#include "tools/mesh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3])
{
	out[0] = a[1] * b[2] - a[2] * b[1];
	out[1] = a[2] * b[0] - a[0] * b[2];
	out[2] = a[0] * b[1] - a[1] * b[0];
}

int dp_ray_triangle(const double o[3], const double d[3], const double a[3], const double e1[3],
		    const double e2[3], double *t)
{
	double pvec[3], qvec[3], tvec[3] = {o[0] - a[0], o[1] - a[1], o[2] - a[2]};
	cross3(d, e2, pvec);
	double det = dot3(e1, pvec);
	if (det == 0)
		return 0;
	double inv = 1.0 / det;
	double u = dot3(tvec, pvec) * inv;
	if (u < 0 || u > 1)
		return 0;
	cross3(tvec, e1, qvec);
	double v = dot3(d, qvec) * inv;
	if (v < 0 || u + v > 1)
		return 0;
	double hit = dot3(e2, qvec) * inv;
	if (!(hit > 0))
		return 0;
	*t = hit;
	return 1;
}

static void closest_point_segment(const double p[3], const double a[3], const double b[3], double out[3])
{
	double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
	double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
	double len2 = dot3(ab, ab);
	double s = len2 > 0 ? dot3(ap, ab) / len2 : 0;
	s = s < 0 ? 0 : (s > 1 ? 1 : s);
	for (int k = 0; k < 3; k++)
		out[k] = a[k] + s * ab[k];
}

static double dist2(const double a[3], const double b[3])
{
	double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
	return dx * dx + dy * dy + dz * dz;
}

/* A collinear triangle is the union of its edges. */
static void closest_point_degenerate(const double p[3], const double a[3], const double b[3],
				     const double c[3], double out[3])
{
	const double *ends[3][2] = {{a, b}, {b, c}, {c, a}};
	double best = INFINITY, q[3];
	for (int e = 0; e < 3; e++) {
		closest_point_segment(p, ends[e][0], ends[e][1], q);
		double d2 = dist2(p, q);
		if (d2 < best) {
			best = d2;
			memcpy(out, q, sizeof q);
		}
	}
}

void dp_closest_point_triangle(const double p[3], const double a[3], const double b[3],
			       const double c[3], double out[3])
{
	double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
	double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
	double n[3];
	cross3(ab, ac, n);
	if (dot3(n, n) <= DBL_EPSILON * DBL_EPSILON * dot3(ab, ab) * dot3(ac, ac)) {
		closest_point_degenerate(p, a, b, c, out);
		return;
	}
	double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
	double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
	if (d1 <= 0 && d2 <= 0) {
		memcpy(out, a, 3 * sizeof(double));
		return;
	}
	double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
	double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
	if (d3 >= 0 && d4 <= d3) {
		memcpy(out, b, 3 * sizeof(double));
		return;
	}
	double vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0) {
		double v = d1 / (d1 - d3);
		for (int k = 0; k < 3; k++)
			out[k] = a[k] + v * ab[k];
		return;
	}
	double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
	double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
	if (d6 >= 0 && d5 <= d6) {
		memcpy(out, c, 3 * sizeof(double));
		return;
	}
	double vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0) {
		double w = d2 / (d2 - d6);
		for (int k = 0; k < 3; k++)
			out[k] = a[k] + w * ac[k];
		return;
	}
	double va = d3 * d6 - d5 * d4;
	if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
		double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
		for (int k = 0; k < 3; k++)
			out[k] = b[k] + w * (c[k] - b[k]);
		return;
	}
	double denom = 1.0 / (va + vb + vc);
	double v = vb * denom, w = vc * denom;
	for (int k = 0; k < 3; k++)
		out[k] = a[k] + v * ab[k] + w * ac[k];
}

/* ------------------------------------------------------------------ build */

typedef struct builder {
	dp_bvh *bvh;
	const dp_cloud *mesh;
	const double *centroid; /* 3 per face */
	uint32_t *ids;          /* faces in slot order, permuted by the splits */
} builder;

static void swap_ids(uint32_t *ids, size_t i, size_t j)
{
	uint32_t t = ids[i];
	ids[i] = ids[j];
	ids[j] = t;
}

static double median3(double a, double b, double c)
{
	if (a > b) {
		double t = a;
		a = b;
		b = t;
	}
	return c < a ? a : (c > b ? b : c);
}

/* Reorders ids[0..n) so that ids[k] has the k-th smallest key and nothing
 * before it is larger (quickselect, three-way partition so that many equal
 * keys cannot make it quadratic). */
static void select_nth(uint32_t *ids, size_t n, size_t k, const double *centroid, int axis)
{
	size_t lo = 0, hi = n;
	while (hi - lo > 1) {
		double pivot = median3(centroid[3 * ids[lo] + axis], centroid[3 * ids[lo + (hi - lo) / 2] + axis],
				       centroid[3 * ids[hi - 1] + axis]);
		size_t lt = lo, i = lo, gt = hi;
		while (i < gt) {
			double v = centroid[3 * ids[i] + axis];
			if (v < pivot)
				swap_ids(ids, lt++, i++);
			else if (v > pivot)
				swap_ids(ids, i, --gt);
			else
				i++;
		}
		if (k < lt)
			hi = lt;
		else if (k >= gt)
			lo = gt;
		else
			return;
	}
}

static uint32_t build_node(builder *b, size_t begin, size_t end)
{
	dp_bvh *bvh = b->bvh;
	uint32_t index = (uint32_t)bvh->nnodes++;
	dp_bvh_node *node = &bvh->nodes[index];
	double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
	for (int d = 0; d < 3; d++) {
		node->lo[d] = INFINITY;
		node->hi[d] = -INFINITY;
	}
	for (size_t s = begin; s < end; s++) {
		double v[3][3];
		dp_mesh_triangle(b->mesh, b->ids[s], v[0], v[1], v[2]);
		for (int d = 0; d < 3; d++) {
			for (int k = 0; k < 3; k++) {
				node->lo[d] = fmin(node->lo[d], v[k][d]);
				node->hi[d] = fmax(node->hi[d], v[k][d]);
			}
			clo[d] = fmin(clo[d], b->centroid[3 * b->ids[s] + d]);
			chi[d] = fmax(chi[d], b->centroid[3 * b->ids[s] + d]);
		}
	}
	if (end - begin <= DP_BVH_LEAF_SIZE) {
		node->first = (uint32_t)begin;
		node->count = (uint32_t)(end - begin);
		return index;
	}
	int axis = 0;
	for (int d = 1; d < 3; d++)
		if (chi[d] - clo[d] > chi[axis] - clo[axis])
			axis = d;
	size_t mid = begin + (end - begin) / 2;
	select_nth(b->ids + begin, end - begin, mid - begin, b->centroid, axis);
	node->count = 0;
	build_node(b, begin, mid);
	uint32_t right = build_node(b, mid, end);
	/* build_node may not move the array (it is allocated at its maximum size),
	 * so `node` is still valid here. */
	node->first = right;
	return index;
}

dp_status dp_bvh_build(dp_bvh *bvh, const dp_cloud *mesh, dp_error *err)
{
	memset(bvh, 0, sizeof *bvh);
	size_t n = mesh->nfaces;
	if (n == 0 || n > UINT32_MAX / 2)
		return dp_fail(err, DP_ERR_ARG, "bvh: %zu faces is out of range", n);
	/* A binary tree with at least one face per leaf has fewer than 2n nodes. */
	bvh->nodes = dp_alloc_array(2 * n, sizeof(dp_bvh_node));
	bvh->face = dp_alloc_array(n, sizeof(uint32_t));
	bvh->tri = dp_alloc_array(9 * n, sizeof(double));
	double *centroid = dp_alloc_array(3 * n, sizeof(double));
	if (!bvh->nodes || !bvh->face || !bvh->tri || !centroid) {
		free(centroid);
		dp_bvh_free(bvh);
		return dp_fail(err, DP_ERR_NOMEM, "bvh: out of memory for %zu faces", n);
	}
	for (size_t f = 0; f < n; f++) {
		double a[3], b[3], c[3];
		dp_mesh_triangle(mesh, f, a, b, c);
		for (int d = 0; d < 3; d++)
			centroid[3 * f + d] = (a[d] + b[d] + c[d]) / 3.0;
		bvh->face[f] = (uint32_t)f;
	}
	builder b = {bvh, mesh, centroid, bvh->face};
	build_node(&b, 0, n);
	free(centroid);
	for (size_t s = 0; s < n; s++) {
		double a[3], bb[3], c[3], *t = bvh->tri + 9 * s;
		dp_mesh_triangle(mesh, bvh->face[s], a, bb, c);
		for (int d = 0; d < 3; d++) {
			t[d] = a[d];
			t[3 + d] = bb[d] - a[d];
			t[6 + d] = c[d] - a[d];
		}
	}
	bvh->ntris = n;
	return DP_OK;
}

void dp_bvh_free(dp_bvh *bvh)
{
	if (!bvh)
		return;
	free(bvh->nodes);
	free(bvh->face);
	free(bvh->tri);
	memset(bvh, 0, sizeof *bvh);
}

/* ---------------------------------------------------------------- queries */

/* Entry parameter of the ray into the box, or INFINITY when it misses it
 * within (0, tmax]. */
static double box_entry(const dp_bvh_node *node, const double o[3], const double inv[3], double tmax)
{
	double tmin = 0;
	for (int d = 0; d < 3; d++) {
		/* A ray parallel to the slab: (lo - o) * inf is NaN when o lies on
		 * the slab's face, and fmin/fmax would then drop the box. A scan's
		 * rays in the plane of a mesh's edges (a sphere's meridian) lost
		 * every box touching that plane and hit the far side instead. */
		if (isinf(inv[d])) {
			if (o[d] < node->lo[d] || o[d] > node->hi[d])
				return INFINITY;
			continue;
		}
		double t0 = (node->lo[d] - o[d]) * inv[d], t1 = (node->hi[d] - o[d]) * inv[d];
		tmin = fmax(tmin, fmin(t0, t1));
		tmax = fmin(tmax, fmax(t0, t1));
	}
	return tmin <= tmax ? tmin : INFINITY;
}

int dp_bvh_raycast(const dp_bvh *bvh, const double origin[3], const double dir[3], double tmax,
		   dp_bvh_hit *hit)
{
	double inv[3] = {1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]};
	double best = tmax;
	int found = 0;
	uint32_t stack[DP_BVH_MAX_DEPTH];
	int sp = 0;
	if (box_entry(&bvh->nodes[0], origin, inv, best) == INFINITY)
		return 0;
	stack[sp++] = 0;
	while (sp > 0) {
		const dp_bvh_node *node = &bvh->nodes[stack[--sp]];
		if (node->count) {
			for (uint32_t s = node->first; s < node->first + node->count; s++) {
				const double *t = bvh->tri + 9 * (size_t)s;
				double th;
				if (dp_ray_triangle(origin, dir, t, t + 3, t + 6, &th) && th <= best) {
					best = th;
					hit->t = th;
					hit->face = bvh->face[s];
					found = 1;
				}
			}
			continue;
		}
		uint32_t left = (uint32_t)(node - bvh->nodes) + 1, right = node->first;
		double tl = box_entry(&bvh->nodes[left], origin, inv, best);
		double tr = box_entry(&bvh->nodes[right], origin, inv, best);
		/* Push the farther child first so the nearer one is searched first
		 * and shrinks `best` before the other is opened. */
		if (tl > tr) {
			uint32_t u = left;
			left = right;
			right = u;
			double x = tl;
			tl = tr;
			tr = x;
		}
		if (tr != INFINITY)
			stack[sp++] = right;
		if (tl != INFINITY)
			stack[sp++] = left;
	}
	return found;
}

static double box_dist2(const dp_bvh_node *node, const double p[3])
{
	double d2 = 0;
	for (int d = 0; d < 3; d++) {
		double e = fmax(fmax(node->lo[d] - p[d], 0.0), p[d] - node->hi[d]);
		d2 += e * e;
	}
	return d2;
}

double dp_bvh_nearest(const dp_bvh *bvh, const double p[3], double closest[3], uint32_t *face)
{
	double best = INFINITY;
	uint32_t stack[DP_BVH_MAX_DEPTH];
	int sp = 0;
	stack[sp++] = 0;
	while (sp > 0) {
		const dp_bvh_node *node = &bvh->nodes[stack[--sp]];
		if (box_dist2(node, p) >= best)
			continue;
		if (node->count) {
			for (uint32_t s = node->first; s < node->first + node->count; s++) {
				const double *t = bvh->tri + 9 * (size_t)s;
				double b[3], c[3], q[3];
				for (int d = 0; d < 3; d++) {
					b[d] = t[d] + t[3 + d];
					c[d] = t[d] + t[6 + d];
				}
				dp_closest_point_triangle(p, t, b, c, q);
				double d2 = dist2(p, q);
				if (d2 < best) {
					best = d2;
					memcpy(closest, q, sizeof q);
					*face = bvh->face[s];
				}
			}
			continue;
		}
		uint32_t left = (uint32_t)(node - bvh->nodes) + 1, right = node->first;
		double dl = box_dist2(&bvh->nodes[left], p), dr = box_dist2(&bvh->nodes[right], p);
		if (dl > dr) {
			uint32_t u = left;
			left = right;
			right = u;
			double x = dl;
			dl = dr;
			dr = x;
		}
		if (dr < best)
			stack[sp++] = right;
		if (dl < best)
			stack[sp++] = left;
	}
	return best;
}

int dp_bvh_facing_within(const dp_bvh *bvh, const double p[3], double r2, const double n[3])
{
	/* depth-first, one node popped for two pushed: at most one waiting
	 * sibling per level, as in the other queries */
	uint32_t stack[DP_BVH_MAX_DEPTH];
	int sp = 0;
	stack[sp++] = 0;
	while (sp > 0) {
		const dp_bvh_node *node = &bvh->nodes[stack[--sp]];
		if (box_dist2(node, p) > r2)
			continue;
		if (!node->count) {
			stack[sp++] = node->first;
			stack[sp++] = (uint32_t)(node - bvh->nodes) + 1;
			continue;
		}
		for (uint32_t s = node->first; s < node->first + node->count; s++) {
			const double *t = bvh->tri + 9 * (size_t)s;
			double face_n[3], b[3], c[3], q[3];
			cross3(t + 3, t + 6, face_n);
			if (dot3(face_n, n) <= 0.0)
				continue;
			for (int d = 0; d < 3; d++) {
				b[d] = t[d] + t[3 + d];
				c[d] = t[d] + t[6 + d];
			}
			dp_closest_point_triangle(p, t, b, c, q);
			if (dist2(p, q) <= r2)
				return 1;
		}
	}
	return 0;
}
