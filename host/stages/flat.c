/* The depth of flat faces scanned from one side: see flat.h. */
#include "stages/flat.h"

#include "core/common.h"
#include "knn/knn.h"

#include <math.h>
#include <stdlib.h>

#define NO_ORIGIN UINT32_MAX

static int by_value(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
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

dp_status dp_flat_cap(size_t n, const float *const p[3], const float *const normal[3], float *const q[3],
		      unsigned char *settled_by, double r, double angle_deg, size_t *capped, dp_error *err)
{
	*capped = 0;
	if (n < 2)
		return DP_OK;
	int k = n - 1 < DP_FLAT_NEIGHBOURS ? (int)(n - 1) : DP_FLAT_NEIGHBOURS;
	int *idx = dp_alloc_array(n, (size_t)k * sizeof(int));
	float *d2 = dp_alloc_array(n, (size_t)k * sizeof(float));
	float *cap = dp_alloc_array(n, sizeof(float)), *own = dp_alloc_array(n, sizeof(float));
	int *ridx = dp_alloc_array(DP_FLAT_RIM_COUNT, sizeof(int));
	float *rd2 = dp_alloc_array(DP_FLAT_RIM_COUNT, sizeof(float)), *rdepth = dp_alloc_array(DP_FLAT_RIM_COUNT, sizeof(float));
	uint32_t *origin = dp_alloc_array(n, sizeof(uint32_t));
	dp_knn knn = {0};
	dp_status st = DP_OK;
	if (!idx || !d2 || !cap || !own || !origin || !ridx || !rd2 || !rdepth) {
		st = dp_fail(err, DP_ERR_NOMEM, "sink: out of memory for the flat-face depths of %zu points", n);
		goto out;
	}
	if ((st = dp_knn_build(&knn, n, p[0], p[1], p[2], err)) != DP_OK ||
	    (st = dp_knn_self(&knn, k, idx, d2, err)) != DP_OK)
		goto out;
	float min_cos = (float)cos(angle_deg * M_PI / 180.0);
	for (size_t i = 0; i < n; i++)
		own[i] = depth(p, q, i);
	/* An evidence point's depth says how far its own ball reaches, which
	 * near a rim runs from 0 at the crease to the full thickness a
	 * thickness in; the face's is the median over the evidence around it
	 * that faces the same way. */
	float rim2 = (float)(DP_FLAT_RIM_R * r * DP_FLAT_RIM_R * r);
	for (size_t i = 0; i < n; i++) {
		origin[i] = NO_ORIGIN;
		cap[i] = INFINITY;
		if (!evidence(settled_by[i]))
			continue;
		int found = dp_knn_radius(&knn, p[0][i], p[1][i], p[2][i], rim2, ridx, rd2, DP_FLAT_RIM_COUNT);
		size_t m = 0;
		for (int j = 0; j < found && j < DP_FLAT_RIM_COUNT; j++) {
			int o = ridx[j];
			if (o >= 0 && evidence(settled_by[o]) &&
			    normal[0][i] * normal[0][o] + normal[1][i] * normal[1][o] + normal[2][i] * normal[2][o] >= min_cos)
				rdepth[m++] = own[o];
		}
		if (m == 0)
			continue; /* the radius search missed the point itself: NaN coordinates, checked before */
		qsort(rdepth, m, sizeof *rdepth, by_value);
		cap[i] = rdepth[m / 2];
		origin[i] = (uint32_t)i;
	}
	/* Sweeps until nothing changes: each passes the smallest depth at
	 * least one link further, so a face D r across takes about D / FLAT_LINK_R
	 * of them. */
	float link2 = (float)(DP_FLAT_LINK_R * r * DP_FLAT_LINK_R * r);
	int changed = 1;
	while (changed) {
		changed = 0;
		for (size_t i = 0; i < n; i++) {
			for (int j = 0; j < k; j++) {
				int nb = idx[i * (size_t)k + (size_t)j];
				if (nb < 0 || !(d2[i * (size_t)k + (size_t)j] <= link2))
					break; /* ascending: the rest are farther */
				uint32_t o = origin[nb];
				if (o == NO_ORIGIN || !(cap[nb] < cap[i]))
					continue;
				float c = normal[0][i] * normal[0][o] + normal[1][i] * normal[1][o] + normal[2][i] * normal[2][o];
				if (c < min_cos)
					continue;
				cap[i] = cap[nb];
				origin[i] = o;
				changed = 1;
			}
		}
	}
	for (size_t i = 0; i < n; i++) {
		if (settled_by[i] != DP_SETTLE_SLOW || !isfinite(cap[i]))
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
	free(idx);
	free(d2);
	free(cap);
	free(own);
	free(origin);
	free(ridx);
	free(rd2);
	free(rdepth);
	return st;
}
