/* Uniform-grid helpers shared by every kernel (host side: host/grid/grid.h).
 * The neighbour set of a query is scanned as 9 rows of 3 consecutive cells
 * (GRID_PAIRS), or (2 ry + 1)(2 rz + 1) rows of 2 rx + 1 cells (GRID_PAIRS_REACH):
 * cells adjacent in x are adjacent in the counting sort, so one row is one
 * contiguous index range. grid_dim.w is the grid's margin (empty cells on each
 * side). */

#define GRID_ARGS                                                                    \
	__global const float *gx, __global const float *gy, __global const float *gz, \
	__global const uint *cell_start, __global const uint *cell_count,            \
	const float4 grid_origin_cell, const int4 grid_dim

/* Cell coordinate clamped to [margin, dim-1-margin], as dp_grid_coord. */
int grid_coord_margin(float v, float origin, float cell, int dim, int margin)
{
	float f = (v - origin) / cell;
	if (!(f >= (float)margin))
		return margin;
	if (f >= (float)(dim - 1 - margin))
		return dim - 1 - margin;
	return (int)f;
}

/* Cells covering a length, clamped to [0, margin], as dp_grid_reach_cells. */
int grid_reach_cells(float len, float cell, int margin)
{
	float f = ceil(len / cell);
	if (!(f < (float)margin))
		return margin;
	return f > 0.0f ? (int)f : 0;
}

/* Candidates DP_LANES at a time (the host sets it by device type, DP_CL_LANES_*
 * in host/cl/runtime.h). PoCL cannot vectorise across work-items whose
 * neighbour loops differ in length, and its vectorisation of the inner loop
 * leaves the tail of every short grid row to scalar code; explicit vectors
 * with the lanes past the row's end masked off ran the WLOP attraction 2.7x
 * faster on PoCL (AVX-512) than a plain loop over the row. A GPU's work-items
 * are its lanes: there DP_LANES is 1 and LANE_T is float. */
#ifndef DP_LANES
#define DP_LANES 16
#endif
#if DP_LANES == 16
#define LANE_T float16
#define LANE_I int16
#define LANE_IDS (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)
#define LANE_LOAD(p, k) vload16(0, (p) + (k))
#define LANE_SUM(v) lane_sum4(lane_sum8((v).lo + (v).hi))
#define LANE_MIN(v) lane_min4(lane_min8(fmin((v).lo, (v).hi)))
#elif DP_LANES == 8
#define LANE_T float8
#define LANE_I int8
#define LANE_IDS (int8)(0, 1, 2, 3, 4, 5, 6, 7)
#define LANE_LOAD(p, k) vload8(0, (p) + (k))
#define LANE_SUM(v) lane_sum4(lane_sum8(v))
#define LANE_MIN(v) lane_min4(lane_min8(v))
#elif DP_LANES == 4
#define LANE_T float4
#define LANE_I int4
#define LANE_IDS (int4)(0, 1, 2, 3)
#define LANE_LOAD(p, k) vload4(0, (p) + (k))
#define LANE_SUM(v) lane_sum4(v)
#define LANE_MIN(v) lane_min4(v)
#elif DP_LANES == 1
#define LANE_T float
#define LANE_I int
#define LANE_IDS 0
#define LANE_LOAD(p, k) ((p)[k])
#define LANE_SUM(v) (v)
#define LANE_MIN(v) (v)
#else
#error "DP_LANES must be 1, 4, 8 or 16"
#endif
#define SCALAR_LOAD(p, k) ((p)[k])
/* The grid index of each lane of the block from k, and of a tail index. */
#define LANE_INDEX_v(k) ((LANE_I)(int)(k) + LANE_IDS)
#define LANE_INDEX_s(k) ((int)(k))
#if DP_LANES == 1
#define LANE_STORE(v, p) (*(p) = (v))
#define LANE_STORE_I(v, p) (*(p) = (v))
#else
#define LANE_STORE_F_(n) vstore##n
#define LANE_STORE_N_(n) LANE_STORE_F_(n)
#define LANE_STORE(v, p) LANE_STORE_N_(DP_LANES)((v), 0, (p))
#define LANE_STORE_I(v, p) LANE_STORE_N_(DP_LANES)((v), 0, (p))
#endif

float4 lane_sum8(float8 v) { return v.lo + v.hi; }
float lane_sum4(float4 v) { float2 a = v.lo + v.hi; return a.x + a.y; }
float4 lane_min8(float8 v) { return fmin(v.lo, v.hi); }
float lane_min4(float4 v) { float2 a = fmin(v.lo, v.hi); return fmin(a.x, a.y); }

/* Runs BODY over every grid index whose point may lie within one cell of
 * (px, py, pz) (9 rows of 3 cells): as BODY(LANE_T, LANE_LOAD, k, live, _v)
 * for blocks of DP_LANES indices from k, `live` masking the lanes inside the
 * row, then as BODY(float, SCALAR_LOAD, k, 1, _s) one index at a time for the
 * rest of a row when a block would read past the end of the arrays. BODY
 * accumulates into variables suffixed _v and _s (combine them with LANE_SUM or
 * LANE_MIN). The grid's last cell is an empty margin cell, so its start is the
 * number of points. */
#define GRID_PAIRS(px, py, pz, BODY) GRID_PAIRS_REACH(px, py, pz, 1, 1, 1, BODY)

/* GRID_PAIRS over every grid index whose point may lie within (rx, ry, rz)
 * cells of (px, py, pz), each reach in [0, margin] (grid_reach_cells gives
 * that). */
#define GRID_PAIRS_REACH(px, py, pz, rx, ry, rz, BODY)                                         \
	{                                                                                      \
		uint gp_last_ = (uint)(grid_dim.x * grid_dim.y * grid_dim.z) - 1u;             \
		uint gp_n_ = cell_start[gp_last_] + cell_count[gp_last_];                     \
		int gm_ = grid_dim.w;                                                          \
		int gp_cx_ = grid_coord_margin((px), grid_origin_cell.x, grid_origin_cell.w, grid_dim.x, gm_); \
		int gp_cy_ = grid_coord_margin((py), grid_origin_cell.y, grid_origin_cell.w, grid_dim.y, gm_); \
		int gp_cz_ = grid_coord_margin((pz), grid_origin_cell.z, grid_origin_cell.w, grid_dim.z, gm_); \
		int gp_rx_ = (rx), gp_ry_ = (ry), gp_rz_ = (rz);                              \
		for (int gp_dz_ = -gp_rz_; gp_dz_ <= gp_rz_; gp_dz_++)                        \
			for (int gp_dy_ = -gp_ry_; gp_dy_ <= gp_ry_; gp_dy_++) {              \
				uint gp_row_ = ((uint)(gp_cz_ + gp_dz_) * (uint)grid_dim.y +   \
						(uint)(gp_cy_ + gp_dy_)) * (uint)grid_dim.x +  \
					       (uint)gp_cx_;                                   \
				uint gp_end_ = cell_start[gp_row_ + (uint)gp_rx_] +            \
					       cell_count[gp_row_ + (uint)gp_rx_];             \
				uint k = cell_start[gp_row_ - (uint)gp_rx_];                   \
				for (; k < gp_end_ && k + DP_LANES <= gp_n_; k += DP_LANES) {  \
					LANE_I live = LANE_IDS < (LANE_I)(int)(gp_end_ - k);   \
					BODY(LANE_T, LANE_LOAD, k, live, _v)                   \
				}                                                              \
				for (; k < gp_end_; k++) {                                     \
					BODY(float, SCALAR_LOAD, k, 1, _s)                     \
				}                                                              \
			}                                                                      \
	}
