/* Uniform grid over a point set: a counting sort by cell id (DESIGN §3).
 *
 * Cells are cubes of side `cell`. The grid spans the points' bounding box plus
 * `margin` empty cells on each side, and a query's cell coordinate is clamped
 * to [margin, dim-1-margin], the cells that hold points. A query may then scan
 * up to `margin` cells to each side without bounds tests. A scan of R <=
 * margin cells still finds every point within R cells of the query: inside the
 * box it is centred on the query's own cell; a query outside along an axis is
 * clamped to the outermost cell that holds points, and a point within R cells
 * of the query lies less than R cells further in than that cell, inside the
 * scanned range. dp_grid_build (margin 1) serves the 27-cell scan of dp_grid_rows
 * and GRID_PAIRS (cells >= the radius); dp_grid_build_margin with margin R the
 * scan of R cells per side (dp_grid_row, GRID_PAIRS_REACH), for queries whose
 * reach differs, with cells smaller than the longest reach. Positions are
 * stored sorted by cell; perm maps a sorted index back to the caller's index. */
#ifndef DP_GRID_GRID_H
#define DP_GRID_GRID_H

#include "dpoints.h"

#include <math.h>

/* Grids are capped at this many cells; a finer request grows the cell size,
 * which keeps neighbour queries correct (cells only need to be >= radius). */
#define DP_GRID_MAX_CELLS (1u << 24)
/* ... and at this many cells per point: a fine grid over a surface is mostly
 * empty cells, whose counts cost memory, host time and, on a device, an upload
 * per launch (measured: sinking's 1 r grid over 67K points made the OpenCL
 * backend slower than the reference). Coarser cells cost only extra distance
 * tests. */
#define DP_GRID_CELLS_PER_POINT 8
#define DP_GRID_MIN_CELLS 4096
/* The margin cells alone, (2 margin + 1)^3, must fit under DP_GRID_MAX_CELLS
 * whatever the cell size. */
#define DP_GRID_MAX_MARGIN 64

typedef struct dp_grid {
	size_t n;
	float cell;           /* actual cell side, >= the requested one */
	float origin[3];      /* corner of cell (0,0,0), a margin cell */
	int dim[3];           /* cells per axis, margins included */
	int margin;           /* empty cells on each side */
	uint32_t ncells;
	uint32_t *cell_start; /* ncells: first sorted index of each cell */
	uint32_t *cell_count; /* ncells */
	uint32_t *perm;       /* n: sorted index -> original index */
	float *x, *y, *z;     /* n: positions in sorted order */
	/* capacities, so rebuilding every iteration reuses memory */
	size_t cap_n;
	uint32_t cap_cells;
	uint32_t *scratch;    /* n: cell id of each original point */
} dp_grid;

/* Buckets n points into cells of side >= `cell` with one margin cell. Reuses
 * g's buffers when large enough; zero-initialise g before the first call. n may
 * be 0. */
dp_status dp_grid_build(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float cell,
			dp_error *err);
/* The same with `margin` (1..DP_GRID_MAX_MARGIN) empty cells on each side, for
 * scans of up to `margin` cells per side. */
dp_status dp_grid_build_margin(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float cell,
			       int margin, dp_error *err);
void dp_grid_free(dp_grid *g);

/* dst[k] = src[perm[k]] for the n sorted slots: brings per-point attributes
 * into the grid's order. */
void dp_grid_gather(const dp_grid *g, const float *src, float *dst);

/* Cell coordinate of a position along one axis, clamped to [margin, dim-1-margin]. */
static inline int dp_grid_coord(const dp_grid *g, int axis, float v)
{
	/* Compared as float first: float -> int of huge values is undefined,
	 * and NaN fails every comparison. */
	float f = (v - g->origin[axis]) / g->cell;
	if (!(f >= (float)g->margin))
		return g->margin;
	if (f >= (float)(g->dim[axis] - 1 - g->margin))
		return g->dim[axis] - 1 - g->margin;
	return (int)f;
}

static inline uint32_t dp_grid_cell_id(const dp_grid *g, int cx, int cy, int cz)
{
	return ((uint32_t)cz * (uint32_t)g->dim[1] + (uint32_t)cy) * (uint32_t)g->dim[0] + (uint32_t)cx;
}

/* The sorted-index ranges [beg[r], end[r]) of the 9 rows of 3 cells around
 * (px, py, pz): every point within one cell of it lies in one of them. Cells
 * adjacent in x are adjacent in the sort, so a row is one contiguous range. */
static inline void dp_grid_rows(const dp_grid *g, float px, float py, float pz, uint32_t beg[9], uint32_t end[9])
{
	int cx = dp_grid_coord(g, 0, px), cy = dp_grid_coord(g, 1, py), cz = dp_grid_coord(g, 2, pz);
	int r = 0;
	for (int dz = -1; dz <= 1; dz++)
		for (int dy = -1; dy <= 1; dy++, r++) {
			uint32_t row = dp_grid_cell_id(g, cx, cy + dy, cz + dz);
			beg[r] = g->cell_start[row - 1];
			end[r] = g->cell_start[row + 1] + g->cell_count[row + 1];
		}
}

/* How many (query, candidate) distance tests a 27-cell scan of these queries
 * makes: the "pair evaluations" that benchmarks report per second. */
double dp_grid_candidates(const dp_grid *g, size_t nq, const float *qx, const float *qy, const float *qz);

/* The number of cells that covers a length `len` along an axis, ceil(len /
 * cell), clamped to [0, margin] (NaN gives the margin). A length beyond
 * margin * cell is cut: build with a margin that covers the longest reach.
 * The division is in float, as on the device; callers whose lengths are
 * exact bounds add a little slack, so that a point within reach never sits on
 * the far side of a rounded cell border. */
static inline int dp_grid_reach_cells(const dp_grid *g, float len)
{
	float f = ceilf(len / g->cell);
	if (!(f < (float)g->margin))
		return g->margin;
	return f > 0.0f ? (int)f : 0;
}

/* The sorted-index range [*beg, *end) of the row of 2 rx + 1 cells centred on
 * cell (cx, cy, cz), 0 <= rx <= margin. A scan of reach (rx, ry, rz) around a
 * query takes the rows at (cx, cy + dy, cz + dz) for |dy| <= ry, |dz| <= rz,
 * with (cx, cy, cz) its clamped cell (dp_grid_coord): it holds every point
 * whose offset from the query is at most rx, ry, rz cells along x, y, z. */
static inline void dp_grid_row(const dp_grid *g, int cx, int cy, int cz, int rx, uint32_t *beg, uint32_t *end)
{
	uint32_t row = dp_grid_cell_id(g, cx, cy, cz);
	*beg = g->cell_start[row - (uint32_t)rx];
	*end = g->cell_start[row + (uint32_t)rx] + g->cell_count[row + (uint32_t)rx];
}

/* Pair evaluations of scans with per-query reaches: reach[3*i + a] is query
 * i's reach along axis a as a length (converted by dp_grid_reach_cells). */
double dp_grid_candidates_reach(const dp_grid *g, size_t nq, const float *qx, const float *qy, const float *qz,
				const float *reach);

/* Pair evaluations of scans of `cells` cells on each side on every axis
 * (0 <= cells <= margin). */
double dp_grid_candidates_cells(const dp_grid *g, size_t nq, const float *qx, const float *qy, const float *qz,
				int cells);

#endif
