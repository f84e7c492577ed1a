/* Scalar reference of the surface consolidation operators: the specification
 * the kernels in kernels/surface.cl must match (meanings in
 * host/ops/operators.h). */
#include "ops/operators.h"

#include <math.h>

void dp_ref_surface_data(const dp_surface_data_args *a)
{
	const dp_grid *g = a->input;
	float rad2 = a->radius * a->radius, inv_r = 1.0f / a->r;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float px = a->px[i], py = a->py[i], pz = a->pz[i];
		float eta = 1.0f, sa = 0.0f, sx = 0.0f, sy = 0.0f, sz = 0.0f;
		dp_grid_rows(g, px, py, pz, beg, end);
		for (int row = 0; row < 9; row++)
			for (uint32_t k = beg[row]; k < end[row]; k++) {
				float dx = g->x[k] - px, dy = g->y[k] - py, dz = g->z[k] - pz;
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 >= rad2)
					continue;
				if (!(dx * a->sx[i] + dy * a->sy[i] + dz * a->sz[i] + a->depth[i] > 0.0f))
					continue; /* behind the inner end: the far side of a thin part */
				float theta = expf(-d2 * inv_r * inv_r);
				eta += theta;
				if (d2 < a->min_d2)
					continue;
				float alpha = theta / (sqrtf(d2) * inv_r);
				sa += alpha;
				sx += alpha * dx;
				sy += alpha * dy;
				sz += alpha * dz;
			}
		a->eta[i] = eta;
		a->sum_alpha[i] = sa;
		a->ox[i] = sa > 0.0f ? sx / sa : 0.0f;
		a->oy[i] = sa > 0.0f ? sy / sa : 0.0f;
		a->oz[i] = sa > 0.0f ? sz / sa : 0.0f;
	}
}

void dp_ref_surface_neighbour(const dp_surface_neighbour_args *a)
{
	const dp_grid *g = a->surface;
	float rad2 = a->radius * a->radius, inv_r = 1.0f / a->r;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float px = a->px[i], py = a->py[i], pz = a->pz[i];
		float nx = a->nx[i], ny = a->ny[i], nz = a->nz[i], len = a->len[i];
		float count = 0.0f, sd = 0.0f, sd2 = 0.0f, st = 0.0f, stl = 0.0f;
		float sb = 0.0f, bx = 0.0f, by = 0.0f, bz = 0.0f, nn2 = rad2;
		float cx = 0.0f, cy = 0.0f, cz = 0.0f;
		dp_grid_rows(g, px, py, pz, beg, end);
		for (int row = 0; row < 9; row++)
			for (uint32_t k = beg[row]; k < end[row]; k++) {
				float dx = px - g->x[k], dy = py - g->y[k], dz = pz - g->z[k];
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 >= rad2)
					continue;
				if (!(nx * a->gnx[k] + ny * a->gny[k] + nz * a->gnz[k] > a->side_cos))
					continue;
				float theta = expf(-d2 * inv_r * inv_r);
				float dl = a->glen[k] - len;
				count += 1.0f;
				sd += dl * inv_r;
				sd2 += (dl * inv_r) * (dl * inv_r);
				st += theta;
				stl += theta * dl;
				cx -= theta * dx;
				cy -= theta * dy;
				cz -= theta * dz;
				if (d2 < a->min_d2)
					continue;
				nn2 = fminf(nn2, d2);
				float dn = dx * nx + dy * ny + dz * nz;
				float tx = dx - dn * nx, ty = dy - dn * ny, tz = dz - dn * nz;
				float t = fmaxf(sqrtf(tx * tx + ty * ty + tz * tz) * inv_r, a->tfloor);
				float beta = theta / (t * t * t * t * t);
				sb += beta;
				bx += beta * tx;
				by += beta * ty;
				bz += beta * tz;
			}
		float mean = count > 0.0f ? sd / count : 0.0f;
		a->L[i] = st > 0.0f ? len + stl / st : len;
		a->var[i] = count > 0.0f ? fmaxf(sd2 / count - mean * mean, 0.0f) : 0.0f;
		a->rx[i] = sb > 0.0f ? bx / sb : 0.0f;
		a->ry[i] = sb > 0.0f ? by / sb : 0.0f;
		a->rz[i] = sb > 0.0f ? bz / sb : 0.0f;
		a->nn[i] = sqrtf(nn2);
		a->mx[i] = st > 0.0f ? cx / st : 0.0f;
		a->my[i] = st > 0.0f ? cy / st : 0.0f;
		a->mz[i] = st > 0.0f ? cz / st : 0.0f;
	}
}

void dp_ref_surface_covariance(const dp_surface_covariance_args *a)
{
	const dp_grid *g = a->surface;
	float rad2 = a->radius * a->radius, inv_r = 1.0f / a->r;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float px = a->px[i], py = a->py[i], pz = a->pz[i];
		float n = 0.0f, mx = 0.0f, my = 0.0f, mz = 0.0f;
		float cxx = 0.0f, cxy = 0.0f, cxz = 0.0f, cyy = 0.0f, cyz = 0.0f, czz = 0.0f;
		dp_grid_rows(g, px, py, pz, beg, end);
		for (int row = 0; row < 9; row++)
			for (uint32_t k = beg[row]; k < end[row]; k++) {
				float dx = g->x[k] - px, dy = g->y[k] - py, dz = g->z[k] - pz;
				if (dx * dx + dy * dy + dz * dz >= rad2)
					continue;
				if (!(a->nx[i] * a->gnx[k] + a->ny[i] * a->gny[k] + a->nz[i] * a->gnz[k] > a->side_cos))
					continue;
				dx *= inv_r;
				dy *= inv_r;
				dz *= inv_r;
				n += 1.0f;
				mx += dx;
				my += dy;
				mz += dz;
				cxx += dx * dx;
				cxy += dx * dy;
				cxz += dx * dz;
				cyy += dy * dy;
				cyz += dy * dz;
				czz += dz * dz;
			}
		float *c = a->cov + 6 * i;
		if (n == 0.0f) {
			for (int m = 0; m < 6; m++)
				c[m] = 0.0f;
			continue;
		}
		mx /= n;
		my /= n;
		mz /= n;
		c[0] = cxx / n - mx * mx;
		c[1] = cxy / n - mx * my;
		c[2] = cxz / n - mx * mz;
		c[3] = cyy / n - my * my;
		c[4] = cyz / n - my * mz;
		c[5] = czz / n - mz * mz;
	}
}

void dp_ref_surface_ends(const dp_surface_ends_args *a)
{
	const dp_grid *g = a->surface;
	float rad2 = a->radius * a->radius, inv_s = 1.0f / a->sigma;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float px = a->px[i], py = a->py[i], pz = a->pz[i];
		float sw = 0.0f, sx = 0.0f, sy = 0.0f, sz = 0.0f;
		dp_grid_rows(g, px, py, pz, beg, end);
		for (int row = 0; row < 9; row++)
			for (uint32_t k = beg[row]; k < end[row]; k++) {
				float dx = g->x[k] - px, dy = g->y[k] - py, dz = g->z[k] - pz;
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 >= rad2)
					continue;
				if (!(a->nx[i] * a->gnx[k] + a->ny[i] * a->gny[k] + a->nz[i] * a->gnz[k] > a->side_cos))
					continue;
				float w = expf(-d2 * inv_s * inv_s);
				sw += w;
				sx += w * (a->gsx[k] - px);
				sy += w * (a->gsy[k] - py);
				sz += w * (a->gsz[k] - pz);
			}
		a->wsum[i] = sw;
		a->ox[i] = sw > 0.0f ? sx / sw : 0.0f;
		a->oy[i] = sw > 0.0f ? sy / sw : 0.0f;
		a->oz[i] = sw > 0.0f ? sz / sw : 0.0f;
	}
}

void dp_ref_surface_reattach(const dp_surface_reattach_args *a)
{
	const dp_grid *g = a->skeleton;
	float rad2 = a->radius * a->radius, inv_r2 = 1.0f / (a->r * a->r);
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float qx = a->qx[i], qy = a->qy[i], qz = a->qz[i];
		float px = a->px[i], py = a->py[i], pz = a->pz[i];
		float nx = a->nx[i], ny = a->ny[i], nz = a->nz[i];
		int32_t best = -1;
		float best_d2 = 0.0f;
		dp_grid_rows(g, qx, qy, qz, beg, end);
		for (int row = 0; row < 9; row++)
			for (uint32_t k = beg[row]; k < end[row]; k++) {
				float ex = g->x[k] - qx, ey = g->y[k] - qy, ez = g->z[k] - qz;
				if (ex * ex + ey * ey + ez * ez >= rad2)
					continue;
				float vx = px - g->x[k], vy = py - g->y[k], vz = pz - g->z[k];
				float t = vx * nx + vy * ny + vz * nz;
				if (!(t > 0.0f))
					continue;
				float wx = vx - t * nx, wy = vy - t * ny, wz = vz - t * nz;
				float line2 = wx * wx + wy * wy + wz * wz;
				if (best < 0 || line2 < best_d2) {
					best = (int32_t)k;
					best_d2 = line2;
				}
			}
		a->best[i] = best;
		a->dist2[i] = best < 0 ? 0.0f : best_d2 * inv_r2;
	}
}
