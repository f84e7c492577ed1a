/* The width bound of sinking: the deepest each sample's inner point may go
 * (width.h has the reasoning). Scales are read lazily, so a point that
 * settles shallow never pays for the wide ones. */
#include "stages/width.h"

#include "core/common.h"
#include "core/eig3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Larger scales read one in WIDTH_STRIDE_GROWTH times fewer samples: a ball
 * twice as wide on a surface holds four times as many. A power of two, for
 * the mask in kept(). */
#define WIDTH_STRIDE_GROWTH 4
_Static_assert((WIDTH_STRIDE_GROWTH & (WIDTH_STRIDE_GROWTH - 1)) == 0, "the stride must be a power of two");

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

static double scale_r(int k)
{
	return DP_WIDTH_MIN_SCALE_R * (double)(1u << k);
}

dp_status dp_width_init(dp_width *w, size_t n, const float *x, const float *y, const float *z, double r,
			double factor, dp_error *err)
{
	memset(w, 0, sizeof *w);
	w->x = x;
	w->y = y;
	w->z = z;
	w->r = r;
	w->factor = factor;
	if (n == 0)
		return DP_OK;
	float *sub = dp_alloc_array(n, 3 * sizeof(float));
	w->level = calloc(n, 1);
	w->bound = dp_alloc_array(n, sizeof(float));
	dp_status st = DP_OK;
	if (!sub || !w->level || !w->bound)
		st = dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for the width bound of %zu points", n);
	size_t stride = 1;
	for (int k = 0; k < DP_WIDTH_SCALES && st == DP_OK; k++) {
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
		st = dp_grid_build(&w->grid[k], m, sub, sub + n, sub + 2 * n, (float)(scale_r(k) * r), err);
	}
	free(sub);
	if (st != DP_OK) {
		dp_width_free(w);
		return st;
	}
	for (size_t i = 0; i < n; i++)
		w->bound[i] = INFINITY;
	return DP_OK;
}

void dp_width_free(dp_width *w)
{
	for (int k = 0; k < DP_WIDTH_SCALES; k++)
		dp_grid_free(&w->grid[k]);
	free(w->level);
	free(w->bound);
	memset(w, 0, sizeof *w);
}

/* The spread of scale k's ball around sample i across the part: the square
 * root of the middle eigenvalue of its samples' second moments about i, or
 * NAN where the ball holds fewer than DP_WIDTH_MIN_COUNT of the scale's
 * samples (a patch of surface holds about 40 at 4 r, 200 beyond). */
static double spread(const dp_width *w, int k, size_t i)
{
	const dp_grid *g = &w->grid[k];
	/* in double: squares of a float span near its range overflow */
	double px = w->x[i], py = w->y[i], pz = w->z[i], rho = scale_r(k) * w->r, rho2 = rho * rho;
	double ss[6] = {0}, count = 0.0;
	uint32_t beg[9], end[9];
	dp_grid_rows(g, w->x[i], w->y[i], w->z[i], beg, end);
	for (int row = 0; row < 9; row++)
		for (uint32_t j = beg[row]; j < end[row]; j++) {
			double dx = g->x[j] - px, dy = g->y[j] - py, dz = g->z[j] - pz;
			if (dx * dx + dy * dy + dz * dz >= rho2)
				continue;
			ss[0] += dx * dx;
			ss[1] += dx * dy;
			ss[2] += dx * dz;
			ss[3] += dy * dy;
			ss[4] += dy * dz;
			ss[5] += dz * dz;
			count += 1.0;
		}
	if (count < DP_WIDTH_MIN_COUNT)
		return NAN;
	double m[6], ev[3], vec[3][3];
	for (int c = 0; c < 6; c++)
		m[c] = ss[c] / count;
	dp_eig3_sym(m, ev, vec);
	return sqrt(fmax(ev[1], 0.0));
}

int dp_width_too_deep(dp_width *w, size_t i, float depth)
{
	/* scale k can bound sample i only once it is rho_k / 2 deep */
	while (!isfinite(w->bound[i]) && w->level[i] < DP_WIDTH_SCALES &&
	       depth >= (float)(0.5 * scale_r(w->level[i]) * w->r)) {
		int k = w->level[i]++;
		double rho = scale_r(k) * w->r, s = spread(w, k, i);
		/* Too few samples at a small scale is a sparse spot, such as a
		 * straggler at a scan's rim, which must still sink to the centre
		 * with its neighbours. Too few in the widest ball is an outlier
		 * or a stray cluster with no part around it: nothing else stops
		 * a point without neighbours short of the iteration cap. */
		int isolated = isnan(s) && k == DP_WIDTH_SCALES - 1;
		if (isolated || 0.5 * rho > w->factor * s)
			w->bound[i] = (float)(0.5 * rho);
	}
	return depth >= w->bound[i];
}

dp_status dp_width_bound(size_t n, const float *x, const float *y, const float *z, double r, double factor,
			 float *bound, dp_error *err)
{
	dp_width w;
	dp_status st = dp_width_init(&w, n, x, y, z, r, factor, err);
	if (st != DP_OK)
		return st;
	for (size_t i = 0; i < n; i++) {
		dp_width_too_deep(&w, i, INFINITY);
		bound[i] = w.bound[i];
	}
	dp_width_free(&w);
	return DP_OK;
}
