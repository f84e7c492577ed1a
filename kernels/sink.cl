/* Sinking operators (DESIGN 4.1); the specification is host/ref/sink_ref.c. */

/* Same value as DP_SINK_NO_FRONT (host/backend/sink_ops.h). */
#define SINK_NO_FRONT 2.0f

__kernel void sink_front(const uint n, __global const float *qx, __global const float *qy,
			 __global const float *qz, __global const float *px, __global const float *py,
			 __global const float *pz, __global const float *qnx, __global const float *qny,
			 __global const float *qnz, GRID_ARGS, __global const float *sx, __global const float *sy,
			 __global const float *sz, __global const float *nx, __global const float *ny,
			 __global const float *nz, const float radius, const float far_d2,
			 __global float *min_dot)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = qx[i], ay = qy[i], az = qz[i];
	float bx = px[i], by = py[i], bz = pz[i];
	float mx = qnx[i], my = qny[i], mz = qnz[i];
	float r2 = radius * radius, best = SINK_NO_FRONT;
	GRID_FOR(ax, ay, az, k)
		float dx = ax - gx[k], dy = ay - gy[k], dz = az - gz[k];
		if (dx * dx + dy * dy + dz * dz < r2) {
			float ex = bx - sx[k], ey = by - sy[k], ez = bz - sz[k];
			if (ex * ex + ey * ey + ez * ez > far_d2)
				best = fmin(best, mx * nx[k] + my * ny[k] + mz * nz[k]);
		}
	GRID_FOR_END
	min_dot[i] = best;
}

__kernel void sink_step(const uint n, __global const float *px, __global const float *py,
			__global const float *pz, GRID_ARGS, __global const float *move, const float radius,
			__global float *mean)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i];
	float r2 = radius * radius, sum = 0.0f, count = 0.0f;
	GRID_FOR(ax, ay, az, k)
		float dx = ax - gx[k], dy = ay - gy[k], dz = az - gz[k];
		if (dx * dx + dy * dy + dz * dz < r2) {
			sum += move[k];
			count += 1.0f;
		}
	GRID_FOR_END
	mean[i] = count > 0.0f ? sum / count : 0.0f;
}

__kernel void sink_smooth(const uint n, __global const float *px, __global const float *py,
			  __global const float *pz, __global const float *qnx, __global const float *qny,
			  __global const float *qnz, __global const float *qx, __global const float *qy,
			  __global const float *qz, GRID_ARGS, __global const float *nx, __global const float *ny,
			  __global const float *nz, __global const float *ix, __global const float *iy,
			  __global const float *iz, const float radius, const float inv_r2, const float phi_scale,
			  __global float *out_x, __global float *out_y, __global float *out_z, __global float *out_w)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i];
	float mx = qnx[i], my = qny[i], mz = qnz[i];
	float cx = qx[i], cy = qy[i], cz = qz[i];
	float r2 = radius * radius, sx = 0.0f, sy = 0.0f, sz = 0.0f, sw = 0.0f;
	GRID_FOR(ax, ay, az, k)
		float dx = ax - gx[k], dy = ay - gy[k], dz = az - gz[k];
		float d2 = dx * dx + dy * dy + dz * dz;
		if (d2 < r2) {
			float u = (1.0f - (mx * nx[k] + my * ny[k] + mz * nz[k])) * phi_scale;
			float w = exp(-d2 * inv_r2 - u * u);
			sx += w * (ix[k] - cx);
			sy += w * (iy[k] - cy);
			sz += w * (iz[k] - cz);
			sw += w;
		}
	GRID_FOR_END
	out_x[i] = sx;
	out_y[i] = sy;
	out_z[i] = sz;
	out_w[i] = sw;
}
