/* Exact k-nearest-neighbour and radius queries on the host, through FLANN's C
 * API (a single kd-tree searched without a check limit, so answers are exact).
 * FLANN's L2 distances are squared; this wrapper returns squared distances too
 * and takes squared radii, named `_d2`. */
#ifndef DP_KNN_KNN_H
#define DP_KNN_KNN_H

#include "dpoints.h"

typedef struct dp_knn {
	void *index;   /* flann_index_t */
	float *xyz;    /* interleaved copy FLANN indexes (it keeps a pointer) */
	size_t n;
} dp_knn;

/* Refuses (DP_ERR_ARG, the message starting with `stage`) points whose
 * bounding box has a squared diagonal beyond FLT_MAX: their squared distances
 * overflow to infinity, and no neighbour search or kernel weight means
 * anything. A far outlier (one point at 1e20 beside a unit sphere) does it. */
dp_status dp_check_span(const char *stage, size_t n, const float *x, const float *y, const float *z, dp_error *err);

/* Fails as dp_check_span does when the points span too large a range. */
dp_status dp_knn_build(dp_knn *knn, size_t n, const float *x, const float *y, const float *z, dp_error *err);
void dp_knn_free(dp_knn *knn);

/* For each of the nq queries, the k nearest indexed points (ascending), in
 * idx[q*k + j] / d2[q*k + j]. When k > n the missing slots get index -1 and
 * distance INFINITY. */
dp_status dp_knn_query(const dp_knn *knn, size_t nq, const float *qx, const float *qy, const float *qz, int k,
		       int *idx, float *d2, dp_error *err);

/* k nearest neighbours of every indexed point, itself excluded. */
dp_status dp_knn_self(const dp_knn *knn, int k, int *idx, float *d2, dp_error *err);

/* All indexed points within squared radius r2 of (x, y, z), at most `cap`;
 * returns how many (which may exceed cap: then only cap were written). */
int dp_knn_radius(const dp_knn *knn, float x, float y, float z, float r2, int *idx, float *d2, int cap);

/* Paper Eq. 1: the mean distance of each point to its nearest other point.
 * 0 for fewer than two points. */
dp_status dp_mean_spacing(size_t n, const float *x, const float *y, const float *z, double *spacing,
			  dp_error *err);

#endif
