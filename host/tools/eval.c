/* Metrics of a point set against a ground-truth mesh: accuracy, completeness,
 * coverage, normal error and flips (all, and those the points' spacing
 * resolves), spacing uniformity, and the points' scatter off a surface. */
#include "core/common.h"
#include "core/eig3.h"
#include "knn/knn.h"
#include "tools/bvh.h"
#include "tools/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Surface samples are stored like any cloud; this keeps a typo from asking
 * for gigabytes. */
#define EVAL_MAX_SAMPLES ((size_t)1 << 26)
/* A normal shorter than this is treated as missing. */
#define EVAL_MIN_NORMAL 1e-12
#define EVAL_PERCENTILE 0.95

void dp_eval_params_default(dp_eval_params *p)
{
	p->samples = 20000;
	p->coverage_factor = 1.5;
	p->seed = 1;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

dp_status dp_eval_params_check(const dp_eval_params *p, dp_error *err)
{
	if (!p)
		return DP_OK; /* dp_eval's defaults */
	if (p->samples == 0 || p->samples > EVAL_MAX_SAMPLES)
		return dp_fail(err, DP_ERR_ARG, "eval: samples %zu outside [1, %zu]", p->samples, EVAL_MAX_SAMPLES);
	if (!isfinite(p->coverage_factor) || p->coverage_factor <= 0)
		return dp_fail(err, DP_ERR_ARG, "eval: coverage factor %g must be > 0", p->coverage_factor);
	return DP_OK;
}

static dp_status check_inputs(const dp_cloud *mesh, const dp_cloud *points, const dp_eval_params *p,
			      dp_error *err)
{
	dp_status st = dp_mesh_check(mesh, "eval", err);
	if (st == DP_OK)
		st = dp_eval_params_check(p, err);
	if (st != DP_OK)
		return st;
	if (!points || points->n < 2)
		return dp_fail(err, DP_ERR_EMPTY, "eval: need at least 2 points, got %zu", points ? points->n : 0);
	for (size_t i = 0; i < points->n; i++)
		if (!isfinite(points->x[i]) || !isfinite(points->y[i]) || !isfinite(points->z[i]))
			return dp_fail(err, DP_ERR_ARG, "eval: point %zu is not finite", i);
	if (!(dp_mesh_diagonal(mesh) > 0))
		return dp_fail(err, DP_ERR_ARG, "eval: the mesh has zero extent");
	return DP_OK;
}

/* Accuracy and normal metrics: each point against its nearest triangle; a
 * flip is clear when no face within the point's distance plus `tolerance`
 * faces along its normal. */
static void point_to_surface(const dp_bvh *bvh, const dp_cloud *mesh, const dp_cloud *points, double tolerance,
			     double *dist, dp_eval_result *r)
{
	double angle_sum = 0;
	size_t flipped = 0, clear = 0, used = 0;
	for (size_t i = 0; i < points->n; i++) {
		double p[3] = {points->x[i], points->y[i], points->z[i]}, q[3];
		uint32_t face;
		dist[i] = sqrt(dp_bvh_nearest(bvh, p, q, &face));
		if (!points->nx)
			continue;
		double n[3] = {points->nx[i], points->ny[i], points->nz[i]}, t[3];
		double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		if (!isfinite(len) || len < EVAL_MIN_NORMAL || dp_mesh_triangle_normal(mesh, face, t) <= 0)
			continue;
		double c = (n[0] * t[0] + n[1] * t[1] + n[2] * t[2]) / len;
		if (c < 0) {
			double reach = dist[i] + tolerance;
			flipped++;
			clear += !dp_bvh_facing_within(bvh, p, reach * reach, n);
		}
		angle_sum += acos(fmin(fabs(c), 1.0)) * 180.0 / M_PI;
		used++;
	}
	r->normals_used = used;
	r->has_normals = used > 0;
	r->normal_angle_deg = used ? angle_sum / (double)used : 0;
	r->normal_flipped = used ? (double)flipped / (double)used : 0;
	r->normal_flipped_clear = used ? (double)clear / (double)used : 0;
}

static void accuracy_stats(double *dist, size_t n, double diag, dp_eval_result *r)
{
	double sum = 0, sum2 = 0, max = 0;
	for (size_t i = 0; i < n; i++) {
		sum += dist[i];
		sum2 += dist[i] * dist[i];
		max = fmax(max, dist[i]);
	}
	qsort(dist, n, sizeof *dist, cmp_double);
	/* Nearest-rank percentile. */
	size_t rank = (size_t)ceil(EVAL_PERCENTILE * (double)n);
	r->accuracy_mean = sum / (double)n / diag;
	r->accuracy_rms = sqrt(sum2 / (double)n) / diag;
	r->accuracy_max = max / diag;
	r->accuracy_p95 = dist[rank > 0 ? rank - 1 : 0] / diag;
}

/* The median is read off at most this many points, chosen evenly at random
 * through the set, their neighbours among all of them: its sampling error
 * is then below a percent, and a scan of millions of points does not double
 * the time of the whole evaluation. */
#define SCATTER_MAX_POINTS 100000
/* The point itself, at distance 0, and its neighbours. */
#define SCATTER_K (DP_EVAL_SCATTER_NEIGHBOURS + 1)

/* dp_eval_result.scatter_median, the neighbours from knn's index of all the
 * points. Offsets are taken from the point itself, which keeps float
 * positions far from the origin precise. */
static dp_status scatter(const dp_knn *knn, const dp_cloud *points, uint64_t seed, dp_eval_result *r,
			 dp_error *err)
{
	size_t n = points->n, m = n < SCATTER_MAX_POINTS ? n : SCATTER_MAX_POINTS;
	int k = n < SCATTER_K ? (int)n : SCATTER_K;
	double *ratio = dp_alloc_array(m, sizeof(double));
	float *q = m < n ? dp_alloc_array(m, 3 * sizeof(float)) : NULL;
	int *idx = dp_alloc_array(m * (size_t)k, sizeof(int));
	float *d2 = dp_alloc_array(m * (size_t)k, sizeof(float));
	dp_status st = DP_OK;
	if (!ratio || (m < n && !q) || !idx || !d2) {
		st = dp_fail(err, DP_ERR_NOMEM, "eval: out of memory for the scatter of %zu points", m);
		goto done;
	}
	const float *qx = points->x, *qy = points->y, *qz = points->z;
	if (q) {
		/* one point from each of m equal runs of the set: scan order
		 * has rows, which a fixed stride could alias with */
		dp_rng rng;
		dp_rng_seed(&rng, seed);
		for (size_t j = 0; j < m; j++) {
			size_t at = (size_t)(((double)j + dp_rng_uniform(&rng)) * (double)n / (double)m);
			at = at < n ? at : n - 1;
			q[j] = points->x[at], q[m + j] = points->y[at], q[2 * m + j] = points->z[at];
		}
		qx = q, qy = q + m, qz = q + 2 * m;
	}
	if ((st = dp_knn_query(knn, m, qx, qy, qz, k, idx, d2, err)) != DP_OK)
		goto done;
	for (size_t j = 0; j < m; j++) {
		dp_moments mo = {0};
		for (int a = 0; a < k; a++) {
			int i = idx[j * (size_t)k + (size_t)a];
			if (i < 0)
				continue;
			double d[3] = {(double)points->x[i] - qx[j], (double)points->y[i] - qy[j],
				       (double)points->z[i] - qz[j]};
			dp_moments_add(&mo, d);
		}
		double cov[6], w[3], v[3][3];
		dp_moments_cov(&mo, cov);
		dp_eig3_sym(cov, w, v);
		ratio[j] = w[2] > 0.0 ? sqrt(fmax(w[0], 0.0) / w[2]) : 0.0;
	}
	qsort(ratio, m, sizeof *ratio, cmp_double);
	r->scatter_median = m % 2 ? ratio[m / 2] : 0.5 * (ratio[m / 2 - 1] + ratio[m / 2]);
done:
	free(ratio);
	free(q);
	free(idx);
	free(d2);
	return st;
}

/* Spacing (nearest other point), scatter and, for the surface samples,
 * completeness and coverage against the points. */
static dp_status spacing_and_coverage(const dp_cloud *mesh, const dp_cloud *points, const dp_eval_params *p,
				      double diag, dp_eval_result *r, dp_error *err)
{
	size_t n = points->n, m = p->samples, most = n > m ? n : m;
	dp_knn knn;
	dp_cloud samples = {0};
	int *idx = dp_alloc_array(most, sizeof(int));
	float *d2 = dp_alloc_array(most, sizeof(float));
	if (!idx || !d2) {
		free(idx);
		free(d2);
		return dp_fail(err, DP_ERR_NOMEM, "eval: out of memory for %zu neighbours", most);
	}
	dp_status st = dp_knn_build(&knn, n, points->x, points->y, points->z, err);
	if (st != DP_OK)
		goto done_buffers;
	st = dp_knn_self(&knn, 1, idx, d2, err);
	if (st != DP_OK)
		goto done;
	double sum = 0, sum2 = 0;
	for (size_t i = 0; i < n; i++) {
		double s = sqrt((double)d2[i]);
		sum += s;
		sum2 += s * s;
	}
	double mean = sum / (double)n, var = fmax(sum2 / (double)n - mean * mean, 0.0);
	r->spacing_mean = mean / diag;
	r->spacing_cv = mean > 0 ? sqrt(var) / mean : 0;
	r->coverage_radius = p->coverage_factor * r->spacing_mean;
	st = scatter(&knn, points, p->seed, r, err);
	if (st != DP_OK)
		goto done;

	st = dp_mesh_sample(mesh, m, 0.0, p->seed, &samples, err);
	if (st != DP_OK)
		goto done;
	st = dp_knn_query(&knn, m, samples.x, samples.y, samples.z, 1, idx, d2, err);
	if (st != DP_OK)
		goto done;
	double total = 0, radius = r->coverage_radius * diag;
	size_t covered = 0;
	for (size_t i = 0; i < m; i++) {
		double d = sqrt((double)d2[i]);
		total += d;
		covered += d <= radius;
	}
	r->samples = m;
	r->completeness_mean = total / (double)m / diag;
	r->coverage = (double)covered / (double)m;
done:
	dp_cloud_free(&samples);
	dp_knn_free(&knn);
done_buffers:
	free(idx);
	free(d2);
	return st;
}

dp_status dp_eval(const dp_cloud *mesh, const dp_cloud *points, const dp_eval_params *params,
		  dp_eval_result *result, dp_error *err)
{
	double t0 = dp_seconds();
	dp_eval_params defaults;
	if (!params) {
		dp_eval_params_default(&defaults);
		params = &defaults;
	}
	memset(result, 0, sizeof *result);
	dp_status st = check_inputs(mesh, points, params, err);
	if (st != DP_OK)
		return st;
	double diag = dp_mesh_diagonal(mesh);
	result->points = points->n;
	result->diagonal = diag;

	/* the spacing first: it sets the tolerance of the clear flips */
	st = spacing_and_coverage(mesh, points, params, diag, result, err);
	if (st != DP_OK)
		return st;
	double *dist = dp_alloc_array(points->n, sizeof(double));
	if (!dist)
		return dp_fail(err, DP_ERR_NOMEM, "eval: out of memory for %zu points", points->n);
	dp_bvh bvh;
	st = dp_bvh_build(&bvh, mesh, err);
	if (st != DP_OK) {
		free(dist);
		return st;
	}
	point_to_surface(&bvh, mesh, points, 0.5 * result->spacing_mean * diag, dist, result);
	dp_bvh_free(&bvh);
	accuracy_stats(dist, points->n, diag, result);
	free(dist);
	result->seconds = dp_seconds() - t0;
	return DP_OK;
}

void dp_eval_json(const dp_eval_result *r, FILE *out)
{
	fprintf(out,
		"{\"points\": %zu, \"samples\": %zu, \"diagonal\": %.9g, \"accuracy_mean\": %.9g, "
		"\"accuracy_p95\": %.9g, \"accuracy_rms\": %.9g, \"accuracy_max\": %.9g, "
		"\"completeness_mean\": %.9g, \"coverage\": %.9g, \"coverage_radius\": %.9g, "
		"\"spacing_mean\": %.9g, \"spacing_cv\": %.9g, \"scatter_median\": %.9g, ",
		r->points, r->samples, r->diagonal, r->accuracy_mean, r->accuracy_p95, r->accuracy_rms,
		r->accuracy_max, r->completeness_mean, r->coverage, r->coverage_radius, r->spacing_mean,
		r->spacing_cv, r->scatter_median);
	if (r->has_normals)
		fprintf(out,
			"\"normals_used\": %zu, \"normal_angle_deg\": %.9g, \"normal_flipped\": %.9g, "
			"\"normal_flipped_clear\": %.9g, ",
			r->normals_used, r->normal_angle_deg, r->normal_flipped, r->normal_flipped_clear);
	else
		fprintf(out, "\"normals_used\": 0, \"normal_angle_deg\": null, \"normal_flipped\": null, "
			     "\"normal_flipped_clear\": null, ");
	fprintf(out, "\"seconds\": %.6g}\n", r->seconds);
}
