/* The bare pair loop, the ceiling every operator is measured against
 * (bench/bench_peak.c, bench_stages): the grid scan of GRID_PAIRS_REACH with
 * the cheapest sum that still needs every distance, a count of the candidates
 * within the radius and Σ exp(-d²/radius²) over them. The specification is
 * host/ref/peak_ref.c. */
#define PEAK_BODY(T, LOAD, k, live, s)                                                         \
	{                                                                                      \
		T dx = px - LOAD(gx, k), dy = py - LOAD(gy, k), dz = pz - LOAD(gz, k);        \
		T d2 = dx * dx + dy * dy + dz * dz;                                            \
		T hit = select((T)0.0f, (T)1.0f, (live) & (d2 < r2));                          \
		count##s += hit;                                                               \
		sum##s += hit * exp(kk * d2);                                                  \
	}

/* reach: cells scanned on each side (the grid's cell is radius / reach or
 * more, its margin at least reach). Counts are summed in float: exact below
 * 2^24 neighbours of one query. */
__kernel void peak_pairs(const uint n, __global const float *qx, __global const float *qy,
			 __global const float *qz, GRID_ARGS, const float radius, const int reach,
			 __global float *count, __global float *sum)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float r2 = radius * radius, kk = -1.0f / r2;
	LANE_T count_v = 0.0f, sum_v = 0.0f;
	float count_s = 0.0f, sum_s = 0.0f;
	GRID_PAIRS_REACH(px, py, pz, reach, reach, reach, PEAK_BODY)
	count[i] = LANE_SUM(count_v) + count_s;
	sum[i] = LANE_SUM(sum_v) + sum_s;
}
