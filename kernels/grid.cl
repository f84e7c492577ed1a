/* Uniform-grid helpers shared by every kernel (host side: host/grid/grid.h).
 * The neighbour set of a query is scanned as 9 rows of 3 consecutive cells:
 * cells adjacent in x are adjacent in the counting sort, so one row is one
 * contiguous index range. */

#define GRID_ARGS                                                                    \
	__global const float *gx, __global const float *gy, __global const float *gz, \
	__global const uint *cell_start, __global const uint *cell_count,            \
	const float4 grid_origin_cell, const int4 grid_dim

int grid_coord(float v, float origin, float cell, int dim)
{
	float f = (v - origin) / cell;
	if (!(f >= 1.0f))
		return 1;
	if (f >= (float)(dim - 2))
		return dim - 2;
	return (int)f;
}

/* Opens a loop over every grid index `k` whose point may lie within one cell of
 * (px, py, pz); close it with GRID_FOR_END. */
#define GRID_FOR(px, py, pz, k)                                                          \
	{                                                                                \
		int gcx_ = grid_coord((px), grid_origin_cell.x, grid_origin_cell.w, grid_dim.x); \
		int gcy_ = grid_coord((py), grid_origin_cell.y, grid_origin_cell.w, grid_dim.y); \
		int gcz_ = grid_coord((pz), grid_origin_cell.z, grid_origin_cell.w, grid_dim.z); \
		for (int gdz_ = -1; gdz_ <= 1; gdz_++)                                     \
			for (int gdy_ = -1; gdy_ <= 1; gdy_++) {                           \
				uint grow_ = ((uint)(gcz_ + gdz_) * (uint)grid_dim.y +     \
					      (uint)(gcy_ + gdy_)) * (uint)grid_dim.x +    \
					     (uint)gcx_;                                   \
				uint gbeg_ = cell_start[grow_ - 1];                        \
				uint gend_ = cell_start[grow_ + 1] + cell_count[grow_ + 1]; \
				for (uint k = gbeg_; k < gend_; k++) {

#define GRID_FOR_END }}}
