/* Meso-skeleton operators (DESIGN 4.2); the specification is
 * host/ref/skeleton_ref.c, the argument meaning host/ops/operators.h. */

/* Candidates are taken DP_LANES at a time (GRID_PAIRS, kernels/grid.cl),
 * pairs outside a sum masked by select. */
#define SKELETON_COV_BODY(T, LOAD, k, live, s)                                                 \
	{                                                                                      \
		T dx = LOAD(gx, k) - px, dy = LOAD(gy, k) - py, dz = LOAD(gz, k) - pz;        \
		T one = select((T)0.0f, (T)1.0f, (live) & (dx * dx + dy * dy + dz * dz < r2));  \
		dx *= one;                                                                     \
		dy *= one;                                                                     \
		dz *= one;                                                                     \
		c##s += one;                                                                   \
		sx##s += dx;                                                                   \
		sy##s += dy;                                                                   \
		sz##s += dz;                                                                   \
		sxx##s += dx * dx;                                                             \
		sxy##s += dx * dy;                                                             \
		sxz##s += dx * dz;                                                             \
		syy##s += dy * dy;                                                             \
		syz##s += dy * dz;                                                             \
		szz##s += dz * dz;                                                             \
	}

__kernel void skeleton_cov(const uint n, __global const float *qx, __global const float *qy,
			   __global const float *qz, GRID_ARGS, const float radius, __global float *count,
			   __global float *cov)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float r2 = radius * radius;
	LANE_T c_v = 0.0f, sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f;
	LANE_T sxx_v = 0.0f, sxy_v = 0.0f, sxz_v = 0.0f, syy_v = 0.0f, syz_v = 0.0f, szz_v = 0.0f;
	float c_s = 0.0f, sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f;
	float sxx_s = 0.0f, sxy_s = 0.0f, sxz_s = 0.0f, syy_s = 0.0f, syz_s = 0.0f, szz_s = 0.0f;
	GRID_PAIRS(px, py, pz, SKELETON_COV_BODY)
	float c = LANE_SUM(c_v) + c_s;
	float sx = LANE_SUM(sx_v) + sx_s, sy = LANE_SUM(sy_v) + sy_s, sz = LANE_SUM(sz_v) + sz_s;
	float sxx = LANE_SUM(sxx_v) + sxx_s, sxy = LANE_SUM(sxy_v) + sxy_s, sxz = LANE_SUM(sxz_v) + sxz_s;
	float syy = LANE_SUM(syy_v) + syy_s, syz = LANE_SUM(syz_v) + syz_s, szz = LANE_SUM(szz_v) + szz_s;
	count[i] = c;
	float inv = c > 0.0f ? 1.0f / c : 0.0f;
	float mx = sx * inv, my = sy * inv, mz = sz * inv;
	cov[6 * i + 0] = sxx * inv - mx * mx;
	cov[6 * i + 1] = sxy * inv - mx * my;
	cov[6 * i + 2] = sxz * inv - mx * mz;
	cov[6 * i + 3] = syy * inv - my * my;
	cov[6 * i + 4] = syz * inv - my * mz;
	cov[6 * i + 5] = szz * inv - mz * mz;
}

#define SKELETON_SEMIAXES_BODY(T, LOAD, k, live, s)                                            \
	{                                                                                      \
		T dx = LOAD(gx, k) - px, dy = LOAD(gy, k) - py, dz = LOAD(gz, k) - pz;        \
		T one = select((T)0.0f, (T)1.0f, (live) & (dx * dx + dy * dy + dz * dz < r2));  \
		T nx = LOAD(gnx, k), ny = LOAD(gny, k), nz = LOAD(gnz, k);                     \
		c##s += one;                                                                   \
		s0##s += one * fabs(nx * v0x + ny * v0y + nz * v0z);                           \
		s1##s += one * fabs(nx * v1x + ny * v1y + nz * v1z);                           \
		s2##s += one * fabs(nx * v2x + ny * v2y + nz * v2z);                           \
	}

__kernel void skeleton_semiaxes(const uint n, __global const float *qx, __global const float *qy,
				__global const float *qz, GRID_ARGS, __global const float *gnx,
				__global const float *gny, __global const float *gnz,
				__global const float *frames, const float radius, const float eps,
				__global float *semi)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	__global const float *v = frames + 9 * i;
	float v0x = v[0], v0y = v[1], v0z = v[2], v1x = v[3], v1y = v[4], v1z = v[5];
	float v2x = v[6], v2y = v[7], v2z = v[8];
	float r2 = radius * radius;
	LANE_T c_v = 0.0f, s0_v = 0.0f, s1_v = 0.0f, s2_v = 0.0f;
	float c_s = 0.0f, s0_s = 0.0f, s1_s = 0.0f, s2_s = 0.0f;
	GRID_PAIRS(px, py, pz, SKELETON_SEMIAXES_BODY)
	float c = LANE_SUM(c_v) + c_s;
	float s0 = LANE_SUM(s0_v) + s0_s, s1 = LANE_SUM(s1_v) + s1_s, s2 = LANE_SUM(s2_v) + s2_s;
	float inv = c > 0.0f ? 1.0f / c : 0.0f;
	semi[3 * i + 0] = 1.0f / (s0 * inv + eps);
	semi[3 * i + 1] = 1.0f / (s1 * inv + eps);
	semi[3 * i + 2] = 1.0f / (s2 * inv + eps);
}

/* Both sums below weigh a neighbour by ϑ = exp(-u²), u the ellipsoid distance
 * in units of r under the query's metric rows m0, m1, m2. */
#define SKELETON_METRIC_LOAD(metric, i)                                                   \
	__global const float *m_ = (metric) + 9 * (i);                                    \
	float m0x = m_[0], m0y = m_[1], m0z = m_[2], m1x = m_[3], m1y = m_[4], m1z = m_[5]; \
	float m2x = m_[6], m2y = m_[7], m2z = m_[8];

/* The query's scan reach in cells along x, y, z (host/ops/operators.h). */
#define SKELETON_REACH_LOAD(reach, i)                                              \
	int rx = grid_reach_cells((reach)[3 * (i)], grid_origin_cell.w, grid_dim.w);     \
	int ry = grid_reach_cells((reach)[3 * (i) + 1], grid_origin_cell.w, grid_dim.w); \
	int rz = grid_reach_cells((reach)[3 * (i) + 2], grid_origin_cell.w, grid_dim.w);

/* u² of an offset (dx, dy, dz) of type T under the metric rows. */
#define SKELETON_U2(T, dx, dy, dz)                                                              \
	(skeleton_sq((T)(m0x * (dx) + m0y * (dy) + m0z * (dz))) +                               \
	 skeleton_sq((T)(m1x * (dx) + m1y * (dy) + m1z * (dz))) +                               \
	 skeleton_sq((T)(m2x * (dx) + m2y * (dy) + m2z * (dz))))
#define skeleton_sq(a) ((a) * (a))

/* The two sums take candidates DP_LANES at a time (GRID_PAIRS_REACH,
 * kernels/grid.cl), pairs outside them masked by select. Every lane computes
 * the weight, so u² is clamped to the cut-off first: exp of the far lanes'
 * large u² gives denormals, which made the unclamped repulsion 3x slower. */
#define SKELETON_MEDIAN_BODY(T, LOAD, k, live, s)                                              \
	{                                                                                      \
		T hx = LOAD(gx, k), hy = LOAD(gy, k), hz = LOAD(gz, k);                        \
		T dx = px - hx, dy = py - hy, dz = pz - hz;                                    \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T u2 = SKELETON_U2(T, dx, dy, dz);                                             \
		T alpha = select((T)0.0f, exp(-fmin(u2, cut2)) / sqrt(d2),                     \
				 (live) & (u2 <= cut2) & (d2 >= min_d2));                       \
		w##s += alpha;                                                                 \
		sx##s += alpha * hx;                                                           \
		sy##s += alpha * hy;                                                           \
		sz##s += alpha * hz;                                                           \
	}

__kernel void skeleton_median(const uint n, __global const float *qx, __global const float *qy,
			      __global const float *qz, __global const float *metric, __global const float *reach,
			      GRID_ARGS, const float cutoff, const float min_d2, __global float *median)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	SKELETON_METRIC_LOAD(metric, i)
	SKELETON_REACH_LOAD(reach, i)
	float cut2 = cutoff * cutoff;
	LANE_T w_v = 0.0f, sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f;
	float w_s = 0.0f, sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f;
	GRID_PAIRS_REACH(px, py, pz, rx, ry, rz, SKELETON_MEDIAN_BODY)
	float w = LANE_SUM(w_v) + w_s;
	float sx = LANE_SUM(sx_v) + sx_s, sy = LANE_SUM(sy_v) + sy_s, sz = LANE_SUM(sz_v) + sz_s;
	int found = w > 0.0f;
	float inv = found ? 1.0f / w : 0.0f;
	median[3 * i + 0] = found ? sx * inv : px;
	median[3 * i + 1] = found ? sy * inv : py;
	median[3 * i + 2] = found ? sz * inv : pz;
}

#define SKELETON_REPULSE_BODY(T, LOAD, k, live, s)                                             \
	{                                                                                      \
		T dx = px - LOAD(gx, k), dy = py - LOAD(gy, k), dz = pz - LOAD(gz, k);        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T u2 = SKELETON_U2(T, dx, dy, dz);                                             \
		T uc = fmin(u2, cut2);                                                         \
		T beta = select((T)0.0f, exp(-uc) / (uc * uc * sqrt(uc)),                      \
				(live) & (u2 <= cut2) & (d2 >= min_d2));                        \
		w##s += beta;                                                                  \
		sx##s += beta * dx;                                                            \
		sy##s += beta * dy;                                                            \
		sz##s += beta * dz;                                                            \
	}

__kernel void skeleton_repulse(const uint n, __global const float *qx, __global const float *qy,
			       __global const float *qz, __global const float *metric, __global const float *reach,
			       GRID_ARGS, const float cutoff, const float min_d2, __global float *repulse)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	SKELETON_METRIC_LOAD(metric, i)
	SKELETON_REACH_LOAD(reach, i)
	float cut2 = cutoff * cutoff;
	LANE_T w_v = 0.0f, sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f;
	float w_s = 0.0f, sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f;
	GRID_PAIRS_REACH(px, py, pz, rx, ry, rz, SKELETON_REPULSE_BODY)
	float w = LANE_SUM(w_v) + w_s;
	float sx = LANE_SUM(sx_v) + sx_s, sy = LANE_SUM(sy_v) + sy_s, sz = LANE_SUM(sz_v) + sz_s;
	float inv = w > 0.0f ? 1.0f / w : 0.0f;
	repulse[3 * i + 0] = sx * inv;
	repulse[3 * i + 1] = sy * inv;
	repulse[3 * i + 2] = sz * inv;
}
