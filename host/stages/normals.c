/* Normal estimation (DESIGN §4 "Normals"): PCA over the k nearest neighbours,
 * then a consistent outward orientation (stages/orient.c) or, when the
 * scanner position is known, orientation towards it. */
#include "core/common.h"
#include "core/distinct.h"
#include "core/eig3.h"
#include "knn/knn.h"
#include "stages/orient.h"

#include <math.h>
#include <stdlib.h>

/* How far (in mean nearest-neighbour spacings) a fragment cut off from the
 * body by a gap still takes its orientation from the body
 * (dp_orient_outward): the one-view bunny's foot top lies 4.6 under its
 * belly. Not tuned beyond that: CGAL's hippo2 has a strip right at 10
 * (linked), and a separate object nearer than this is linked too, which
 * the mirrored test gets right where the two face each other across the
 * gap. */
#define LINK_RANGE 10.0

void dp_normal_params_default(dp_normal_params *p)
{
	p->k = 16;
	p->k_graph = 8;
	p->use_viewpoint = 0;
	p->viewpoint[0] = p->viewpoint[1] = p->viewpoint[2] = 0.0;
}

static dp_status validate(const dp_cloud *cloud, const dp_normal_params *p, dp_error *err)
{
	if (!cloud)
		return dp_fail(err, DP_ERR_ARG, "normals: no point cloud given");
	if (cloud->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "normals: the point cloud is empty");
	if (cloud->n > INT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "normals: %zu points exceed the kNN index range", cloud->n);
	if (p->k < 2)
		return dp_fail(err, DP_ERR_ARG, "normals: PCA neighbourhood k = %d, need at least 2", p->k);
	if (p->k_graph < 1)
		return dp_fail(err, DP_ERR_ARG, "normals: orientation graph degree k_graph = %d, need at least 1",
			       p->k_graph);
	if (p->use_viewpoint &&
	    !(isfinite(p->viewpoint[0]) && isfinite(p->viewpoint[1]) && isfinite(p->viewpoint[2])))
		return dp_fail(err, DP_ERR_ARG, "normals: the viewpoint is not finite");
	for (size_t i = 0; i < cloud->n; i++)
		if (!isfinite(cloud->x[i]) || !isfinite(cloud->y[i]) || !isfinite(cloud->z[i]))
			return dp_fail(err, DP_ERR_ARG, "normals: point %zu has a non-finite coordinate", i);
	return dp_check_span("normals", cloud->n, cloud->x, cloud->y, cloud->z, err);
}

/* Covariance of point i and its first k listed neighbours, taken about p_i in
 * double so large coordinates keep their precision. Writes the unit normal
 * (for a line or a repeated point, whose normal is undefined, dp_eig3_sym's
 * unit vector for the smallest eigenvalue is still some perpendicular);
 * returns the total variance, proportional to the area the point stands for. */
static double pca_normal(const dp_cloud *c, size_t i, const int *nb, int k)
{
	/* the point itself, at offset 0, then its neighbours */
	dp_moments mom = {{0, 0, 0}, {0, 0, 0, 0, 0, 0}, 0};
	double zero[3] = {0, 0, 0}, cov[6];
	dp_moments_add(&mom, zero);
	for (int m = 0; m < k; m++) {
		if (nb[m] < 0)
			continue;
		size_t j = (size_t)nb[m];
		double d[3] = {(double)c->x[j] - c->x[i], (double)c->y[j] - c->y[i], (double)c->z[j] - c->z[i]};
		dp_moments_add(&mom, d);
	}
	dp_moments_cov(&mom, cov);
	double w[3], v[3][3];
	dp_eig3_sym(cov, w, v);
	c->nx[i] = (float)v[0][0];
	c->ny[i] = (float)v[0][1];
	c->nz[i] = (float)v[0][2];
	double total = w[0] + w[1] + w[2];
	return total > 0.0 ? total : 0.0;
}

static void orient_to_viewpoint(dp_cloud *c, const double v[3])
{
	for (size_t i = 0; i < c->n; i++) {
		double d = (v[0] - c->x[i]) * c->nx[i] + (v[1] - c->y[i]) * c->ny[i] + (v[2] - c->z[i]) * c->nz[i];
		if (d < 0.0) {
			c->nx[i] = -c->nx[i];
			c->ny[i] = -c->ny[i];
			c->nz[i] = -c->nz[i];
		}
	}
}

/* Normals of a cloud of distinct points (the caller has removed duplicates). */
static dp_status normals_of_distinct(dp_cloud *cloud, const dp_normal_params *params, dp_error *err)
{
	size_t n = cloud->n;
	/* Tiny inputs: every other point is a neighbour. */
	size_t others = n - 1;
	int k = (size_t)params->k < others ? params->k : (int)others;
	int kg = (size_t)params->k_graph < others ? params->k_graph : (int)others;
	int stride = k > kg ? k : kg;

	dp_status st = DP_OK;
	dp_knn knn = {0};
	int *nbr = dp_alloc_array(n * (size_t)(stride ? stride : 1), sizeof *nbr);
	float *d2 = dp_alloc_array(n * (size_t)(stride ? stride : 1), sizeof *d2);
	double *area = dp_alloc_array(n, sizeof *area);
	uint32_t *comp = dp_alloc_array(n, sizeof *comp);
	if (!nbr || !d2 || !area || !comp) {
		st = dp_fail(err, DP_ERR_NOMEM, "normals: out of memory for %zu points", n);
		goto done;
	}
	if (stride > 0) {
		st = dp_knn_build(&knn, n, cloud->x, cloud->y, cloud->z, err);
		if (st == DP_OK)
			st = dp_knn_self(&knn, stride, nbr, d2, err);
		if (st != DP_OK)
			goto done;
	}
	for (size_t i = 0; i < n; i++)
		area[i] = pca_normal(cloud, i, nbr + i * (size_t)stride, k);

	if (params->use_viewpoint) {
		orient_to_viewpoint(cloud, params->viewpoint);
	} else {
		size_t ncomp;
		/* Eq. 1's mean spacing, from the neighbour lists at hand */
		double spacing = 0.0;
		for (size_t i = 0; stride > 0 && i < n; i++)
			spacing += sqrt((double)d2[i * (size_t)stride]) / (double)n;
		st = dp_orient_mst(n, cloud->x, cloud->y, cloud->z, cloud->nx, cloud->ny, cloud->nz, nbr, stride, kg,
				   comp, &ncomp, err);
		if (st == DP_OK)
			st = dp_orient_outward(n, cloud->x, cloud->y, cloud->z, cloud->nx, cloud->ny, cloud->nz, area,
					       comp, ncomp, LINK_RANGE * spacing, NULL, err);
	}
done:
	dp_knn_free(&knn);
	free(nbr);
	free(d2);
	free(area);
	free(comp);
	return st;
}

/* Exact duplicates (merged overlapping scans) would crowd the neighbourhoods
 * with copies and leave a point repeated more than k times without any
 * neighbourhood at all, so the work runs on the distinct positions: `distinct`
 * receives them (with normal arrays) and of[i] the distinct point of point i. */
static dp_status distinct_positions(const dp_cloud *cloud, dp_cloud *distinct, uint32_t *of, dp_error *err)
{
	size_t n = cloud->n, m;
	dp_status st = dp_distinct(n, cloud->x, cloud->y, cloud->z, of, &m, err);
	if (st == DP_OK)
		st = dp_cloud_alloc(distinct, m, 1, err);
	if (st != DP_OK)
		return st;
	/* of[i] <= i, so a repeated point's slot is known when it is reached */
	uint32_t u = 0;
	for (size_t i = 0; i < n; i++) {
		if (of[i] != i) {
			of[i] = of[of[i]];
			continue;
		}
		distinct->x[u] = cloud->x[i];
		distinct->y[u] = cloud->y[i];
		distinct->z[u] = cloud->z[i];
		of[i] = u++;
	}
	return DP_OK;
}

dp_status dp_estimate_normals(dp_cloud *cloud, const dp_normal_params *params, dp_error *err)
{
	dp_normal_params defaults;
	if (!params) {
		dp_normal_params_default(&defaults);
		params = &defaults;
	}
	dp_status st = validate(cloud, params, err);
	if (st != DP_OK)
		return st;
	st = dp_cloud_add_normals(cloud, err);
	if (st != DP_OK)
		return st;
	dp_cloud distinct = {0};
	uint32_t *of = dp_alloc_array(cloud->n, sizeof *of);
	if (!of)
		return dp_fail(err, DP_ERR_NOMEM, "normals: out of memory for %zu points", cloud->n);
	st = distinct_positions(cloud, &distinct, of, err);
	if (st == DP_OK)
		st = normals_of_distinct(&distinct, params, err);
	if (st == DP_OK)
		for (size_t i = 0; i < cloud->n; i++) {
			cloud->nx[i] = distinct.nx[of[i]];
			cloud->ny[i] = distinct.ny[of[i]];
			cloud->nz[i] = distinct.nz[of[i]];
		}
	dp_cloud_free(&distinct);
	free(of);
	return st;
}
