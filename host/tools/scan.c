/* Virtual range scanner: ray-casts a mesh from viewpoints around it. */
#include "core/common.h"
#include "tools/bvh.h"
#include "tools/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SCAN_MAX_VIEWS 100000
#define SCAN_MAX_RES 16384
/* Output is preallocated for every ray (24 bytes each with normals), so the
 * total is capped well below what a host can hold. */
#define SCAN_MAX_RAYS ((size_t)1 << 27)
/* Below this |forward . z| the world z axis is a usable "up" for a view. */
#define SCAN_UP_PARALLEL 0.999

void dp_scan_params_default(dp_scan_params *p)
{
	p->views = 6;
	p->res = 256;
	p->noise = 0;
	p->distance = 2;
	p->perspective = 1;
	p->layout = DP_SCAN_RING;
	p->elevation_deg = 20;
	p->up_axis = 2;
	p->azimuth_deg = 0;
	p->normals = 1;
	p->seed = 1;
}

dp_status dp_scan_params_check(const dp_scan_params *p, dp_error *err)
{
	if (!p)
		return dp_fail(err, DP_ERR_ARG, "scan: no parameters given");
	if (p->views < 1 || p->views > SCAN_MAX_VIEWS)
		return dp_fail(err, DP_ERR_ARG, "scan: views %d outside [1, %d]", p->views, SCAN_MAX_VIEWS);
	if (p->res < 1 || p->res > SCAN_MAX_RES)
		return dp_fail(err, DP_ERR_ARG, "scan: res %d outside [1, %d]", p->res, SCAN_MAX_RES);
	if ((size_t)p->views * (size_t)p->res * (size_t)p->res > SCAN_MAX_RAYS)
		return dp_fail(err, DP_ERR_ARG, "scan: %d views of %d x %d rays exceed %zu rays", p->views, p->res,
			       p->res, SCAN_MAX_RAYS);
	if (!isfinite(p->noise) || p->noise < 0)
		return dp_fail(err, DP_ERR_ARG, "scan: noise %g must be >= 0", p->noise);
	if (!isfinite(p->distance) || p->distance <= 0.5)
		return dp_fail(err, DP_ERR_ARG, "scan: distance %g must exceed 0.5 diagonals (outside the mesh)",
			       p->distance);
	if (p->layout != DP_SCAN_RING && p->layout != DP_SCAN_SPHERE)
		return dp_fail(err, DP_ERR_ARG, "scan: unknown layout %d", (int)p->layout);
	if (p->up_axis < 0 || p->up_axis > 2)
		return dp_fail(err, DP_ERR_ARG, "scan: up axis %d is not 0 (x), 1 (y) or 2 (z)", p->up_axis);
	if (!isfinite(p->elevation_deg) || fabs(p->elevation_deg) > 90 || !isfinite(p->azimuth_deg))
		return dp_fail(err, DP_ERR_ARG, "scan: elevation %g / azimuth %g out of range", p->elevation_deg,
			       p->azimuth_deg);
	return DP_OK;
}

/* Unit direction from the bbox centre to the eye of view v. Computed with
 * the up axis as local z, then rotated cyclically (x, y, z) -> world axes
 * (up + 1, up + 2, up), which keeps the frame right-handed. */
static void view_direction(const dp_scan_params *p, int v, double dir[3])
{
	double az = p->azimuth_deg * M_PI / 180.0, local[3];
	if (p->layout == DP_SCAN_RING) {
		double el = p->elevation_deg * M_PI / 180.0;
		az += 2.0 * M_PI * v / p->views;
		local[0] = cos(el) * cos(az);
		local[1] = cos(el) * sin(az);
		local[2] = sin(el);
	} else {
		/* Fibonacci lattice: equal-area latitude bands, golden-angle azimuths. */
		double z = 1.0 - (2.0 * v + 1.0) / p->views, r = sqrt(fmax(0.0, 1.0 - z * z));
		az += v * M_PI * (3.0 - sqrt(5.0));
		local[0] = r * cos(az);
		local[1] = r * sin(az);
		local[2] = z;
	}
	for (int k = 0; k < 3; k++)
		dir[(p->up_axis + 1 + k) % 3] = local[k];
}

typedef struct frame {
	double centre[3], radius; /* bounding sphere of the bbox */
} frame;

static void mesh_frame(const dp_cloud *mesh, frame *f)
{
	double lo[3], hi[3];
	dp_mesh_bbox(mesh, lo, hi);
	for (int d = 0; d < 3; d++)
		f->centre[d] = 0.5 * (lo[d] + hi[d]);
	f->radius = 0.5 * dp_mesh_diagonal(mesh);
}

static void eye_of(const frame *f, const dp_scan_params *p, int v, double eye[3])
{
	double dir[3];
	view_direction(p, v, dir);
	for (int d = 0; d < 3; d++)
		eye[d] = f->centre[d] + 2.0 * f->radius * p->distance * dir[d];
}

dp_status dp_scan_viewpoints(const dp_cloud *mesh, const dp_scan_params *params, double *eyes, dp_error *err)
{
	dp_status st = dp_mesh_check(mesh, "scan", err);
	if (st == DP_OK)
		st = dp_scan_params_check(params, err);
	if (st != DP_OK)
		return st;
	frame f;
	mesh_frame(mesh, &f);
	for (int v = 0; v < params->views; v++)
		eye_of(&f, params, v, eyes + 3 * v);
	return DP_OK;
}

static void normalize(double v[3])
{
	double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	for (int k = 0; k < 3; k++)
		v[k] /= len;
}

/* Camera basis looking from `eye` at the centre: forward, right, up. */
static void camera(const double eye[3], const double centre[3], int up_axis, double fwd[3], double right[3],
		   double up[3])
{
	for (int d = 0; d < 3; d++)
		fwd[d] = centre[d] - eye[d];
	normalize(fwd);
	double world_up[3] = {0, 0, 0};
	world_up[fabs(fwd[up_axis]) > SCAN_UP_PARALLEL ? (up_axis + 2) % 3 : up_axis] = 1;
	right[0] = fwd[1] * world_up[2] - fwd[2] * world_up[1];
	right[1] = fwd[2] * world_up[0] - fwd[0] * world_up[2];
	right[2] = fwd[0] * world_up[1] - fwd[1] * world_up[0];
	normalize(right);
	up[0] = right[1] * fwd[2] - right[2] * fwd[1];
	up[1] = right[2] * fwd[0] - right[0] * fwd[2];
	up[2] = right[0] * fwd[1] - right[1] * fwd[0];
}

/* Shrinks an over-allocated array to n elements; keeps it when realloc fails. */
static void *shrink(void *p, size_t n, size_t size)
{
	void *q = realloc(p, (n ? n : 1) * size);
	return q ? q : p;
}

static void shrink_cloud(dp_cloud *c)
{
	c->x = shrink(c->x, c->n, sizeof(float));
	c->y = shrink(c->y, c->n, sizeof(float));
	c->z = shrink(c->z, c->n, sizeof(float));
	if (c->nx) {
		c->nx = shrink(c->nx, c->n, sizeof(float));
		c->ny = shrink(c->ny, c->n, sizeof(float));
		c->nz = shrink(c->nz, c->n, sizeof(float));
	}
}

dp_status dp_scan(const dp_cloud *mesh, const dp_scan_params *params, dp_cloud *out,
		  uint32_t **view_of_point, dp_error *err)
{
	memset(out, 0, sizeof *out);
	if (view_of_point)
		*view_of_point = NULL;
	dp_status st = dp_mesh_check(mesh, "scan", err);
	if (st == DP_OK)
		st = dp_scan_params_check(params, err);
	if (st != DP_OK)
		return st;
	frame f;
	mesh_frame(mesh, &f);
	if (!(f.radius > 0))
		return dp_fail(err, DP_ERR_ARG, "scan: the mesh has zero extent");
	dp_bvh bvh;
	st = dp_bvh_build(&bvh, mesh, err);
	if (st != DP_OK)
		return st;
	size_t res = (size_t)params->res, rays = (size_t)params->views * res * res;
	uint32_t *views = NULL;
	st = dp_cloud_alloc(out, rays, params->normals, err);
	if (st == DP_OK && view_of_point && !(views = dp_alloc_array(rays, sizeof(uint32_t)))) {
		dp_cloud_free(out);
		st = dp_fail(err, DP_ERR_NOMEM, "scan: out of memory for %zu rays", rays);
	}
	if (st != DP_OK) {
		dp_bvh_free(&bvh);
		return st;
	}
	double sigma = params->noise * 2.0 * f.radius, reach = 2.0 * f.radius * params->distance;
	/* Rays are spread over the bounding sphere's silhouette: its radius for
	 * parallel rays, the tangent of its half-angle seen from the eye for a
	 * pinhole. */
	double half = params->perspective ? f.radius / sqrt(reach * reach - f.radius * f.radius) : f.radius;
	double tmax = reach + 2.0 * f.radius;
	dp_rng rng;
	dp_rng_seed(&rng, params->seed);
	size_t n = 0;
	for (int v = 0; v < params->views; v++) {
		double eye[3], fwd[3], right[3], up[3];
		eye_of(&f, params, v, eye);
		camera(eye, f.centre, params->up_axis, fwd, right, up);
		for (size_t j = 0; j < res; j++) {
			double sy = half * ((2.0 * j + 1.0) / res - 1.0);
			for (size_t i = 0; i < res; i++) {
				double sx = half * ((2.0 * i + 1.0) / res - 1.0), o[3], d[3];
				for (int k = 0; k < 3; k++) {
					if (params->perspective) {
						o[k] = eye[k];
						d[k] = fwd[k] + sx * right[k] + sy * up[k];
					} else {
						o[k] = eye[k] + sx * right[k] + sy * up[k];
						d[k] = fwd[k];
					}
				}
				normalize(d);
				dp_bvh_hit hit;
				if (!dp_bvh_raycast(&bvh, o, d, tmax, &hit))
					continue;
				double p[3];
				for (int k = 0; k < 3; k++) {
					p[k] = o[k] + hit.t * d[k];
					if (sigma > 0)
						p[k] += sigma * dp_rng_normal(&rng);
				}
				out->x[n] = (float)p[0];
				out->y[n] = (float)p[1];
				out->z[n] = (float)p[2];
				if (params->normals) {
					double nrm[3];
					dp_mesh_triangle_normal(mesh, hit.face, nrm);
					double s = nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2] > 0 ? -1.0 : 1.0;
					out->nx[n] = (float)(s * nrm[0]);
					out->ny[n] = (float)(s * nrm[1]);
					out->nz[n] = (float)(s * nrm[2]);
				}
				if (views)
					views[n] = (uint32_t)v;
				n++;
			}
		}
	}
	dp_bvh_free(&bvh);
	if (n == 0) {
		dp_cloud_free(out);
		free(views);
		return dp_fail(err, DP_ERR_EMPTY, "scan: no ray hit the mesh");
	}
	out->n = n;
	shrink_cloud(out);
	if (view_of_point)
		*view_of_point = shrink(views, n, sizeof(uint32_t));
	return DP_OK;
}
