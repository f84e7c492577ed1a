/* Uniform grid over a point set: a counting sort by cell id (DESIGN §3).
 *
 * Cells are cubes of side `cell` (the largest radius used by the pass). The
 * grid spans the points' bounding box plus one empty margin cell on each side,
 * so a query whose cell coordinate is clamped to [1, dim-2] can loop over the
 * 27 surrounding cells without bounds tests: for a query outside the box the
 * clamped cells are at least one cell away, and the strict `d < radius` test
 * rejects everything there. Positions are stored sorted by cell; perm maps a
 * sorted index back to the caller's index. */
#ifndef DP_GRID_GRID_H
#define DP_GRID_GRID_H

#include "dpoints.h"

/* Grids are capped at this many cells; a finer request grows the cell size,
 * which keeps neighbour queries correct (cells only need to be >= radius). */
#define DP_GRID_MAX_CELLS (1u << 24)

typedef struct dp_grid {
	size_t n;
	float cell;           /* actual cell side, >= the requested one */
	float origin[3];      /* corner of cell (0,0,0), the margin cell */
	int dim[3];           /* cells per axis, margins included */
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

/* Buckets n points into cells of side >= `cell`. Reuses g's buffers when large
 * enough; zero-initialise g before the first call. n may be 0. */
dp_status dp_grid_build(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float cell,
			dp_error *err);
void dp_grid_free(dp_grid *g);

/* dst[k] = src[perm[k]] for the n sorted slots: brings per-point attributes
 * into the grid's order. */
void dp_grid_gather(const dp_grid *g, const float *src, float *dst);

/* Cell coordinate of a position along one axis, clamped to [1, dim-2]. */
static inline int dp_grid_coord(const dp_grid *g, int axis, float v)
{
	/* Compared as float first: float -> int of huge values is undefined,
	 * and NaN fails every comparison. */
	float f = (v - g->origin[axis]) / g->cell;
	if (!(f >= 1.0f))
		return 1;
	if (f >= (float)(g->dim[axis] - 2))
		return g->dim[axis] - 2;
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

#endif
