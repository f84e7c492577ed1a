#include "tools/mesh.h"

#include "core/common.h"

#include <math.h>
#include <stdlib.h>

dp_status dp_mesh_check(const dp_cloud *mesh, const char *stage, dp_error *err)
{
	if (!mesh || !mesh->faces || mesh->nfaces == 0)
		return dp_fail(err, DP_ERR_ARG, "%s: the input is not a triangle mesh (it has no faces)", stage);
	if (mesh->n > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "%s: mesh has %zu vertices, more than 32-bit indices reach",
			       stage, mesh->n);
	for (size_t i = 0; i < mesh->n; i++)
		if (!isfinite(mesh->x[i]) || !isfinite(mesh->y[i]) || !isfinite(mesh->z[i]))
			return dp_fail(err, DP_ERR_FORMAT, "%s: mesh vertex %zu is not finite", stage, i);
	for (size_t k = 0; k < 3 * mesh->nfaces; k++)
		if (mesh->faces[k] >= mesh->n)
			return dp_fail(err, DP_ERR_FORMAT, "%s: face %zu uses vertex %u of only %zu", stage,
				       k / 3, mesh->faces[k], mesh->n);
	return DP_OK;
}

void dp_mesh_bbox(const dp_cloud *mesh, double lo[3], double hi[3])
{
	const float *c[3] = {mesh->x, mesh->y, mesh->z};
	for (int d = 0; d < 3; d++) {
		lo[d] = INFINITY;
		hi[d] = -INFINITY;
		for (size_t i = 0; i < mesh->n; i++) {
			lo[d] = fmin(lo[d], c[d][i]);
			hi[d] = fmax(hi[d], c[d][i]);
		}
	}
}

double dp_mesh_diagonal(const dp_cloud *mesh)
{
	double lo[3], hi[3];
	dp_mesh_bbox(mesh, lo, hi);
	return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
		    (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

void dp_mesh_triangle(const dp_cloud *mesh, size_t f, double a[3], double b[3], double c[3])
{
	double *out[3] = {a, b, c};
	for (int k = 0; k < 3; k++) {
		uint32_t v = mesh->faces[3 * f + k];
		out[k][0] = mesh->x[v];
		out[k][1] = mesh->y[v];
		out[k][2] = mesh->z[v];
	}
}

double dp_mesh_triangle_normal(const dp_cloud *mesh, size_t f, double n[3])
{
	double a[3], b[3], c[3];
	dp_mesh_triangle(mesh, f, a, b, c);
	double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
	double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	if (len > 0) {
		n[0] /= len;
		n[1] /= len;
		n[2] /= len;
	}
	return 0.5 * len;
}

double dp_mesh_area(const dp_cloud *mesh)
{
	double total = 0, n[3];
	for (size_t f = 0; f < mesh->nfaces; f++)
		total += dp_mesh_triangle_normal(mesh, f, n);
	return total;
}

double dp_mesh_signed_volume(const dp_cloud *mesh)
{
	/* Relative to the bbox centre, so that far-from-origin meshes do not lose
	 * the volume to cancellation. */
	double lo[3], hi[3];
	dp_mesh_bbox(mesh, lo, hi);
	double o[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
	double total = 0, a[3], b[3], c[3];
	for (size_t f = 0; f < mesh->nfaces; f++) {
		dp_mesh_triangle(mesh, f, a, b, c);
		for (int d = 0; d < 3; d++) {
			a[d] -= o[d];
			b[d] -= o[d];
			c[d] -= o[d];
		}
		total += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
			 a[2] * (b[0] * c[1] - b[1] * c[0]);
	}
	return total / 6.0;
}

/* Index of the first cumulative area above `target` (binary search). */
static size_t pick_face(const double *cumulative, size_t nfaces, double target)
{
	size_t lo = 0, hi = nfaces - 1;
	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		if (cumulative[mid] > target)
			hi = mid;
		else
			lo = mid + 1;
	}
	return lo;
}

dp_status dp_mesh_sample(const dp_cloud *mesh, size_t n, double noise, uint64_t seed,
			 dp_cloud *out, dp_error *err)
{
	dp_status st = dp_mesh_check(mesh, "mesh sample", err);
	if (st != DP_OK)
		return st;
	if (n == 0)
		return dp_fail(err, DP_ERR_ARG, "mesh sample: asked for 0 samples");
	if (!(noise >= 0) || !isfinite(noise))
		return dp_fail(err, DP_ERR_ARG, "mesh sample: noise %g must be >= 0", noise);
	double *cumulative = dp_alloc_array(mesh->nfaces, sizeof(double));
	if (!cumulative)
		return dp_fail(err, DP_ERR_NOMEM, "mesh sample: out of memory for %zu faces", mesh->nfaces);
	double total = 0, nrm[3];
	for (size_t f = 0; f < mesh->nfaces; f++) {
		total += dp_mesh_triangle_normal(mesh, f, nrm);
		cumulative[f] = total;
	}
	if (!(total > 0)) {
		free(cumulative);
		return dp_fail(err, DP_ERR_ARG, "mesh sample: the mesh has zero area");
	}
	st = dp_cloud_alloc(out, n, 1, err);
	if (st != DP_OK) {
		free(cumulative);
		return st;
	}
	double sigma = noise * dp_mesh_diagonal(mesh);
	dp_rng rng;
	dp_rng_seed(&rng, seed);
	for (size_t i = 0; i < n; i++) {
		size_t f = pick_face(cumulative, mesh->nfaces, dp_rng_uniform(&rng) * total);
		double a[3], b[3], c[3];
		dp_mesh_triangle(mesh, f, a, b, c);
		dp_mesh_triangle_normal(mesh, f, nrm);
		/* sqrt warps the first coordinate so the density is uniform in area. */
		double r1 = sqrt(dp_rng_uniform(&rng)), r2 = dp_rng_uniform(&rng);
		double wa = 1.0 - r1, wb = r1 * (1.0 - r2), wc = r1 * r2;
		double p[3];
		for (int d = 0; d < 3; d++) {
			p[d] = wa * a[d] + wb * b[d] + wc * c[d];
			if (sigma > 0)
				p[d] += sigma * dp_rng_normal(&rng);
		}
		out->x[i] = (float)p[0];
		out->y[i] = (float)p[1];
		out->z[i] = (float)p[2];
		out->nx[i] = (float)nrm[0];
		out->ny[i] = (float)nrm[1];
		out->nz[i] = (float)nrm[2];
	}
	free(cumulative);
	return DP_OK;
}
