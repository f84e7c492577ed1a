/* Surface points stranded in a skeletal sheet, moved across it
 * (sheet_points.h has the reasoning). */
#include "stages/sheet_points.h"

#include "core/common.h"
#include "core/eig3.h"
#include "knn/kdtree.h"

#include <math.h>
#include <stdlib.h>

/* Skeleton spots within this (in r) of the inner end give the sheet. */
#define SHEET_REACH_R 3.0
#define SHEET_MIN_SPOTS 5
/* A sheet: the smallest eigenvalue of the spots' spread below this times
 * the middle one, and the middle one above this times the largest (a
 * curve's two small ones are alike and both far below the largest, a
 * clump's three alike). */
#define SHEET_FLATNESS 0.1
/* A deep point whose direction makes a cosine below this with the sheet's
 * normal lies along the sheet (within about 45° of it). */
#define SHEET_ALONG_COS 0.7
/* A point farther than this (in r) from the sheet's plane is off the sheet:
 * an oblique deep point to a body's surface, not a point in a plate. */
#define SHEET_OFF_R 0.5
/* A point whose foot on the sheet's plane has no spot within this (in r) lies
 * beyond the sheet's edge: a plate's rim face, whose deep points run along
 * the sheet outwards by right (a medial sheet ends half a thickness inside
 * the rim). */
#define SHEET_OVER_R 1.0
/* Closer than this to the plane (in r), the side is the less sampled face. */
#define SHEET_SIDE_R 0.3
/* The faces are sampled around h ± SHEET_FACE_R r s, within SHEET_COUNT_R r. */
#define SHEET_FACE_R 2.0
#define SHEET_COUNT_R 1.5
/* Deep points within this (in r) of the point, whose direction makes a
 * cosine above SHEET_ACROSS_COS with s, give the length; at least
 * SHEET_MIN_ACROSS of them. */
#define SHEET_LENGTH_R 4.0
#define SHEET_ACROSS_COS 0.8
#define SHEET_MIN_ACROSS 3
/* Neighbours read per query: a ball of 4 r holds about 50 surface points. */
#define SHEET_CAP 512

static int ascending(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/* The unit normal of the sheet the spots around h form, or 0 where they form
 * none. */
static int sheet_normal(const dp_sheet_points_args *a, const dp_kdtree *spots, const float h[3], uint32_t *idx,
			float *d2, double s[3])
{
	float reach = (float)(SHEET_REACH_R * a->r);
	size_t k = dp_kdtree_nearest_within(spots, h[0], h[1], h[2], reach * reach, SHEET_CAP, idx, d2);
	if (k < SHEET_MIN_SPOTS)
		return 0;
	dp_moments m = {0};
	for (size_t j = 0; j < k; j++) {
		double d[3] = {a->sx[idx[j]] - h[0], a->sy[idx[j]] - h[1], a->sz[idx[j]] - h[2]};
		dp_moments_add(&m, d);
	}
	double cov[6], w[3];
	dp_moments_cov(&m, cov);
	dp_eig3_smallest(cov, w, s);
	return w[0] < SHEET_FLATNESS * w[1] && w[1] > SHEET_FLATNESS * w[2];
}

static size_t count_within(const dp_kdtree *t, const double c[3], float reach, uint32_t *idx, float *d2)
{
	return dp_kdtree_nearest_within(t, (float)c[0], (float)c[1], (float)c[2], reach * reach, SHEET_CAP, idx, d2);
}

dp_status dp_sheet_points_lift(const dp_sheet_points_args *a, size_t *moved, dp_error *err)
{
	size_t n = a->n;
	double r = a->r;
	dp_kdtree spots = {0}, surface = {0};
	uint32_t *idx = dp_alloc_array(SHEET_CAP, sizeof *idx);
	float *d2 = dp_alloc_array(SHEET_CAP, sizeof *d2), *lengths = dp_alloc_array(SHEET_CAP, sizeof *lengths);
	float *to_x = a->to_x, *to_y = a->to_y, *to_z = a->to_z, *chosen = a->chosen;
	dp_status st = DP_OK;
	*moved = 0;
	if (!idx || !d2 || !lengths) {
		st = dp_fail(err, DP_ERR_NOMEM, "surface: out of memory for the sheet test");
		goto out;
	}
	if ((st = dp_kdtree_build(&spots, a->spots, a->sx, a->sy, a->sz, err)) != DP_OK ||
	    (st = dp_kdtree_build(&surface, n, a->px, a->py, a->pz, err)) != DP_OK)
		goto out;
	for (size_t i = 0; i < n; i++) {
		chosen[i] = 0.0f;
		if (a->eta[i] - 1.0f >= a->held_support)
			continue;
		float h[3] = {a->hx[i], a->hy[i], a->hz[i]};
		double v[3] = {a->px[i] - h[0], a->py[i] - h[1], a->pz[i] - h[2]}, s[3];
		double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
		if (!(len > 0.0) || !sheet_normal(a, &spots, h, idx, d2, s))
			continue;
		double off = v[0] * s[0] + v[1] * s[1] + v[2] * s[2];
		if (fabs(off) >= SHEET_ALONG_COS * len || fabs(off) > SHEET_OFF_R * r)
			continue;
		float over = (float)(SHEET_OVER_R * r);
		if (!dp_kdtree_any_within(&spots, (float)(a->px[i] - off * s[0]), (float)(a->py[i] - off * s[1]),
					  (float)(a->pz[i] - off * s[2]), over * over))
			continue;
		double side = off > 0.0 ? 1.0 : -1.0;
		if (fabs(off) < SHEET_SIDE_R * r) {
			double up[3], down[3];
			for (int c = 0; c < 3; c++) {
				up[c] = h[c] + SHEET_FACE_R * r * s[c];
				down[c] = h[c] - SHEET_FACE_R * r * s[c];
			}
			float reach = (float)(SHEET_COUNT_R * r);
			size_t n_up = count_within(&surface, up, reach, idx, d2);
			size_t n_down = count_within(&surface, down, reach, idx, d2);
			/* on a tie, the side it lies towards: s's sign is the
			 * eigen-solver's */
			if (n_up != n_down)
				side = n_up < n_down ? 1.0 : -1.0;
		}
		float reach = (float)(SHEET_LENGTH_R * r);
		size_t k = dp_kdtree_nearest_within(&surface, a->px[i], a->py[i], a->pz[i], reach * reach, SHEET_CAP,
						    idx, d2), across = 0;
		for (size_t j = 0; j < k; j++) {
			uint32_t o = idx[j];
			double u[3] = {a->px[o] - a->hx[o], a->py[o] - a->hy[o], a->pz[o] - a->hz[o]};
			double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
			double us = fabs(u[0] * s[0] + u[1] * s[1] + u[2] * s[2]);
			/* the depth across the sheet, not the length of a leaning deep point */
			if (ul > 0.0 && us > SHEET_ACROSS_COS * ul)
				lengths[across++] = (float)us;
		}
		if (across < SHEET_MIN_ACROSS)
			continue;
		qsort(lengths, across, sizeof *lengths, ascending);
		double depth = lengths[across / 2];
		to_x[i] = (float)(a->px[i] + (side * depth - off) * s[0]);
		to_y[i] = (float)(a->py[i] + (side * depth - off) * s[1]);
		to_z[i] = (float)(a->pz[i] + (side * depth - off) * s[2]);
		/* no decision reads a normal */
		a->nx[i] = (float)(side * s[0]);
		a->ny[i] = (float)(side * s[1]);
		a->nz[i] = (float)(side * s[2]);
		chosen[i] = 1.0f;
	}
	for (size_t i = 0; i < n; i++)
		if (chosen[i] != 0.0f) {
			a->px[i] = to_x[i];
			a->py[i] = to_y[i];
			a->pz[i] = to_z[i];
			(*moved)++;
		}
out:
	dp_kdtree_free(&spots);
	dp_kdtree_free(&surface);
	free(idx);
	free(d2);
	free(lengths);
	return st;
}
