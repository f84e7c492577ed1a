#include "knn/knn.h"

#include "core/common.h"

#include <flann/flann.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static struct FLANNParameters exact_params(void)
{
	struct FLANNParameters p = DEFAULT_FLANN_PARAMETERS;
	p.algorithm = FLANN_INDEX_KDTREE_SINGLE;
	p.checks = FLANN_CHECKS_UNLIMITED;
	p.eps = 0.0f;
	p.sorted = 1;
	p.cores = 1;
	p.log_level = FLANN_LOG_NONE;
	return p;
}

dp_status dp_check_span(const char *stage, size_t n, const float *x, const float *y, const float *z, dp_error *err)
{
	if (n == 0)
		return DP_OK;
	double lo[3] = {x[0], y[0], z[0]}, hi[3] = {x[0], y[0], z[0]};
	for (size_t i = 1; i < n; i++) {
		double p[3] = {x[i], y[i], z[i]};
		for (int a = 0; a < 3; a++) {
			lo[a] = p[a] < lo[a] ? p[a] : lo[a];
			hi[a] = p[a] > hi[a] ? p[a] : hi[a];
		}
	}
	double d2 = 0.0;
	for (int a = 0; a < 3; a++)
		d2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
	if (d2 <= FLT_MAX)
		return DP_OK;
	return dp_fail(err, DP_ERR_ARG,
		       "%s: the coordinates span %.3g (box diagonal), too large a range: squared distances overflow "
		       "single precision (remove far outliers or rescale)",
		       stage, sqrt(d2));
}

dp_status dp_knn_build(dp_knn *knn, size_t n, const float *x, const float *y, const float *z, dp_error *err)
{
	memset(knn, 0, sizeof *knn);
	if (n == 0 || n > INT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "knn: cannot index %zu points", n);
	dp_status st = dp_check_span("knn", n, x, y, z, err);
	if (st != DP_OK)
		return st;
	knn->xyz = dp_alloc_array(3 * n, sizeof(float));
	if (!knn->xyz)
		return dp_fail(err, DP_ERR_NOMEM, "knn: out of memory for %zu points", n);
	for (size_t i = 0; i < n; i++) {
		knn->xyz[3 * i] = x[i];
		knn->xyz[3 * i + 1] = y[i];
		knn->xyz[3 * i + 2] = z[i];
	}
	struct FLANNParameters p = exact_params();
	float speedup;
	knn->index = flann_build_index_float(knn->xyz, (int)n, 3, &speedup, &p);
	if (!knn->index) {
		free(knn->xyz);
		knn->xyz = NULL;
		return dp_fail(err, DP_ERR_INTERNAL, "knn: FLANN could not build an index of %zu points", n);
	}
	knn->n = n;
	return DP_OK;
}

void dp_knn_free(dp_knn *knn)
{
	if (knn->index) {
		struct FLANNParameters p = exact_params();
		flann_free_index_float(knn->index, &p);
	}
	free(knn->xyz);
	memset(knn, 0, sizeof *knn);
}

/* Queries in blocks so the interleaved query copy stays small. */
#define QUERY_BLOCK 4096

static dp_status query_block(const dp_knn *knn, float *q, size_t nq, int k, int kk, int *idx, float *d2,
			     int *tmp_i, float *tmp_d, int skip_self, size_t first, dp_error *err)
{
	struct FLANNParameters p = exact_params();
	/* When squared distances overflow to infinity FLANN finds fewer
	 * neighbours than asked: it may leave slots unwritten, or fill them with
	 * index 0 at an infinite distance. Neither is a neighbour. */
	for (size_t j = 0; j < nq * (size_t)kk; j++) {
		tmp_i[j] = -1;
		tmp_d[j] = INFINITY;
	}
	if (flann_find_nearest_neighbors_index_float(knn->index, q, (int)nq, tmp_i, tmp_d, kk, &p) != 0)
		return dp_fail(err, DP_ERR_INTERNAL, "knn: FLANN query failed");
	for (size_t i = 0; i < nq; i++) {
		/* With skip_self one extra neighbour was asked for; when duplicates
		 * push the point itself out of the list, the extra one is kept. */
		int out = 0;
		for (int j = 0; j < kk && out < k; j++) {
			int id = tmp_i[i * (size_t)kk + (size_t)j];
			float d = tmp_d[i * (size_t)kk + (size_t)j];
			if (id < 0 || (size_t)id >= knn->n || !(d < INFINITY) || (skip_self && (size_t)id == first + i))
				continue;
			idx[i * (size_t)k + (size_t)out] = id;
			d2[i * (size_t)k + (size_t)out] = d;
			out++;
		}
		for (; out < k; out++) {
			idx[i * (size_t)k + (size_t)out] = -1;
			d2[i * (size_t)k + (size_t)out] = INFINITY;
		}
	}
	return DP_OK;
}

static dp_status query(const dp_knn *knn, size_t nq, const float *qx, const float *qy, const float *qz, int k,
		       int skip_self, int *idx, float *d2, dp_error *err)
{
	if (k <= 0)
		return dp_fail(err, DP_ERR_ARG, "knn: k must be positive");
	int kk = k + (skip_self ? 1 : 0);
	int avail = knn->n < (size_t)kk ? (int)knn->n : kk;
	float *q = dp_alloc_array(3 * QUERY_BLOCK, sizeof(float));
	int *ti = dp_alloc_array((size_t)QUERY_BLOCK * (size_t)avail, sizeof(int));
	float *td = dp_alloc_array((size_t)QUERY_BLOCK * (size_t)avail, sizeof(float));
	dp_status st = DP_OK;
	if (!q || !ti || !td) {
		st = dp_fail(err, DP_ERR_NOMEM, "knn: out of memory for queries");
		goto done;
	}
	for (size_t b = 0; b < nq && st == DP_OK; b += QUERY_BLOCK) {
		size_t m = nq - b < QUERY_BLOCK ? nq - b : QUERY_BLOCK;
		for (size_t i = 0; i < m; i++) {
			q[3 * i] = qx[b + i];
			q[3 * i + 1] = qy[b + i];
			q[3 * i + 2] = qz[b + i];
		}
		st = query_block(knn, q, m, k, avail, idx + b * (size_t)k, d2 + b * (size_t)k, ti, td, skip_self, b,
				 err);
	}
done:
	free(q);
	free(ti);
	free(td);
	return st;
}

dp_status dp_knn_query(const dp_knn *knn, size_t nq, const float *qx, const float *qy, const float *qz, int k,
		       int *idx, float *d2, dp_error *err)
{
	return query(knn, nq, qx, qy, qz, k, 0, idx, d2, err);
}

dp_status dp_knn_self(const dp_knn *knn, int k, int *idx, float *d2, dp_error *err)
{
	/* Queries are the indexed points themselves, read back from the copy. */
	float *x = dp_alloc_array(knn->n, sizeof(float)), *y = dp_alloc_array(knn->n, sizeof(float)),
	      *z = dp_alloc_array(knn->n, sizeof(float));
	dp_status st;
	if (!x || !y || !z) {
		st = dp_fail(err, DP_ERR_NOMEM, "knn: out of memory");
	} else {
		for (size_t i = 0; i < knn->n; i++) {
			x[i] = knn->xyz[3 * i];
			y[i] = knn->xyz[3 * i + 1];
			z[i] = knn->xyz[3 * i + 2];
		}
		st = query(knn, knn->n, x, y, z, k, 1, idx, d2, err);
	}
	free(x);
	free(y);
	free(z);
	return st;
}

int dp_knn_radius(const dp_knn *knn, float x, float y, float z, float r2, int *idx, float *d2, int cap)
{
	struct FLANNParameters p = exact_params();
	p.max_neighbors = -1;
	float q[3] = {x, y, z};
	return flann_radius_search_float(knn->index, q, idx, d2, cap, r2, &p);
}

dp_status dp_mean_spacing(size_t n, const float *x, const float *y, const float *z, double *spacing, dp_error *err)
{
	*spacing = 0.0;
	if (n < 2)
		return DP_OK;
	dp_knn knn;
	dp_status st = dp_knn_build(&knn, n, x, y, z, err);
	if (st != DP_OK)
		return st;
	int *idx = dp_alloc_array(n, sizeof(int));
	float *d2 = dp_alloc_array(n, sizeof(float));
	if (!idx || !d2) {
		st = dp_fail(err, DP_ERR_NOMEM, "knn: out of memory");
	} else {
		st = dp_knn_self(&knn, 1, idx, d2, err);
		double sum = 0.0;
		for (size_t i = 0; st == DP_OK && i < n; i++)
			sum += sqrt((double)d2[i]);
		*spacing = sum / (double)n;
	}
	free(idx);
	free(d2);
	dp_knn_free(&knn);
	return st;
}
