/* WLOP operators; the specification is host/ref/wlop_ref.c. Candidates are
 * taken DP_LANES at a time (GRID_PAIRS, kernels/grid.cl). */

/* θ = exp(kk d²) with kk = -theta_k/h², for pairs with min_d2 <= d² < h². */
#define WLOP_DENSITY_BODY(T, LOAD, k, live, s)                                                 \
	{                                                                                      \
		T dx = px - LOAD(gx, k), dy = py - LOAD(gy, k), dz = pz - LOAD(gz, k);        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		sum##s += select((T)0.0f, exp(kk * d2), (live) & (d2 < h2) & (d2 >= min_d2));  \
	}

__kernel void wlop_density(const uint n, __global const float *qx, __global const float *qy,
			   __global const float *qz, GRID_ARGS, const float h, const float theta_k,
			   const float min_d2, const int sqrt_density, __global float *out)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float h2 = h * h, kk = -theta_k / h2;
	LANE_T sum_v = 0.0f;
	float sum_s = 0.0f;
	GRID_PAIRS(px, py, pz, WLOP_DENSITY_BODY)
	float sum = 1.0f + LANE_SUM(sum_v) + sum_s;
	out[i] = sqrt_density ? sqrt(sum) : sum;
}

/* Weight α/v_j = θ [/d] inv_v; the whole product is masked, so the infinite
 * 1/d of a skipped pair never reaches the sums. */
#define WLOP_ATTRACTION_BODY(T, LOAD, k, live, s)                                              \
	{                                                                                      \
		T dx = LOAD(gx, k) - px, dy = LOAD(gy, k) - py, dz = LOAD(gz, k) - pz;        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T a = exp(kk * d2) * LOAD(inv_v, k);                                           \
		if (!gaussian)                                                                 \
			a *= rsqrt(d2);                                                        \
		T wt = select((T)0.0f, a, (live) & (d2 < h2) & (d2 >= min_d2));                \
		sx##s += wt * dx;                                                              \
		sy##s += wt * dy;                                                              \
		sz##s += wt * dz;                                                              \
		sw##s += wt;                                                                   \
	}

__kernel void wlop_attraction(const uint n, __global const float *qx, __global const float *qy,
			      __global const float *qz, GRID_ARGS, __global const float *inv_v, const float h,
			      const float theta_k, const float min_d2, const int gaussian,
			      __global float *out_x, __global float *out_y, __global float *out_z,
			      __global float *out_w)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float h2 = h * h, kk = -theta_k / h2;
	LANE_T sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f, sw_v = 0.0f;
	float sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f, sw_s = 0.0f;
	GRID_PAIRS(px, py, pz, WLOP_ATTRACTION_BODY)
	out_x[i] = LANE_SUM(sx_v) + sx_s;
	out_y[i] = LANE_SUM(sy_v) + sy_s;
	out_z[i] = LANE_SUM(sz_v) + sz_s;
	out_w[i] = LANE_SUM(sw_v) + sw_s;
}

/* Weight w_i' β = w θ/d, masked like the attraction's. */
#define WLOP_REPULSION_BODY(T, LOAD, k, live, s)                                               \
	{                                                                                      \
		T dx = px - LOAD(gx, k), dy = py - LOAD(gy, k), dz = pz - LOAD(gz, k);        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T b = exp(kk * d2) * rsqrt(d2) * LOAD(w, k);                                   \
		T wt = select((T)0.0f, b, (live) & (d2 < h2) & (d2 >= min_d2));                \
		sx##s += wt * dx;                                                              \
		sy##s += wt * dy;                                                              \
		sz##s += wt * dz;                                                              \
		sw##s += wt;                                                                   \
	}

__kernel void wlop_repulsion(const uint n, __global const float *qx, __global const float *qy,
			     __global const float *qz, GRID_ARGS, __global const float *w, const float h,
			     const float theta_k, const float min_d2, __global float *out_x,
			     __global float *out_y, __global float *out_z, __global float *out_w)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float h2 = h * h, kk = -theta_k / h2;
	LANE_T sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f, sw_v = 0.0f;
	float sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f, sw_s = 0.0f;
	GRID_PAIRS(px, py, pz, WLOP_REPULSION_BODY)
	out_x[i] = LANE_SUM(sx_v) + sx_s;
	out_y[i] = LANE_SUM(sy_v) + sy_s;
	out_z[i] = LANE_SUM(sz_v) + sz_s;
	out_w[i] = LANE_SUM(sw_v) + sw_s;
}
