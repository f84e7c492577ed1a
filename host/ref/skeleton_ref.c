/* Scalar reference of the meso-skeleton operators: the specification the
 * kernels in kernels/skeleton.cl must match. */
#include "ops/operators.h"

#include <math.h>

void dp_ref_skeleton_cov(const dp_skeleton_cov_args *a)
{
	const dp_grid *g = a->data;
	float r2 = a->radius * a->radius;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float c = 0.0f, sx = 0.0f, sy = 0.0f, sz = 0.0f;
		float sxx = 0.0f, sxy = 0.0f, sxz = 0.0f, syy = 0.0f, syz = 0.0f, szz = 0.0f;
		dp_grid_rows(g, a->qx[i], a->qy[i], a->qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = g->x[k] - a->qx[i], dy = g->y[k] - a->qy[i], dz = g->z[k] - a->qz[i];
				if (dx * dx + dy * dy + dz * dz >= r2)
					continue;
				c += 1.0f;
				sx += dx;
				sy += dy;
				sz += dz;
				sxx += dx * dx;
				sxy += dx * dy;
				sxz += dx * dz;
				syy += dy * dy;
				syz += dy * dz;
				szz += dz * dz;
			}
		float *cov = a->cov + 6 * i;
		a->count[i] = c;
		if (c == 0.0f) {
			for (int m = 0; m < 6; m++)
				cov[m] = 0.0f;
			continue;
		}
		float inv = 1.0f / c, mx = sx * inv, my = sy * inv, mz = sz * inv;
		cov[0] = sxx * inv - mx * mx;
		cov[1] = sxy * inv - mx * my;
		cov[2] = sxz * inv - mx * mz;
		cov[3] = syy * inv - my * my;
		cov[4] = syz * inv - my * mz;
		cov[5] = szz * inv - mz * mz;
	}
}

void dp_ref_skeleton_semiaxes(const dp_skeleton_semiaxes_args *a)
{
	const dp_grid *g = a->data;
	float r2 = a->radius * a->radius;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		const float *v = a->frames + 9 * i;
		float c = 0.0f, s[3] = {0.0f, 0.0f, 0.0f};
		dp_grid_rows(g, a->qx[i], a->qy[i], a->qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = g->x[k] - a->qx[i], dy = g->y[k] - a->qy[i], dz = g->z[k] - a->qz[i];
				if (dx * dx + dy * dy + dz * dz >= r2)
					continue;
				c += 1.0f;
				for (int m = 0; m < 3; m++)
					s[m] += fabsf(a->gnx[k] * v[3 * m] + a->gny[k] * v[3 * m + 1] +
						      a->gnz[k] * v[3 * m + 2]);
			}
		for (int m = 0; m < 3; m++)
			a->semi[3 * i + m] = 1.0f / ((c > 0.0f ? s[m] / c : 0.0f) + a->eps);
	}
}

/* u² = |A_i^T d|², the squared ellipsoid distance in units of r. */
static float ellipsoid_u2(const float *m, float dx, float dy, float dz)
{
	float a = m[0] * dx + m[1] * dy + m[2] * dz;
	float b = m[3] * dx + m[4] * dy + m[5] * dz;
	float c = m[6] * dx + m[7] * dy + m[8] * dz;
	return a * a + b * b + c * c;
}

/* Query i's clamped cell c and its reach rc in cells along x, y, z: the scan
 * takes the rows dp_grid_row(c[0], c[1] + dy, c[2] + dz, rc[0]) for |dy| <=
 * rc[1], |dz| <= rc[2]. */
static void scan_box(const dp_grid *g, float px, float py, float pz, const float *reach, int c[3], int rc[3])
{
	c[0] = dp_grid_coord(g, 0, px);
	c[1] = dp_grid_coord(g, 1, py);
	c[2] = dp_grid_coord(g, 2, pz);
	for (int a = 0; a < 3; a++)
		rc[a] = dp_grid_reach_cells(g, reach[a]);
}

void dp_ref_skeleton_median(const dp_skeleton_median_args *a)
{
	const dp_grid *g = a->data;
	float cut2 = a->cutoff * a->cutoff;
	for (size_t i = 0; i < a->nq; i++) {
		const float *m = a->metric + 9 * i;
		float w = 0.0f, sx = 0.0f, sy = 0.0f, sz = 0.0f;
		int c[3], rc[3];
		scan_box(g, a->qx[i], a->qy[i], a->qz[i], a->reach + 3 * i, c, rc);
		for (int dz = -rc[2]; dz <= rc[2]; dz++)
			for (int dy = -rc[1]; dy <= rc[1]; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, c[0], c[1] + dy, c[2] + dz, rc[0], &beg, &end);
				for (uint32_t k = beg; k < end; k++) {
					float ex = a->qx[i] - g->x[k], ey = a->qy[i] - g->y[k], ez = a->qz[i] - g->z[k];
					float d2 = ex * ex + ey * ey + ez * ez;
					float u2 = ellipsoid_u2(m, ex, ey, ez);
					if (u2 > cut2 || d2 < a->min_d2)
						continue;
					float alpha = expf(-u2) / sqrtf(d2);
					w += alpha;
					sx += alpha * g->x[k];
					sy += alpha * g->y[k];
					sz += alpha * g->z[k];
				}
			}
		float *out = a->median + 3 * i;
		if (w > 0.0f) {
			out[0] = sx / w;
			out[1] = sy / w;
			out[2] = sz / w;
		} else {
			out[0] = a->qx[i];
			out[1] = a->qy[i];
			out[2] = a->qz[i];
		}
	}
}

void dp_ref_skeleton_repulse(const dp_skeleton_repulse_args *a)
{
	const dp_grid *g = a->data;
	float cut2 = a->cutoff * a->cutoff;
	for (size_t i = 0; i < a->nq; i++) {
		const float *m = a->metric + 9 * i;
		float w = 0.0f, sx = 0.0f, sy = 0.0f, sz = 0.0f;
		int c[3], rc[3];
		scan_box(g, a->qx[i], a->qy[i], a->qz[i], a->reach + 3 * i, c, rc);
		for (int dz = -rc[2]; dz <= rc[2]; dz++)
			for (int dy = -rc[1]; dy <= rc[1]; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, c[0], c[1] + dy, c[2] + dz, rc[0], &beg, &end);
				for (uint32_t k = beg; k < end; k++) {
					float ex = a->qx[i] - g->x[k], ey = a->qy[i] - g->y[k], ez = a->qz[i] - g->z[k];
					float d2 = ex * ex + ey * ey + ez * ez;
					float u2 = ellipsoid_u2(m, ex, ey, ez);
					if (u2 > cut2 || d2 < a->min_d2)
						continue;
					float beta = expf(-u2) / (u2 * u2 * sqrtf(u2));
					w += beta;
					sx += beta * ex;
					sy += beta * ey;
					sz += beta * ez;
				}
			}
		float *out = a->repulse + 3 * i;
		if (w > 0.0f) {
			out[0] = sx / w;
			out[1] = sy / w;
			out[2] = sz / w;
		} else {
			out[0] = out[1] = out[2] = 0.0f;
		}
	}
}
