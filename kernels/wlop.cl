/* WLOP operators; the specification is host/ref/wlop_ref.c.
 *
 * The candidates of a query are taken WLOP_LANES at a time as OpenCL vectors.
 * PoCL cannot vectorise across work-items whose neighbour loops differ in
 * length, and its vectorisation of the inner loop leaves the tail of every
 * short grid row to scalar code; explicit vectors with the lanes past the
 * row's end masked off ran the attraction 2.7x faster on PoCL (AVX-512) than
 * the plain GRID_FOR loop. A GPU would rather have 1 lane per work-item. */

#define WLOP_LANES 16
#define WLOP_LANE_IDS (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)
#define WLOP_VLOAD(p, k) vload16(0, (p) + (k))
#define WLOP_SLOAD(p, k) ((p)[k])

float wlop_hsum(float16 v)
{
	float8 a = v.lo + v.hi;
	float4 b = a.lo + a.hi;
	float2 c = b.lo + b.hi;
	return c.x + c.y;
}

/* Runs BODY over every grid index whose point may lie within one cell of
 * (px, py, pz) (the 9 rows of GRID_FOR): as BODY(float16, WLOP_VLOAD, k, live,
 * _v) for blocks of WLOP_LANES indices from k, `live` masking the lanes inside
 * the row, then as BODY(float, WLOP_SLOAD, k, 1, _s) one index at a time for
 * the rest of a row when a block would read past the end of the arrays. BODY
 * accumulates into variables suffixed _v and _s. The grid's last cell is an
 * empty margin cell, so its start is the number of points. */
#define WLOP_PAIRS(px, py, pz, BODY)                                                           \
	{                                                                                      \
		uint wlop_last_ = (uint)(grid_dim.x * grid_dim.y * grid_dim.z) - 1u;           \
		uint wlop_n_ = cell_start[wlop_last_] + cell_count[wlop_last_];               \
		int wlop_cx_ = grid_coord((px), grid_origin_cell.x, grid_origin_cell.w, grid_dim.x); \
		int wlop_cy_ = grid_coord((py), grid_origin_cell.y, grid_origin_cell.w, grid_dim.y); \
		int wlop_cz_ = grid_coord((pz), grid_origin_cell.z, grid_origin_cell.w, grid_dim.z); \
		for (int wlop_dz_ = -1; wlop_dz_ <= 1; wlop_dz_++)                            \
			for (int wlop_dy_ = -1; wlop_dy_ <= 1; wlop_dy_++) {                  \
				uint wlop_row_ = ((uint)(wlop_cz_ + wlop_dz_) * (uint)grid_dim.y + \
						  (uint)(wlop_cy_ + wlop_dy_)) * (uint)grid_dim.x + \
						 (uint)wlop_cx_;                               \
				uint wlop_end_ = cell_start[wlop_row_ + 1] + cell_count[wlop_row_ + 1]; \
				uint k = cell_start[wlop_row_ - 1];                           \
				for (; k < wlop_end_ && k + WLOP_LANES <= wlop_n_; k += WLOP_LANES) { \
					int16 live = WLOP_LANE_IDS < (int16)(int)(wlop_end_ - k); \
					BODY(float16, WLOP_VLOAD, k, live, _v)                \
				}                                                             \
				for (; k < wlop_end_; k++) {                                  \
					BODY(float, WLOP_SLOAD, k, 1, _s)                      \
				}                                                             \
			}                                                                     \
	}

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
	float16 sum_v = 0.0f;
	float sum_s = 0.0f;
	WLOP_PAIRS(px, py, pz, WLOP_DENSITY_BODY)
	float sum = 1.0f + wlop_hsum(sum_v) + sum_s;
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
	float16 sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f, sw_v = 0.0f;
	float sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f, sw_s = 0.0f;
	WLOP_PAIRS(px, py, pz, WLOP_ATTRACTION_BODY)
	out_x[i] = wlop_hsum(sx_v) + sx_s;
	out_y[i] = wlop_hsum(sy_v) + sy_s;
	out_z[i] = wlop_hsum(sz_v) + sz_s;
	out_w[i] = wlop_hsum(sw_v) + sw_s;
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
	float16 sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f, sw_v = 0.0f;
	float sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f, sw_s = 0.0f;
	WLOP_PAIRS(px, py, pz, WLOP_REPULSION_BODY)
	out_x[i] = wlop_hsum(sx_v) + sx_s;
	out_y[i] = wlop_hsum(sy_v) + sy_s;
	out_z[i] = wlop_hsum(sz_v) + sz_s;
	out_w[i] = wlop_hsum(sw_v) + sw_s;
}
