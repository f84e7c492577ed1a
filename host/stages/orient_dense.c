/* Signs of sparse samples' normals from denser WLOP samples of the same input
 * (dp_orient_from_denser, dpoints.h). */
#include "core/common.h"
#include "core/distinct.h"
#include "knn/knn.h"
#include "stages/wlop.h"

#include <math.h>
#include <stdlib.h>

/* Dense samples whose normals a sample agrees with. */
#define DENSE_K 8

/* Turns every normal of `points` to agree with the weighted normals of its
 * DENSE_K nearest `dense` points; counts the turns in *turned. */
static dp_status agree_with(dp_cloud *points, const dp_cloud *dense, size_t *turned, dp_error *err)
{
	int k = dense->n < DENSE_K ? (int)dense->n : DENSE_K;
	dp_knn knn = {0};
	int *idx = dp_alloc_array(points->n * (size_t)k, sizeof *idx);
	float *d2 = dp_alloc_array(points->n * (size_t)k, sizeof *d2);
	dp_status st = DP_OK;
	if (!idx || !d2) {
		st = dp_fail(err, DP_ERR_NOMEM, "normals: out of memory orienting %zu samples", points->n);
		goto done;
	}
	if ((st = dp_knn_build(&knn, dense->n, dense->x, dense->y, dense->z, err)) != DP_OK ||
	    (st = dp_knn_query(&knn, points->n, points->x, points->y, points->z, k, idx, d2, err)) != DP_OK)
		goto done;
	for (size_t i = 0; i < points->n; i++) {
		const int *nb = idx + i * (size_t)k;
		const float *dd = d2 + i * (size_t)k;
		/* weights in the distance over the nearest one's, so the dense
		 * samples' own spacing sets the reach */
		double near2 = dd[0] > 0.0f ? (double)dd[0] : 1.0, agree = 0.0;
		for (int m = 0; m < k; m++) {
			if (nb[m] < 0)
				continue;
			size_t j = (size_t)nb[m];
			double c = (double)points->nx[i] * dense->nx[j] + (double)points->ny[i] * dense->ny[j] +
				   (double)points->nz[i] * dense->nz[j];
			agree += exp(-0.5 * (double)dd[m] / near2) * c;
		}
		if (agree < 0.0) {
			points->nx[i] = -points->nx[i];
			points->ny[i] = -points->ny[i];
			points->nz[i] = -points->nz[i];
			(*turned)++;
		}
	}
done:
	dp_knn_free(&knn);
	free(idx);
	free(d2);
	return st;
}

dp_status dp_orient_from_denser(dp_context *ctx, const dp_cloud *input, const dp_wlop_params *wlop,
				const dp_normal_params *normals, size_t dense, dp_cloud *samples, size_t *dense_run,
				size_t *turned, dp_error *err)
{
	size_t run = 0, flips = 0, distinct = 0;
	dp_wlop_params wp;
	dp_normal_params np;
	dp_cloud guide = {0};
	dp_status st = DP_OK;
	if (!ctx || !input || !samples || !samples->nx) {
		st = dp_fail(err, DP_ERR_ARG, "normals: orienting from denser samples needs a context, the input and "
					     "samples with normals");
		goto done;
	}
	if (wlop)
		wp = *wlop;
	else
		dp_wlop_params_default(&wp);
	if (normals)
		np = *normals;
	else
		dp_normal_params_default(&np);
	if (np.use_viewpoint || samples->n >= dense)
		goto done;
	if ((st = dp_distinct_upto(input, dense, &distinct, err)) != DP_OK)
		goto done;
	run = dense < distinct ? dense : distinct;
	if (run <= samples->n) {
		run = 0;
		goto done;
	}
	wp.samples = run;
	if ((st = dp_wlop_as(ctx, "denser", input, &wp, &guide, NULL, err)) == DP_OK &&
	    (st = dp_estimate_normals(&guide, &np, err)) == DP_OK)
		st = agree_with(samples, &guide, &flips, err);
done:
	dp_cloud_free(&guide);
	if (dense_run)
		*dense_run = st == DP_OK ? run : 0;
	if (turned)
		*turned = st == DP_OK ? flips : 0;
	return st;
}
