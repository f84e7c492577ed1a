/* Surface consolidation operators (DESIGN 4.3); the specification is
 * host/ref/surface_ref.c, the meanings are in host/backend/surface_ops.h. */

__kernel void surface_data(const uint n, __global const float *qx, __global const float *qy,
			   __global const float *qz, __global const float *qsx, __global const float *qsy,
			   __global const float *qsz, __global const float *qdepth, GRID_ARGS, const float radius,
			   const float r, const float min_d2, __global float *eta_out, __global float *sum_alpha_out,
			   __global float *ox, __global float *oy, __global float *oz)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float six = qsx[i], siy = qsy[i], siz = qsz[i], depth = qdepth[i];
	float rad2 = radius * radius, inv_r = 1.0f / r;
	float eta = 1.0f, sa = 0.0f, sx = 0.0f, sy = 0.0f, sz = 0.0f;
	GRID_FOR(px, py, pz, k)
		float dx = gx[k] - px, dy = gy[k] - py, dz = gz[k] - pz;
		float d2 = dx * dx + dy * dy + dz * dz;
		if (d2 < rad2 && dx * six + dy * siy + dz * siz + depth > 0.0f) {
			float theta = exp(-d2 * inv_r * inv_r);
			eta += theta;
			if (d2 >= min_d2) {
				float alpha = theta / (sqrt(d2) * inv_r);
				sa += alpha;
				sx += alpha * dx;
				sy += alpha * dy;
				sz += alpha * dz;
			}
		}
	GRID_FOR_END
	eta_out[i] = eta;
	sum_alpha_out[i] = sa;
	ox[i] = sa > 0.0f ? sx / sa : 0.0f;
	oy[i] = sa > 0.0f ? sy / sa : 0.0f;
	oz[i] = sa > 0.0f ? sz / sa : 0.0f;
}

__kernel void surface_neighbour(const uint n, __global const float *qx, __global const float *qy,
				__global const float *qz, __global const float *qnx, __global const float *qny,
				__global const float *qnz, __global const float *qlen, GRID_ARGS,
				__global const float *glen, __global const float *gnx, __global const float *gny,
				__global const float *gnz, const float radius, const float r, const float min_d2,
				const float tfloor, const float side_cos, __global float *L_out, __global float *var_out,
				__global float *rx, __global float *ry, __global float *rz, __global float *nn_out,
				__global float *mx, __global float *my, __global float *mz)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float nx = qnx[i], ny = qny[i], nz = qnz[i], len = qlen[i];
	float rad2 = radius * radius, inv_r = 1.0f / r;
	float count = 0.0f, sd = 0.0f, sd2 = 0.0f, st = 0.0f, stl = 0.0f;
	float sb = 0.0f, bx = 0.0f, by = 0.0f, bz = 0.0f, nn2 = rad2;
	float cx = 0.0f, cy = 0.0f, cz = 0.0f;
	GRID_FOR(px, py, pz, k)
		float dx = px - gx[k], dy = py - gy[k], dz = pz - gz[k];
		float d2 = dx * dx + dy * dy + dz * dz;
		if (d2 < rad2 && nx * gnx[k] + ny * gny[k] + nz * gnz[k] > side_cos) {
			float theta = exp(-d2 * inv_r * inv_r);
			float dl = glen[k] - len;
			cx -= theta * dx;
			cy -= theta * dy;
			cz -= theta * dz;
			count += 1.0f;
			sd += dl * inv_r;
			sd2 += (dl * inv_r) * (dl * inv_r);
			st += theta;
			stl += theta * dl;
			if (d2 >= min_d2) {
				nn2 = fmin(nn2, d2);
				float dn = dx * nx + dy * ny + dz * nz;
				float tx = dx - dn * nx, ty = dy - dn * ny, tz = dz - dn * nz;
				float t = fmax(sqrt(tx * tx + ty * ty + tz * tz) * inv_r, tfloor);
				float beta = theta / (t * t * t * t * t);
				sb += beta;
				bx += beta * tx;
				by += beta * ty;
				bz += beta * tz;
			}
		}
	GRID_FOR_END
	float mean = count > 0.0f ? sd / count : 0.0f;
	L_out[i] = st > 0.0f ? len + stl / st : len;
	var_out[i] = count > 0.0f ? fmax(sd2 / count - mean * mean, 0.0f) : 0.0f;
	rx[i] = sb > 0.0f ? bx / sb : 0.0f;
	ry[i] = sb > 0.0f ? by / sb : 0.0f;
	rz[i] = sb > 0.0f ? bz / sb : 0.0f;
	nn_out[i] = sqrt(nn2);
	mx[i] = st > 0.0f ? cx / st : 0.0f;
	my[i] = st > 0.0f ? cy / st : 0.0f;
	mz[i] = st > 0.0f ? cz / st : 0.0f;
}

__kernel void surface_covariance(const uint n, __global const float *qx, __global const float *qy,
				 __global const float *qz, __global const float *qnx, __global const float *qny,
				 __global const float *qnz, GRID_ARGS, __global const float *gnx,
				 __global const float *gny, __global const float *gnz, const float radius,
				 const float r, const float side_cos, __global float *cov)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float nx = qnx[i], ny = qny[i], nz = qnz[i];
	float rad2 = radius * radius, inv_r = 1.0f / r;
	float cnt = 0.0f, mx = 0.0f, my = 0.0f, mz = 0.0f;
	float cxx = 0.0f, cxy = 0.0f, cxz = 0.0f, cyy = 0.0f, cyz = 0.0f, czz = 0.0f;
	GRID_FOR(px, py, pz, k)
		float dx = gx[k] - px, dy = gy[k] - py, dz = gz[k] - pz;
		if (dx * dx + dy * dy + dz * dz < rad2 && nx * gnx[k] + ny * gny[k] + nz * gnz[k] > side_cos) {
			dx *= inv_r;
			dy *= inv_r;
			dz *= inv_r;
			cnt += 1.0f;
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
	GRID_FOR_END
	__global float *c = cov + 6 * (size_t)i;
	if (cnt == 0.0f) {
		for (int m = 0; m < 6; m++)
			c[m] = 0.0f;
		return;
	}
	mx /= cnt;
	my /= cnt;
	mz /= cnt;
	c[0] = cxx / cnt - mx * mx;
	c[1] = cxy / cnt - mx * my;
	c[2] = cxz / cnt - mx * mz;
	c[3] = cyy / cnt - my * my;
	c[4] = cyz / cnt - my * mz;
	c[5] = czz / cnt - mz * mz;
}

__kernel void surface_reattach(const uint n, __global const float *iqx, __global const float *iqy,
			       __global const float *iqz, __global const float *ipx, __global const float *ipy,
			       __global const float *ipz, __global const float *inx, __global const float *iny,
			       __global const float *inz, GRID_ARGS, const float radius, const float r,
			       __global int *best_out, __global float *dist2_out)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float qx = iqx[i], qy = iqy[i], qz = iqz[i];
	float px = ipx[i], py = ipy[i], pz = ipz[i];
	float nx = inx[i], ny = iny[i], nz = inz[i];
	float rad2 = radius * radius;
	int best = -1;
	float best_d2 = 0.0f;
	GRID_FOR(qx, qy, qz, k)
		float ex = gx[k] - qx, ey = gy[k] - qy, ez = gz[k] - qz;
		if (ex * ex + ey * ey + ez * ez < rad2) {
			float vx = px - gx[k], vy = py - gy[k], vz = pz - gz[k];
			float t = vx * nx + vy * ny + vz * nz;
			if (t > 0.0f) {
				float wx = vx - t * nx, wy = vy - t * ny, wz = vz - t * nz;
				float line2 = wx * wx + wy * wy + wz * wz;
				if (best < 0 || line2 < best_d2) {
					best = (int)k;
					best_d2 = line2;
				}
			}
		}
	GRID_FOR_END
	best_out[i] = best;
	dist2_out[i] = best < 0 ? 0.0f : best_d2 / (r * r);
}
