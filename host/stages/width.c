/* The width bound of sinking: the deepest each sample's inner point may go
 * (width.h has the reasoning). */
#include "stages/width.h"

#include "core/common.h"
#include "core/eig3.h"
#include "grid/grid.h"

#include <math.h>
#include <stdlib.h>

/* Larger scales read one in WIDTH_STRIDE_GROWTH times fewer samples: a ball
 * twice as wide on a surface holds four times as many. */
#define WIDTH_STRIDE_GROWTH 4

/* Which samples a scale reads, by a hash of the index rather than every k-th
 * one: samples in scan order would otherwise leave whole scan lines. */
static int kept(size_t i, size_t stride)
{
	uint64_t h = (uint64_t)i * 0x9e3779b97f4a7c15ull;
	h ^= h >> 31;
	h *= 0xbf58476d1ce4e5b9ull;
	h ^= h >> 29;
	return (h & (stride - 1)) == 0;
}

/* The spread of a ball's samples across the part: the square root of the
 * middle eigenvalue of their second moments about p. */
static double across(const double ss[6], double count)
{
	double m[6], w[3], v[3][3];
	for (int k = 0; k < 6; k++)
		m[k] = ss[k] / count;
	dp_eig3_sym(m, w, v);
	return sqrt(fmax(w[1], 0.0));
}

/* One scale: every still unbounded sample i whose ball of radius rho over the
 * grid's samples spreads less than rho / (2 factor) is bounded at rho / 2. */
static void bound_at(const dp_grid *g, size_t n, const float *x, const float *y, const float *z, float rho,
		     double factor, float *bound)
{
	float rho2 = rho * rho;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < n; i++) {
		if (isfinite(bound[i]))
			continue;
		double ss[6] = {0}, count = 0.0;
		dp_grid_rows(g, x[i], y[i], z[i], beg, end);
		for (int row = 0; row < 9; row++)
			for (uint32_t k = beg[row]; k < end[row]; k++) {
				float dx = g->x[k] - x[i], dy = g->y[k] - y[i], dz = g->z[k] - z[i];
				if (dx * dx + dy * dy + dz * dz >= rho2)
					continue;
				ss[0] += (double)dx * dx;
				ss[1] += (double)dx * dy;
				ss[2] += (double)dx * dz;
				ss[3] += (double)dy * dy;
				ss[4] += (double)dy * dz;
				ss[5] += (double)dz * dz;
				count += 1.0;
			}
		if (count >= WIDTH_MIN_COUNT && 0.5 * rho > factor * across(ss, count))
			bound[i] = 0.5f * rho;
	}
}

dp_status dp_width_bound(size_t n, const float *x, const float *y, const float *z, double r, double factor,
			 float *bound, dp_error *err)
{
	for (size_t i = 0; i < n; i++)
		bound[i] = INFINITY;
	if (n == 0)
		return DP_OK;
	float *sub = dp_alloc_array(n, 3 * sizeof(float));
	if (!sub)
		return dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for the width bound of %zu points", n);
	dp_grid g = {0};
	dp_status st = DP_OK;
	size_t stride = 1;
	double rho = WIDTH_MIN_SCALE_R;
	for (int k = 0; rho <= WIDTH_MAX_SCALE_R && st == DP_OK; k++, rho *= 2.0) {
		/* the first two scales read every sample (a ball of 4 r holds
		 * only about 50), then each keeps about as many as the second */
		if (k >= 2)
			stride *= WIDTH_STRIDE_GROWTH;
		size_t m = 0;
		for (size_t i = 0; i < n; i++)
			if (kept(i, stride)) {
				sub[m] = x[i];
				sub[n + m] = y[i];
				sub[2 * n + m] = z[i];
				m++;
			}
		st = dp_grid_build(&g, m, sub, sub + n, sub + 2 * n, (float)(rho * r), err);
		if (st == DP_OK)
			bound_at(&g, n, x, y, z, (float)(rho * r), factor, bound);
	}
	dp_grid_free(&g);
	free(sub);
	return st;
}
