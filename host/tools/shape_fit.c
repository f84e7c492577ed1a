/* How well a point set fits a built-in shape: distances to its surface and to
 * its ideal meso-skeleton, and how far a skeleton spreads along the core curve
 * or over the mid-plane (issue 3's "a curve, not a blob", "a sheet, not a
 * curve", "no gap along the circle"). */
#include "core/common.h"
#include "tools/shapes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* The points inside the solid (closer to the skeleton than the half
 * thickness) count for the spread; others are strays, not the skeleton. */
static double half_thickness(const dp_shape *s)
{
	switch (s->kind) {
	case DP_SHAPE_CYLINDER:
	case DP_SHAPE_RODS: return s->radius;
	case DP_SHAPE_SLAB: return 0.5 * s->thickness;
	case DP_SHAPE_TORUS: return s->tube;
	default: return NAN;
	}
}

/* Position of p along the core curve, in [0, length). */
static double curve_parameter(const dp_shape *s, const double p[3])
{
	if (s->kind == DP_SHAPE_CYLINDER)
		return fmin(fmax(p[2] + 0.5 * s->length, 0.0), s->length);
	double a = atan2(p[1], p[0]);
	if (a < 0.0)
		a += 2.0 * M_PI;
	return s->radius * fmin(a, 2.0 * M_PI);
}

/* Sorted parameters t[0..m): covered length of the union of [t - h, t + h]
 * clipped to [0, len) (cyclic when closed), and the largest empty stretch
 * between consecutive parameters (closed curves: also across the seam). */
static void curve_spread(const double *t, size_t m, double len, int closed, double h, dp_shape_fit *fit)
{
	double covered = 0.0, gap = 0.0;
	for (size_t i = 0; i + 1 < m; i++) {
		double d = t[i + 1] - t[i];
		covered += fmin(d, 2.0 * h);
		gap = fmax(gap, d);
	}
	if (closed) {
		double d = t[0] + len - t[m - 1];
		covered += fmin(d, 2.0 * h);
		gap = fmax(gap, d);
	} else {
		covered += fmin(t[0], h) + fmin(len - t[m - 1], h);
	}
	fit->spread = fmin(covered, len) / len;
	fit->largest_gap = gap / len;
}

dp_status dp_shape_fit_points(const dp_shape *shape, const dp_cloud *points, double cell, dp_shape_fit *fit,
			      dp_error *err)
{
	memset(fit, 0, sizeof *fit);
	fit->spread = fit->largest_gap = NAN;
	dp_status st = dp_shape_check(shape, err);
	if (st != DP_OK)
		return st;
	if (!points || points->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "shape fit: no points");
	if (!(cell > 0.0 && isfinite(cell)))
		return dp_fail(err, DP_ERR_ARG, "shape fit: cell %g is not a positive number", cell);
	size_t n = points->n;
	double half = half_thickness(shape);
	int spread = isfinite(half);
	double *t = NULL;
	unsigned char *occupied = NULL;
	size_t cells = 0;
	if (shape->kind == DP_SHAPE_SLAB) {
		/* Whole cells: the width is split into the nearest count of them. */
		cells = (size_t)fmax(1.0, round(shape->width / cell));
		if (cells > 4096)
			return dp_fail(err, DP_ERR_ARG, "shape fit: cell %g is too small for width %g", cell,
				       shape->width);
		occupied = calloc(cells * cells, 1);
		if (!occupied)
			return dp_fail(err, DP_ERR_NOMEM, "shape fit: out of memory for %zu cells", cells * cells);
	} else if (spread) {
		t = dp_alloc_array(n, sizeof *t);
		if (!t)
			return dp_fail(err, DP_ERR_NOMEM, "shape fit: out of memory for %zu points", n);
	}
	double sum_surface = 0.0, sum_skeleton = 0.0;
	size_t inside = 0;
	for (size_t i = 0; i < n; i++) {
		double p[3] = {points->x[i], points->y[i], points->z[i]};
		if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
			free(t);
			free(occupied);
			return dp_fail(err, DP_ERR_ARG, "shape fit: point %zu is not finite", i);
		}
		sum_surface += dp_shape_surface_distance(shape, p);
		double d = dp_shape_skeleton_distance(shape, p);
		sum_skeleton += d;
		if (!spread || !(d <= half))
			continue;
		if (occupied) {
			double h = 0.5 * shape->width, scale = (double)cells / shape->width;
			size_t cx = (size_t)fmin(fmax((p[0] + h) * scale, 0.0), (double)(cells - 1));
			size_t cy = (size_t)fmin(fmax((p[1] + h) * scale, 0.0), (double)(cells - 1));
			occupied[cy * cells + cx] = 1;
		} else {
			t[inside] = curve_parameter(shape, p);
		}
		inside++;
	}
	fit->points = n;
	fit->inside = inside;
	fit->surface_mean = sum_surface / (double)n;
	fit->skeleton_mean = sum_skeleton / (double)n;
	if (occupied) {
		size_t count = 0;
		for (size_t c = 0; c < cells * cells; c++)
			count += occupied[c];
		fit->spread = (double)count / (double)(cells * cells);
	} else if (spread && inside == 0) {
		fit->spread = 0.0;
		fit->largest_gap = 1.0;
	} else if (spread) {
		int closed = shape->kind == DP_SHAPE_TORUS;
		double len = closed ? 2.0 * M_PI * shape->radius : shape->length;
		qsort(t, inside, sizeof *t, cmp_double);
		curve_spread(t, inside, len, closed, 0.5 * cell, fit);
	}
	free(t);
	free(occupied);
	return DP_OK;
}
