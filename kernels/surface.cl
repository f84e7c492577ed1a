/* Surface consolidation operators (DESIGN 4.3); the specification is
 * host/ref/surface_ref.c, the meanings are in host/ops/operators.h. */

/* Candidates are taken DP_LANES at a time (GRID_PAIRS, kernels/grid.cl); a
 * pair outside the sums is masked by select, never by a branch, so the lanes
 * stay in step and the 1/d of a skipped pair never reaches a sum. d² enters
 * exp clamped to the radius: the far lanes' exp would give denormals, which
 * are slow (kernels/skeleton.cl). */

#define SURFACE_DATA_IN(live) ((live) & (d2 < rad2) & (dx * six + dy * siy + dz * siz + qdepth > 0.0f))
#define SURFACE_DATA_BODY(T, LOAD, k, live, s)                                                 \
	{                                                                                      \
		T dx = LOAD(gx, k) - ax, dy = LOAD(gy, k) - ay, dz = LOAD(gz, k) - az;        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T theta = select((T)0.0f, exp(-fmin(d2, rad2) * inv_r * inv_r), SURFACE_DATA_IN(live));    \
		eta##s += theta;                                                               \
		T alpha = select((T)0.0f, theta / (sqrt(d2) * inv_r),                          \
				 SURFACE_DATA_IN(live) & (d2 >= min_d2));                       \
		sa##s += alpha;                                                                \
		sx##s += alpha * dx;                                                           \
		sy##s += alpha * dy;                                                           \
		sz##s += alpha * dz;                                                           \
	}

__kernel void surface_data(const uint n, __global const float *px, __global const float *py,
			   __global const float *pz, __global const float *sx, __global const float *sy,
			   __global const float *sz, __global const float *depth, GRID_ARGS, const float radius,
			   const float r, const float min_d2, __global float *eta, __global float *sum_alpha,
			   __global float *ox, __global float *oy, __global float *oz)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i];
	float six = sx[i], siy = sy[i], siz = sz[i], qdepth = depth[i];
	float rad2 = radius * radius, inv_r = 1.0f / r;
	LANE_T eta_v = 0.0f, sa_v = 0.0f, sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f;
	float eta_s = 0.0f, sa_s = 0.0f, sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f;
	GRID_PAIRS(ax, ay, az, SURFACE_DATA_BODY)
	float sa = LANE_SUM(sa_v) + sa_s;
	float tx = LANE_SUM(sx_v) + sx_s, ty = LANE_SUM(sy_v) + sy_s, tz = LANE_SUM(sz_v) + sz_s;
	eta[i] = 1.0f + LANE_SUM(eta_v) + eta_s;
	sum_alpha[i] = sa;
	ox[i] = sa > 0.0f ? tx / sa : 0.0f;
	oy[i] = sa > 0.0f ? ty / sa : 0.0f;
	oz[i] = sa > 0.0f ? tz / sa : 0.0f;
}

#define SURFACE_NB_IN(live, LOAD)                                                                    \
	((live) & (d2 < rad2) & (qnx * LOAD(gnx, k) + qny * LOAD(gny, k) + qnz * LOAD(gnz, k) > side_cos))
#define SURFACE_NB_BODY(T, LOAD, k, live, s)                                                   \
	{                                                                                      \
		T dx = ax - LOAD(gx, k), dy = ay - LOAD(gy, k), dz = az - LOAD(gz, k);        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T one = select((T)0.0f, (T)1.0f, SURFACE_NB_IN(live, LOAD));                         \
		T theta = one * exp(-fmin(d2, rad2) * inv_r * inv_r);                                      \
		T dl = LOAD(glen, k) - qlen;                                                   \
		T dlr = one * (dl * inv_r);                                                    \
		cx##s -= theta * dx;                                                           \
		cy##s -= theta * dy;                                                           \
		cz##s -= theta * dz;                                                           \
		count##s += one;                                                               \
		sd##s += dlr;                                                                  \
		sd2##s += dlr * dlr;                                                           \
		st##s += theta;                                                                \
		stl##s += theta * dl;                                                          \
		nn2##s = select(nn2##s, fmin(nn2##s, d2), SURFACE_NB_IN(live, LOAD) & (d2 >= min_d2)); \
		T dn = dx * qnx + dy * qny + dz * qnz;                                         \
		T tx = dx - dn * qnx, ty = dy - dn * qny, tz = dz - dn * qnz;                  \
		T t = fmax(sqrt(tx * tx + ty * ty + tz * tz) * inv_r, tfloor);                 \
		T beta = select((T)0.0f, theta / (t * t * t * t * t),                          \
				SURFACE_NB_IN(live, LOAD) & (d2 >= min_d2));                          \
		sb##s += beta;                                                                 \
		bx##s += beta * tx;                                                            \
		by##s += beta * ty;                                                            \
		bz##s += beta * tz;                                                            \
	}

__kernel void surface_neighbour(const uint n, __global const float *px, __global const float *py,
				__global const float *pz, __global const float *nx, __global const float *ny,
				__global const float *nz, __global const float *len, GRID_ARGS,
				__global const float *glen, __global const float *gnx, __global const float *gny,
				__global const float *gnz, const float radius, const float r, const float min_d2,
				const float tfloor, const float side_cos, __global float *L, __global float *var,
				__global float *rx, __global float *ry, __global float *rz, __global float *nn,
				__global float *mx, __global float *my, __global float *mz)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i];
	float qnx = nx[i], qny = ny[i], qnz = nz[i], qlen = len[i];
	float rad2 = radius * radius, inv_r = 1.0f / r;
	LANE_T count_v = 0.0f, sd_v = 0.0f, sd2_v = 0.0f, st_v = 0.0f, stl_v = 0.0f;
	LANE_T sb_v = 0.0f, bx_v = 0.0f, by_v = 0.0f, bz_v = 0.0f, nn2_v = rad2;
	LANE_T cx_v = 0.0f, cy_v = 0.0f, cz_v = 0.0f;
	float count_s = 0.0f, sd_s = 0.0f, sd2_s = 0.0f, st_s = 0.0f, stl_s = 0.0f;
	float sb_s = 0.0f, bx_s = 0.0f, by_s = 0.0f, bz_s = 0.0f, nn2_s = rad2;
	float cx_s = 0.0f, cy_s = 0.0f, cz_s = 0.0f;
	GRID_PAIRS(ax, ay, az, SURFACE_NB_BODY)
	float count = LANE_SUM(count_v) + count_s, sd = LANE_SUM(sd_v) + sd_s, sd2 = LANE_SUM(sd2_v) + sd2_s;
	float st = LANE_SUM(st_v) + st_s, stl = LANE_SUM(stl_v) + stl_s, sb = LANE_SUM(sb_v) + sb_s;
	float bx = LANE_SUM(bx_v) + bx_s, by = LANE_SUM(by_v) + by_s, bz = LANE_SUM(bz_v) + bz_s;
	float cx = LANE_SUM(cx_v) + cx_s, cy = LANE_SUM(cy_v) + cy_s, cz = LANE_SUM(cz_v) + cz_s;
	float nn2 = fmin(LANE_MIN(nn2_v), nn2_s);
	float mean = count > 0.0f ? sd / count : 0.0f;
	L[i] = st > 0.0f ? qlen + stl / st : qlen;
	var[i] = count > 0.0f ? fmax(sd2 / count - mean * mean, 0.0f) : 0.0f;
	rx[i] = sb > 0.0f ? bx / sb : 0.0f;
	ry[i] = sb > 0.0f ? by / sb : 0.0f;
	rz[i] = sb > 0.0f ? bz / sb : 0.0f;
	nn[i] = sqrt(nn2);
	mx[i] = st > 0.0f ? cx / st : 0.0f;
	my[i] = st > 0.0f ? cy / st : 0.0f;
	mz[i] = st > 0.0f ? cz / st : 0.0f;
}

#define SURFACE_COV_BODY(T, LOAD, k, live, s)                                                  \
	{                                                                                      \
		T dx = LOAD(gx, k) - ax, dy = LOAD(gy, k) - ay, dz = LOAD(gz, k) - az;        \
		T one = select((T)0.0f, (T)1.0f,                                               \
			       (live) & (dx * dx + dy * dy + dz * dz < rad2) &                 \
				       (qnx * LOAD(gnx, k) + qny * LOAD(gny, k) + qnz * LOAD(gnz, k) > side_cos)); \
		dx *= one * inv_r;                                                             \
		dy *= one * inv_r;                                                             \
		dz *= one * inv_r;                                                             \
		cnt##s += one;                                                                 \
		mx##s += dx;                                                                   \
		my##s += dy;                                                                   \
		mz##s += dz;                                                                   \
		cxx##s += dx * dx;                                                             \
		cxy##s += dx * dy;                                                             \
		cxz##s += dx * dz;                                                             \
		cyy##s += dy * dy;                                                             \
		cyz##s += dy * dz;                                                             \
		czz##s += dz * dz;                                                             \
	}

__kernel void surface_covariance(const uint n, __global const float *px, __global const float *py,
				 __global const float *pz, __global const float *nx, __global const float *ny,
				 __global const float *nz, GRID_ARGS, __global const float *gnx,
				 __global const float *gny, __global const float *gnz, const float radius,
				 const float r, const float side_cos, __global float *cov)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i];
	float qnx = nx[i], qny = ny[i], qnz = nz[i];
	float rad2 = radius * radius, inv_r = 1.0f / r;
	LANE_T cnt_v = 0.0f, mx_v = 0.0f, my_v = 0.0f, mz_v = 0.0f;
	LANE_T cxx_v = 0.0f, cxy_v = 0.0f, cxz_v = 0.0f, cyy_v = 0.0f, cyz_v = 0.0f, czz_v = 0.0f;
	float cnt_s = 0.0f, mx_s = 0.0f, my_s = 0.0f, mz_s = 0.0f;
	float cxx_s = 0.0f, cxy_s = 0.0f, cxz_s = 0.0f, cyy_s = 0.0f, cyz_s = 0.0f, czz_s = 0.0f;
	GRID_PAIRS(ax, ay, az, SURFACE_COV_BODY)
	float cnt = LANE_SUM(cnt_v) + cnt_s;
	float mx = LANE_SUM(mx_v) + mx_s, my = LANE_SUM(my_v) + my_s, mz = LANE_SUM(mz_v) + mz_s;
	float cxx = LANE_SUM(cxx_v) + cxx_s, cxy = LANE_SUM(cxy_v) + cxy_s, cxz = LANE_SUM(cxz_v) + cxz_s;
	float cyy = LANE_SUM(cyy_v) + cyy_s, cyz = LANE_SUM(cyz_v) + cyz_s, czz = LANE_SUM(czz_v) + czz_s;
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

#define SURFACE_ENDS_BODY(T, LOAD, k, live, s)                                                 \
	{                                                                                      \
		T dx = LOAD(gx, k) - ax, dy = LOAD(gy, k) - ay, dz = LOAD(gz, k) - az;        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T w = select((T)0.0f, exp(-fmin(d2, rad2) * inv_s * inv_s),                    \
			     (live) & (d2 < rad2) &                                            \
				     (qnx * LOAD(gnx, k) + qny * LOAD(gny, k) + qnz * LOAD(gnz, k) > side_cos)); \
		sw##s += w;                                                                    \
		sx##s += w * (LOAD(gsx, k) - ax);                                              \
		sy##s += w * (LOAD(gsy, k) - ay);                                              \
		sz##s += w * (LOAD(gsz, k) - az);                                              \
	}

__kernel void surface_ends(const uint n, __global const float *px, __global const float *py,
			   __global const float *pz, __global const float *nx, __global const float *ny,
			   __global const float *nz, GRID_ARGS, __global const float *gnx, __global const float *gny,
			   __global const float *gnz, __global const float *gsx, __global const float *gsy,
			   __global const float *gsz, const float radius, const float sigma, const float side_cos,
			   __global float *wsum, __global float *ox, __global float *oy, __global float *oz)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float ax = px[i], ay = py[i], az = pz[i];
	float qnx = nx[i], qny = ny[i], qnz = nz[i];
	float rad2 = radius * radius, inv_s = 1.0f / sigma;
	LANE_T sw_v = 0.0f, sx_v = 0.0f, sy_v = 0.0f, sz_v = 0.0f;
	float sw_s = 0.0f, sx_s = 0.0f, sy_s = 0.0f, sz_s = 0.0f;
	GRID_PAIRS(ax, ay, az, SURFACE_ENDS_BODY)
	float sw = LANE_SUM(sw_v) + sw_s;
	float sx = LANE_SUM(sx_v) + sx_s, sy = LANE_SUM(sy_v) + sy_s, sz = LANE_SUM(sz_v) + sz_s;
	wsum[i] = sw;
	ox[i] = sw > 0.0f ? sx / sw : 0.0f;
	oy[i] = sw > 0.0f ? sy / sw : 0.0f;
	oz[i] = sw > 0.0f ? sz / sw : 0.0f;
}

/* Each lane keeps its first smallest line distance (strictly smaller
 * replaces), so the smallest (distance, index) over the lanes and the tail is
 * the first in grid order on ties, as the sequential scan. */
#define SURFACE_REATTACH_BODY(T, LOAD, k, live, s)                                             \
	{                                                                                      \
		T hx = LOAD(gx, k), hy = LOAD(gy, k), hz = LOAD(gz, k);                        \
		T ex = hx - iqx, ey = hy - iqy, ez = hz - iqz;                                 \
		T vx = ipx - hx, vy = ipy - hy, vz = ipz - hz;                                 \
		T t = vx * inx + vy * iny + vz * inz;                                          \
		T wx = vx - t * inx, wy = vy - t * iny, wz = vz - t * inz;                     \
		T line2 = wx * wx + wy * wy + wz * wz;                                         \
		bool_##s better = (live) & (ex * ex + ey * ey + ez * ez < rad2) & (t > 0.0f) & \
				  (line2 < bd##s);                                              \
		bd##s = select(bd##s, line2, better);                                          \
		bk##s = select(bk##s, LANE_INDEX##s(k), better);                               \
	}
#define bool__v LANE_I
#define bool__s int

__kernel void surface_reattach(const uint n, __global const float *qx, __global const float *qy,
			       __global const float *qz, __global const float *px, __global const float *py,
			       __global const float *pz, __global const float *nx, __global const float *ny,
			       __global const float *nz, GRID_ARGS, const float radius, const float r,
			       __global int *best, __global float *dist2)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float iqx = qx[i], iqy = qy[i], iqz = qz[i];
	float ipx = px[i], ipy = py[i], ipz = pz[i];
	float inx = nx[i], iny = ny[i], inz = nz[i];
	float rad2 = radius * radius;
	LANE_T bd_v = INFINITY;
	LANE_I bk_v = -1;
	float bd_s = INFINITY;
	int bk_s = -1;
	GRID_PAIRS(iqx, iqy, iqz, SURFACE_REATTACH_BODY)
	float bd[DP_LANES];
	int bk[DP_LANES];
	LANE_STORE(bd_v, bd);
	LANE_STORE_I(bk_v, bk);
	int bi = bk_s;
	float best_d2 = bd_s;
	for (int l = 0; l < DP_LANES; l++)
		if (bk[l] >= 0 && (bi < 0 || bd[l] < best_d2 || (bd[l] == best_d2 && bk[l] < bi))) {
			bi = bk[l];
			best_d2 = bd[l];
		}
	best[i] = bi;
	dist2[i] = bi < 0 ? 0.0f : best_d2 / (r * r);
}
