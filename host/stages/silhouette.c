/* The scan's outline: silhouette.h. */
#include "stages/silhouette.h"
#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Directions tried for the axis, over the half-sphere: about 3° apart,
 * finer than the 10° band they are judged by. */
#define AXIS_DIRECTIONS 2000
/* |n·axis| below sin 10°: the normal lies within 10° of perpendicular. */
#define GRAZING_SIN 0.17364817766693033
/* Every direction that passes must lie within this of the best, or the scan
 * does not say which it was seen along. The bunny's six scans: every
 * passing direction within 10-39° of the best. A box-like object leaves
 * several unrelated directions free of grazing normals (every direction
 * oblique to all its faces): the demo chair's passing directions reach 90°
 * from the best, and on its one-view scan the best lay 40° from the eye,
 * cutting 0.34% of the true surface off (none along the eye's own axis). */
#define AXIS_UNIQUE_COS 0.7071067811865476
/* The grid holds at most this many cells (8 bytes each and 5 more while it
 * is built: 52 MB at most); a finer outline is coarsened. */
#define MAX_CELLS (1 << 22)

/* Direction d of the fixed set: a Fibonacci spiral over z >= 0, an even
 * spread with no cluster at the pole. */
static void direction(int d, float dir[3])
{
	const double golden = M_PI * (3.0 - sqrt(5.0));
	double z = 1.0 - (d + 0.5) / AXIS_DIRECTIONS, s = sqrt(1.0 - z * z), a = golden * d;
	dir[0] = (float)(s * cos(a)), dir[1] = (float)(s * sin(a)), dir[2] = (float)z;
}

/* How many of the normals lie within 10° of perpendicular to dir, and the
 * sum of |n·dir|. */
static size_t grazing_count(size_t n, const float *nx, const float *ny, const float *nz, const float dir[3],
			    double *facing)
{
	size_t count = 0;
	*facing = 0.0;
	for (size_t i = 0; i < n; i++) {
		float c = fabsf(nx[i] * dir[0] + ny[i] * dir[1] + nz[i] * dir[2]);
		count += c < (float)GRAZING_SIN;
		*facing += c;
	}
	return count;
}

void dp_silhouette_axis(size_t n, const float *nx, const float *ny, const float *nz, double grazing, int *found,
			float axis[3], double *fraction)
{
	*found = 0;
	*fraction = 1.0;
	if (n < DP_SILHOUETTE_MIN_NORMALS)
		return;
	float best[3] = {0.0f, 0.0f, 1.0f};
	size_t least = n + 1;
	double most = -1.0;
	for (int d = 0; d < AXIS_DIRECTIONS; d++) {
		float dir[3];
		double facing;
		direction(d, dir);
		size_t count = grazing_count(n, nx, ny, nz, dir, &facing);
		/* ties (several directions with no grazing normal at all) go to the
		 * one the normals face most squarely: the middle of the tied cap,
		 * not whichever the spiral meets first */
		if (count < least || (count == least && facing > most)) {
			least = count, most = facing;
			memcpy(best, dir, sizeof best);
		}
	}
	*fraction = (double)least / (double)n;
	if (*fraction > grazing)
		return;
	/* a second pass, counting again, rather than a table of every count */
	for (int d = 0; d < AXIS_DIRECTIONS; d++) {
		float dir[3];
		double facing;
		direction(d, dir);
		float c = fabsf(dir[0] * best[0] + dir[1] * best[1] + dir[2] * best[2]);
		if (c < (float)AXIS_UNIQUE_COS && (double)grazing_count(n, nx, ny, nz, dir, &facing) <= grazing * (double)n)
			return;
	}
	*found = 1;
	memcpy(axis, best, sizeof best);
}

int dp_silhouette_unit(const double given[3], float axis[3])
{
	/* scaled by its largest component first: squares of 1e200 or 1e-200
	 * would leave double's range */
	double big = fmax(fabs(given[0]), fmax(fabs(given[1]), fabs(given[2])));
	if (!(big > 0.0) || !isfinite(big))
		return 0;
	double g[3] = {given[0] / big, given[1] / big, given[2] / big};
	double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
	for (int c = 0; c < 3; c++)
		axis[c] = (float)(g[c] / len);
	return 1;
}

void dp_silhouette_pick(const double given[3], size_t n, const float *nx, const float *ny, const float *nz,
			double grazing, int *found, float axis[3], double *fraction)
{
	if (dp_silhouette_unit(given, axis)) {
		*found = 1;
		*fraction = -1.0;
		return;
	}
	dp_silhouette_axis(n, nx, ny, nz, grazing, found, axis, fraction);
}

void dp_silhouette_free(dp_silhouette *s)
{
	if (!s)
		return;
	free(s->nearest);
	free(s->inset);
	memset(s, 0, sizeof *s);
}

void dp_silhouette_across(const float axis[3], float u[3], float v[3])
{
	/* u: the axis crossed with the coordinate axis least along it */
	float e[3] = {0.0f, 0.0f, 0.0f};
	int k = fabsf(axis[0]) <= fabsf(axis[1]) && fabsf(axis[0]) <= fabsf(axis[2]) ? 0
		: fabsf(axis[1]) <= fabsf(axis[2])                                   ? 1
											: 2;
	e[k] = 1.0f;
	u[0] = axis[1] * e[2] - axis[2] * e[1];
	u[1] = axis[2] * e[0] - axis[0] * e[2];
	u[2] = axis[0] * e[1] - axis[1] * e[0];
	float len = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
	for (int c = 0; c < 3; c++)
		u[c] /= len;
	v[0] = axis[1] * u[2] - axis[2] * u[1];
	v[1] = axis[2] * u[0] - axis[0] * u[2];
	v[2] = axis[0] * u[1] - axis[1] * u[0];
}

/* Working memory of the distance transform: one row or column at a time. */
typedef struct line_work {
	double *f, *z;
	int *at;
} line_work;

/* The exact squared distance, in cells², from every cell to the nearest cell
 * with src set, into d2 (INFINITY when none is), and that cell's index into
 * nearest unless it is NULL (-1 when none): Felzenszwalb and Huttenlocher's two passes, a
 * column scan and then, along each row, the lower envelope of the parabolas
 * the columns give. row: room for every cell. Linear in the cells, so a
 * wide margin costs no more than a narrow one. */
static void distance_transform(int nu, int nv, const uint8_t *src, float *d2, int32_t *nearest, int32_t *row,
			       const line_work *lw)
{
	for (int i = 0; i < nu; i++) {
		/* along column i: the nearest source row above and below */
		int last = -1;
		for (int j = 0; j < nv; j++) {
			size_t c = (size_t)j * nu + i;
			if (src[c])
				last = j;
			row[c] = last;
		}
		last = -1;
		for (int j = nv - 1; j >= 0; j--) {
			size_t c = (size_t)j * nu + i;
			if (src[c])
				last = j;
			if (last >= 0 && (row[c] < 0 || last - j < j - row[c]))
				row[c] = last;
			d2[c] = row[c] < 0 ? INFINITY : (float)((double)(j - row[c]) * (j - row[c]));
		}
	}
	for (int j = 0; j < nv; j++) {
		size_t base = (size_t)j * nu;
		/* the lower envelope of the finite parabolas (q - i)² + f(i) */
		int k = -1;
		for (int i = 0; i < nu; i++) {
			double fi = d2[base + i];
			lw->f[i] = fi;
			if (!isfinite(fi))
				continue;
			while (k >= 0) {
				int p = lw->at[k];
				double meet = ((fi + (double)i * i) - (lw->f[p] + (double)p * p)) / (2.0 * (i - p));
				if (meet > lw->z[k])
					break;
				k--;
			}
			k++;
			lw->at[k] = i;
			lw->z[k] = k == 0 ? -INFINITY
					  : ((fi + (double)i * i) - (lw->f[lw->at[k - 1]] + (double)lw->at[k - 1] * lw->at[k - 1])) /
						    (2.0 * (i - lw->at[k - 1]));
			lw->z[k + 1] = INFINITY;
		}
		int e = 0;
		for (int q = 0; q < nu; q++) {
			size_t c = base + q;
			if (k < 0) {
				d2[c] = INFINITY;
				if (nearest)
					nearest[c] = -1;
				continue;
			}
			while (lw->z[e + 1] < q)
				e++;
			int p = lw->at[e];
			d2[c] = (float)((double)(q - p) * (q - p) + lw->f[p]);
			if (nearest)
				nearest[c] = row[base + p] * nu + p;
		}
	}
}

/* Cells outside that no 4-neighbour path joins to the grid's border are
 * holes of the outline: filled. mark: 1 inside, 0 outside; queue as above. */
static void fill_holes(int nu, int nv, uint8_t *mark, int32_t *queue)
{
	size_t head = 0, tail = 0, cells = (size_t)nu * (size_t)nv;
	for (int j = 0; j < nv; j++)
		for (int i = 0; i < nu; i++)
			if ((i == 0 || j == 0 || i == nu - 1 || j == nv - 1) && mark[j * nu + i] == 0) {
				mark[j * nu + i] = 2;
				queue[tail++] = j * nu + i;
			}
	static const int step[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
	while (head < tail) {
		int32_t c = queue[head++];
		int i = c % nu, j = c / nu;
		for (int s = 0; s < 4; s++) {
			int a = i + step[s][0], b = j + step[s][1];
			if (a < 0 || b < 0 || a >= nu || b >= nv || mark[b * nu + a] != 0)
				continue;
			mark[b * nu + a] = 2;
			queue[tail++] = b * nu + a;
		}
	}
	for (size_t c = 0; c < cells; c++)
		mark[c] = mark[c] != 2;
}

/* Marks in `graze` the cells (of s's grid) that hold a sample of `facing`
 * whose unit normal lies more than DP_SILHOUETTE_EDGE_DEG from the axis. */
static void mark_turning(const dp_silhouette *s, const dp_cloud *facing, const float axis[3], uint8_t *graze)
{
	double most = cos(DP_SILHOUETTE_EDGE_DEG * M_PI / 180.0);
	for (size_t i = 0; i < facing->n; i++) {
		double along = facing->nx[i] * axis[0] + facing->ny[i] * axis[1] + facing->nz[i] * axis[2];
		if (!(fabs(along) < most))
			continue;
		double pu = facing->x[i] * s->u[0] + facing->y[i] * s->u[1] + facing->z[i] * s->u[2];
		double pv = facing->x[i] * s->v[0] + facing->y[i] * s->v[1] + facing->z[i] * s->v[2];
		double fa = floor((pu - s->u0) / s->cell), fb = floor((pv - s->v0) / s->cell);
		if (fa >= 0.0 && fb >= 0.0 && fa < s->nu && fb < s->nv)
			graze[(size_t)fb * s->nu + (size_t)fa] = 1;
	}
}

dp_status dp_silhouette_build(dp_silhouette *s, const dp_cloud *input, const float axis[3], double cell, double margin,
			      const dp_cloud *facing, double edge_margin, dp_error *err)
{
	double len = sqrt((double)axis[0] * axis[0] + (double)axis[1] * axis[1] + (double)axis[2] * axis[2]);
	if (facing && !facing->n)
		facing = NULL;
	int bare = facing && (!facing->nx || !facing->ny || !facing->nz);
	if (!input->n || !(cell > 0.0) || !isfinite(cell) || !(margin >= 0.0) || !isfinite(margin) ||
	    !(edge_margin >= 0.0) || !isfinite(edge_margin) || bare || !(fabs(len - 1.0) < 1e-3))
		return dp_fail(err, DP_ERR_ARG, "silhouette: %zu input points, cell %g, margin %g, edge margin %g, axis of "
			       "length %g%s", input->n, cell, margin, edge_margin, len,
			       bare ? ", facing samples without normals" : "");
	dp_silhouette_free(s);
	dp_silhouette_across(axis, s->u, s->v);
	double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY;
	for (size_t i = 0; i < input->n; i++) {
		double pu = input->x[i] * s->u[0] + input->y[i] * s->u[1] + input->z[i] * s->u[2];
		double pv = input->x[i] * s->v[0] + input->y[i] * s->v[1] + input->z[i] * s->v[2];
		lo_u = fmin(lo_u, pu), hi_u = fmax(hi_u, pu), lo_v = fmin(lo_v, pv), hi_v = fmax(hi_v, pv);
	}
	/* coarsen until the grid, margin and border included, fits; the spans
	 * are finite (finite input along a unit axis), so a finite cell ends it */
	int border = 0;
	for (;;) {
		double grow = ceil(margin / cell), nu = ceil((hi_u - lo_u) / cell) + 1.0 + 2.0 * (grow + 2.0),
		       nv = ceil((hi_v - lo_v) / cell) + 1.0 + 2.0 * (grow + 2.0);
		if (!isfinite(cell) || !isfinite(nu * nv))
			return dp_fail(err, DP_ERR_ARG, "silhouette: no grid of cells fits an outline %g x %g wide",
				       hi_u - lo_u, hi_v - lo_v);
		if (nu * nv <= MAX_CELLS) {
			border = (int)grow + 2;
			s->nu = (int)nu, s->nv = (int)nv;
			break;
		}
		cell *= 1.5;
	}
	s->cell = cell;
	s->margin = margin;
	s->u0 = lo_u - border * cell;
	s->v0 = lo_v - border * cell;
	size_t cells = (size_t)s->nu * (size_t)s->nv;
	size_t line = (size_t)(s->nu > s->nv ? s->nu : s->nv);
	uint8_t *mark = calloc(cells, 1);
	int32_t *queue = malloc(cells * sizeof *queue);
	line_work lw = {malloc(line * sizeof *lw.f), malloc((line + 1) * sizeof *lw.z), malloc(line * sizeof *lw.at)};
	s->nearest = malloc(cells * sizeof *s->nearest);
	s->inset = malloc(cells * sizeof *s->inset);
	dp_status st = DP_OK;
	if (!mark || !queue || !lw.f || !lw.z || !lw.at || !s->nearest || !s->inset) {
		st = dp_fail(err, DP_ERR_NOMEM, "silhouette: out of memory for %zu cells", cells);
		goto done;
	}
	for (size_t i = 0; i < input->n; i++) {
		double pu = input->x[i] * s->u[0] + input->y[i] * s->u[1] + input->z[i] * s->u[2];
		double pv = input->x[i] * s->v[0] + input->y[i] * s->v[1] + input->z[i] * s->v[2];
		/* inside by construction; clamped against rounding all the same */
		double fa = floor((pu - s->u0) / cell), fb = floor((pv - s->v0) / cell);
		int a = fa < 0.0 ? 0 : fa >= s->nu ? s->nu - 1 : (int)fa, b = fb < 0.0 ? 0 : fb >= s->nv ? s->nv - 1 : (int)fb;
		mark[(size_t)b * s->nu + a] = 1;
	}
	/* grow by the margin: every cell whose centre lies within it of an
	 * occupied cell's centre (s->inset is scratch until its own turn);
	 * with `facing`, by the edge margin from the others */
	double reach = margin / cell, edge_reach = fmin(edge_margin, margin) / cell;
	distance_transform(s->nu, s->nv, mark, s->inset, NULL, queue, &lw);
	if (facing && edge_reach < reach) {
		float *turning = malloc(cells * sizeof *turning);
		if (!turning) {
			st = dp_fail(err, DP_ERR_NOMEM, "silhouette: out of memory for %zu cells", cells);
			goto done;
		}
		memset(mark, 0, cells);
		mark_turning(s, facing, axis, mark);
		distance_transform(s->nu, s->nv, mark, turning, NULL, queue, &lw);
		for (size_t c = 0; c < cells; c++)
			mark[c] = s->inset[c] <= edge_reach * edge_reach || turning[c] <= reach * reach;
		free(turning);
	} else {
		for (size_t c = 0; c < cells; c++)
			mark[c] = s->inset[c] <= reach * reach;
	}
	fill_holes(s->nu, s->nv, mark, queue);
	/* nearest: the nearest cell inside, a cell inside its own */
	distance_transform(s->nu, s->nv, mark, s->inset, s->nearest, queue, &lw);
	/* the inset: over the inside, the distance to the nearest cell outside */
	for (size_t c = 0; c < cells; c++)
		mark[c] = !mark[c];
	distance_transform(s->nu, s->nv, mark, s->inset, NULL, queue, &lw);
	for (size_t c = 0; c < cells; c++)
		s->inset[c] = mark[c] ? 0.0f : (float)(cell * sqrt(s->inset[c]));
done:
	free(mark);
	free(queue);
	free(lw.f);
	free(lw.z);
	free(lw.at);
	if (st != DP_OK)
		dp_silhouette_free(s);
	return st;
}

/* Whether (x, y, z) lies inside the outline by at least s->margin (inside
 * it at all when the margin is 0): off the grid and outside, no. */
static int inside_by_margin(const dp_silhouette *s, double x, double y, double z)
{
	double pu = x * s->u[0] + y * s->u[1] + z * s->u[2], pv = x * s->v[0] + y * s->v[1] + z * s->v[2];
	double fu = floor((pu - s->u0) / s->cell), fv = floor((pv - s->v0) / s->cell);
	if (!(fu >= 0.0 && fu < s->nu && fv >= 0.0 && fv < s->nv))
		return 0;
	size_t c = (size_t)fv * s->nu + (size_t)fu;
	return s->nearest[c] == (int32_t)c && s->inset[c] >= s->margin;
}

/* Halvings of the bisection: the anchor's place to 2^-7 of its depth. */
#define CAP_HALVINGS 7

int dp_silhouette_cap(const dp_silhouette *s, const float p[3], float q[3])
{
	/* an anchor inside stays; so does one whose sample is not inside by
	 * the margin: rounding at the edge for WLOP samples, which lie on the
	 * input, or a sample within the margin less the edge margin of an edge
	 * that faces the scanner. Holding those to their own depth inside
	 * measured worse: one-view bunny 0.857 / 0.90% -> 0.849 / 1.07%
	 * (coverage / flipped, WLOP seeds 1-6). */
	if (inside_by_margin(s, q[0], q[1], q[2]) || !inside_by_margin(s, p[0], p[1], p[2]))
		return 0;
	/* from p, inside, to q, outside: the last place inside along the line */
	double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, lo = 0.0, hi = 1.0;
	for (int k = 0; k < CAP_HALVINGS; k++) {
		double t = 0.5 * (lo + hi);
		if (!inside_by_margin(s, p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]))
			hi = t;
		else
			lo = t;
	}
	for (int c = 0; c < 3; c++)
		q[c] = (float)(p[c] + lo * d[c]);
	return 1;
}

size_t dp_silhouette_hold(const dp_silhouette *s, size_t n, float *x, float *y, float *z)
{
	size_t moved = 0;
	for (size_t i = 0; i < n; i++) {
		double pu = x[i] * s->u[0] + y[i] * s->u[1] + z[i] * s->u[2];
		double pv = x[i] * s->v[0] + y[i] * s->v[1] + z[i] * s->v[2];
		double fu = floor((pu - s->u0) / s->cell), fv = floor((pv - s->v0) / s->cell);
		int within = fu >= 0.0 && fu < s->nu && fv >= 0.0 && fv < s->nv;
		int a = !(fu >= 0.0) ? 0 : fu >= s->nu ? s->nu - 1 : (int)fu;
		int b = !(fv >= 0.0) ? 0 : fv >= s->nv ? s->nv - 1 : (int)fv;
		int32_t c = b * s->nu + a, k = s->nearest[c];
		if (within && k == c)
			continue;
		/* onto the nearest point of cell k, a hair inside its edges */
		double ku = s->u0 + (k % s->nu) * s->cell, kv = s->v0 + (k / s->nu) * s->cell, hair = 1e-3 * s->cell;
		double tu = fmin(fmax(pu, ku + hair), ku + s->cell - hair), tv = fmin(fmax(pv, kv + hair), kv + s->cell - hair);
		float du = (float)(tu - pu), dv = (float)(tv - pv);
		x[i] += du * s->u[0] + dv * s->v[0];
		y[i] += du * s->u[1] + dv * s->v[1];
		z[i] += du * s->u[2] + dv * s->v[2];
		moved++;
	}
	return moved;
}
