/* Sinking operators (DESIGN 4.1); the specification is host/ref/sink_ref.c. */

/* Same values as DP_SINK_NO_FRONT and DP_SINK_OPPOSITE_COS (host/ops/operators.h). */
#define SINK_NO_FRONT 2.0f
#define SINK_OPPOSITE_COS -0.70710678f

/* Candidates are taken DP_LANES at a time (GRID_PAIRS, kernels/grid.cl),
 * pairs outside a sum masked by select. */
#define SINK_FRONT_BODY(T, LOAD, k, live, s)                                                   \
	{                                                                                      \
		T dx = ax - LOAD(gx, k), dy = ay - LOAD(gy, k), dz = az - LOAD(gz, k);        \
		T ex = bx - LOAD(sx, k), ey = by - LOAD(sy, k), ez = bz - LOAD(sz, k);        \
		T dot = mx * LOAD(nx, k) + my * LOAD(ny, k) + mz * LOAD(nz, k);               \
		T behind = -(LOAD(nx, k) * ex + LOAD(ny, k) * ey + LOAD(nz, k) * ez);         \
		best##s = select(best##s, fmin(best##s, dot),                                  \
				 (live) & (dx * dx + dy * dy + dz * dz < r2) &                  \
					 ((ex * ex + ey * ey + ez * ez > far_d2) |              \
					  (((T)wall_min > (T)0.0f) & (dot < (T)SINK_OPPOSITE_COS) &  \
					   (behind > (T)wall_min))));                             \
	}

__kernel void sink_front(const uint n, __global const float *qx, __global const float *qy,
			 __global const float *qz, __global const float *px, __global const float *py,
			 __global const float *pz, __global const float *qnx, __global const float *qny,
			 __global const float *qnz, GRID_ARGS, __global const float *sx, __global const float *sy,
			 __global const float *sz, __global const float *nx, __global const float *ny,
			 __global const float *nz, const float radius, const float far_d2, const float wall_min,
			 __global float *min_dot)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = qx[i], ay = qy[i], az = qz[i];
	float bx = px[i], by = py[i], bz = pz[i];
	float mx = qnx[i], my = qny[i], mz = qnz[i];
	float r2 = radius * radius;
	LANE_T best_v = SINK_NO_FRONT;
	float best_s = SINK_NO_FRONT;
	GRID_PAIRS(ax, ay, az, SINK_FRONT_BODY)
	min_dot[i] = fmin(LANE_MIN(best_v), best_s);
}

#define SINK_STEP_BODY(T, LOAD, k, live, s)                                                    \
	{                                                                                      \
		T dx = ax - LOAD(gx, k), dy = ay - LOAD(gy, k), dz = az - LOAD(gz, k);        \
		T one = select((T)0.0f, (T)1.0f,                                               \
			       (live) & (dx * dx + dy * dy + dz * dz < r2) & (LOAD(stop, k) >= low)); \
		sum##s += one * LOAD(move, k);                                                 \
		count##s += one;                                                               \
	}

__kernel void sink_step(const uint n, __global const float *px, __global const float *py,
			__global const float *pz, __global const float *depth, GRID_ARGS,
			__global const float *move, __global const float *stop, const float radius,
			const float margin, __global float *mean)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i], low = depth[i] - margin;
	float r2 = radius * radius;
	LANE_T sum_v = 0.0f, count_v = 0.0f;
	float sum_s = 0.0f, count_s = 0.0f;
	GRID_PAIRS(ax, ay, az, SINK_STEP_BODY)
	float sum = LANE_SUM(sum_v) + sum_s, count = LANE_SUM(count_v) + count_s;
	mean[i] = count > 0.0f ? sum / count : 0.0f;
}

/* d² enters exp clamped to the radius: the far lanes' exp would give
 * denormals, which are slow. */
#define SINK_SMOOTH_BODY(T, LOAD, k, live, s)                                                  \
	{                                                                                      \
		T dx = ax - LOAD(gx, k), dy = ay - LOAD(gy, k), dz = az - LOAD(gz, k);        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T u = (1.0f - (mx * LOAD(nx, k) + my * LOAD(ny, k) + mz * LOAD(nz, k))) * phi_scale; \
		T w = select((T)0.0f, exp(-fmin(d2, r2) * inv_r2 - u * u), (live) & (d2 < r2)); \
		sx##s += w * (LOAD(ix, k) - cx);                                               \
		sy##s += w * (LOAD(iy, k) - cy);                                               \
		sz##s += w * (LOAD(iz, k) - cz);                                               \
		sw##s += w;                                                                    \
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
	float r2 = radius * radius;
	LANE_T sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f, sw_v = 0.0f;
	float sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f, sw_s = 0.0f;
	GRID_PAIRS(ax, ay, az, SINK_SMOOTH_BODY)
	out_x[i] = LANE_SUM(sx_v) + sx_s;
	out_y[i] = LANE_SUM(sy_v) + sy_s;
	out_z[i] = LANE_SUM(sz_v) + sz_s;
	out_w[i] = LANE_SUM(sw_v) + sw_s;
}
