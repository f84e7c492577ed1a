/* Facing the scanner (scanner.h). */
#include "stages/scanner.h"
#include "stages/silhouette.h"
#include "core/common.h"

#include <math.h>
#include <stdlib.h>

dp_status dp_scanner_check(const dp_surface_params *p, const char *prefix, dp_error *err)
{
	const double *g = p->silhouette_axis, *e = p->viewpoint;
	if (!(p->face_scanner_cos >= 0.0 && p->face_scanner_cos < 1.0))
		return dp_fail(err, DP_ERR_ARG, "%sface-scanner cosine %g is not in [0, 1)", prefix, p->face_scanner_cos);
	if (p->scanner_side < -1 || p->scanner_side > 1)
		return dp_fail(err, DP_ERR_ARG, "%sscanner side %d is not -1, 0 or 1", prefix, p->scanner_side);
	if (p->scanner_side && g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0)
		return dp_fail(err, DP_ERR_ARG, "%sscanner side %d needs the view axis it lies along", prefix,
			       p->scanner_side);
	if (p->use_viewpoint && !(isfinite(e[0]) && isfinite(e[1]) && isfinite(e[2])))
		return dp_fail(err, DP_ERR_ARG, "%sthe scanner's viewpoint is not finite", prefix);
	if (p->use_viewpoint && p->scanner_side)
		return dp_fail(err, DP_ERR_ARG, "%sa scanner side and a viewpoint both given: one says where the scanner "
			       "was", prefix);
	return DP_OK;
}

/* A sample's column across the axis and its depth along it. */
typedef struct column_depth {
	double u, v, depth;
} column_depth;

static int by_column_then_depth(const void *pa, const void *pb)
{
	const column_depth *a = pa, *b = pb;
	if (a->u != b->u)
		return a->u < b->u ? -1 : 1;
	if (a->v != b->v)
		return a->v < b->v ? -1 : 1;
	return (a->depth > b->depth) - (a->depth < b->depth);
}

dp_status dp_scanner_layered(size_t n, const float *x, const float *y, const float *z, const float axis[3],
			     double r, double *layered, dp_error *err)
{
	*layered = 0.0;
	if (!(r > 0.0 && isfinite(DP_SCANNER_CELL_R * r)))
		return dp_fail(err, DP_ERR_ARG, "scanner: spacing r = %g gives no columns", r);
	if (n == 0)
		return DP_OK;
	column_depth *c = dp_alloc_array(n, sizeof *c);
	if (!c)
		return dp_fail(err, DP_ERR_NOMEM, "scanner: out of memory for %zu depths", n);
	float u[3], v[3];
	dp_silhouette_across(axis, u, v);
	double cell = DP_SCANNER_CELL_R * r, gap = DP_SCANNER_GAP_R * r;
	for (size_t i = 0; i < n; i++) {
		double p[3] = {x[i], y[i], z[i]};
		c[i].u = floor((p[0] * u[0] + p[1] * u[1] + p[2] * u[2]) / cell);
		c[i].v = floor((p[0] * v[0] + p[1] * v[1] + p[2] * v[2]) / cell);
		c[i].depth = p[0] * axis[0] + p[1] * axis[1] + p[2] * axis[2];
	}
	qsort(c, n, sizeof *c, by_column_then_depth);
	size_t count = 0;
	for (size_t begin = 0, end; begin < n; begin = end) {
		int two = 0;
		for (end = begin + 1; end < n && c[end].u == c[begin].u && c[end].v == c[begin].v; end++)
			two |= c[end].depth - c[end - 1].depth > gap;
		count += two ? end - begin : 0;
	}
	free(c);
	*layered = (double)count / (double)n;
	return DP_OK;
}

dp_status dp_scanner_side(size_t n, const float *x, const float *y, const float *z, const float *nx,
			  const float *ny, const float *nz, const float axis[3], double cos_min, double r, int *side,
			  dp_error *err)
{
	*side = 0;
	size_t along = 0, against = 0;
	for (size_t i = 0; i < n; i++) {
		double d = (double)nx[i] * axis[0] + (double)ny[i] * axis[1] + (double)nz[i] * axis[2];
		along += d > cos_min;
		against += d < -cos_min;
	}
	size_t fewer = along < against ? along : against, all = along + against;
	if (all < DP_SCANNER_MIN_NORMALS || (double)fewer > DP_SCANNER_SLIPS * (double)all)
		return DP_OK;
	int way = along >= against ? 1 : -1;
	if ((double)fewer <= DP_SCANNER_MINORITY * (double)all) {
		*side = way;
		return DP_OK;
	}
	double layered;
	dp_status st = dp_scanner_layered(n, x, y, z, axis, r, &layered, err);
	if (st == DP_OK && layered <= DP_SCANNER_LAYERED)
		*side = way;
	return st;
}

/* Negates normal i when `by` (its cosine to the scanner) is below -cos_min:
 * 1 when it did. */
static int turn(float *nx, float *ny, float *nz, size_t i, double by, double cos_min)
{
	if (!(by < -cos_min))
		return 0;
	nx[i] = -nx[i];
	ny[i] = -ny[i];
	nz[i] = -nz[i];
	return 1;
}

size_t dp_scanner_face_eye(size_t n, const float *x, const float *y, const float *z, float *nx, float *ny, float *nz,
			   const double eye[3], double cos_min)
{
	size_t turned = 0;
	for (size_t i = 0; i < n; i++) {
		double to[3] = {eye[0] - x[i], eye[1] - y[i], eye[2] - z[i]};
		double len = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
		if (len > 0.0)
			turned += turn(nx, ny, nz, i, (nx[i] * to[0] + ny[i] * to[1] + nz[i] * to[2]) / len, cos_min);
	}
	return turned;
}

size_t dp_scanner_face(size_t n, float *nx, float *ny, float *nz, const float toward[3], double cos_min)
{
	size_t turned = 0;
	for (size_t i = 0; i < n; i++)
		turned += turn(nx, ny, nz, i,
			       (double)nx[i] * toward[0] + (double)ny[i] * toward[1] + (double)nz[i] * toward[2], cos_min);
	return turned;
}
