/* Uniform-grid helpers shared by every kernel (host side: host/grid/grid.h).
 * The neighbour set of a query is scanned as 9 rows of 3 consecutive cells
 * (GRID_FOR), or (2 ry + 1)(2 rz + 1) rows of 2 rx + 1 cells (GRID_FOR_REACH):
 * cells adjacent in x are adjacent in the counting sort, so one row is one
 * contiguous index range. grid_dim.w is the grid's margin (empty cells on each
 * side). */

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

/* Opens a loop over every grid index `k` whose point may lie within (rx, ry,
 * rz) cells of (px, py, pz) along x, y, z; each reach is in [0, margin]
 * (grid_reach_cells gives that). Close it with GRID_FOR_END. */
#define GRID_FOR_REACH(px, py, pz, rx, ry, rz, k)                                                   \
	{                                                                                           \
		int gm_ = grid_dim.w;                                                               \
		int gcx_ = grid_coord_margin((px), grid_origin_cell.x, grid_origin_cell.w, grid_dim.x, gm_); \
		int gcy_ = grid_coord_margin((py), grid_origin_cell.y, grid_origin_cell.w, grid_dim.y, gm_); \
		int gcz_ = grid_coord_margin((pz), grid_origin_cell.z, grid_origin_cell.w, grid_dim.z, gm_); \
		int grx_ = (rx), gry_ = (ry), grz_ = (rz);                                          \
		for (int gdz_ = -grz_; gdz_ <= grz_; gdz_++)                                        \
			for (int gdy_ = -gry_; gdy_ <= gry_; gdy_++) {                              \
				uint grow_ = ((uint)(gcz_ + gdz_) * (uint)grid_dim.y +                \
					      (uint)(gcy_ + gdy_)) * (uint)grid_dim.x +               \
					     (uint)gcx_;                                              \
				uint gbeg_ = cell_start[grow_ - (uint)grx_];                          \
				uint gend_ = cell_start[grow_ + (uint)grx_] + cell_count[grow_ + (uint)grx_]; \
				for (uint k = gbeg_; k < gend_; k++) {

#define GRID_FOR_END }}}
