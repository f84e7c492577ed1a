/* Colours and intensities carried from a scan to the points made from it.
 * The pipeline moves, adds and completes points, so no output point has an
 * input row of its own; the nearest input point is the one that saw that part
 * of the surface, and taking one point (not a mean) keeps the borders between
 * colours sharp. */
#include "knn/attributes.h"

#include "core/common.h"
#include "knn/knn.h"

#include <stdlib.h>

dp_status dp_transfer_attributes(dp_cloud *dst, const dp_cloud *src, dp_error *err)
{
	free(dst->rgb);
	free(dst->intensity);
	dst->rgb = NULL;
	dst->intensity = NULL;
	if ((!src->rgb && !src->intensity) || src->n == 0 || dst->n == 0)
		return DP_OK;
	unsigned char *rgb = src->rgb ? dp_alloc_array(3 * dst->n, 1) : NULL;
	float *intensity = src->intensity ? dp_alloc_array(dst->n, sizeof *intensity) : NULL;
	int *idx = dp_alloc_array(dst->n, sizeof *idx);
	float *d2 = dp_alloc_array(dst->n, sizeof *d2);
	dp_knn knn = {0};
	dp_status st = DP_OK;
	if ((src->rgb && !rgb) || (src->intensity && !intensity) || !idx || !d2)
		st = dp_fail(err, DP_ERR_NOMEM, "attributes: out of memory for %zu points", dst->n);
	if (st == DP_OK)
		st = dp_knn_build(&knn, src->n, src->x, src->y, src->z, err);
	if (st == DP_OK)
		st = dp_knn_query(&knn, dst->n, dst->x, dst->y, dst->z, 1, idx, d2, err);
	for (size_t i = 0; st == DP_OK && i < dst->n; i++) {
		size_t j = idx[i] >= 0 ? (size_t)idx[i] : 0;
		for (int c = 0; rgb && c < 3; c++)
			rgb[3 * i + c] = src->rgb[3 * j + c];
		if (intensity)
			intensity[i] = src->intensity[j];
	}
	dp_knn_free(&knn);
	free(idx);
	free(d2);
	if (st != DP_OK) {
		free(rgb);
		free(intensity);
		return st;
	}
	dst->rgb = rgb;
	dst->intensity = intensity;
	return DP_OK;
}
