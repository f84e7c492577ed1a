#include "grid/grid.h"

#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static dp_status reserve(dp_grid *g, size_t n, uint32_t ncells, dp_error *err)
{
	if (n > g->cap_n || !g->perm) {
		size_t cap = n ? n : 1;
		uint32_t *perm = realloc(g->perm, cap * sizeof *perm);
		if (perm)
			g->perm = perm;
		uint32_t *scratch = realloc(g->scratch, cap * sizeof *scratch);
		if (scratch)
			g->scratch = scratch;
		float *x = realloc(g->x, cap * sizeof *x);
		if (x)
			g->x = x;
		float *y = realloc(g->y, cap * sizeof *y);
		if (y)
			g->y = y;
		float *z = realloc(g->z, cap * sizeof *z);
		if (z)
			g->z = z;
		if (!perm || !scratch || !x || !y || !z)
			return dp_fail(err, DP_ERR_NOMEM, "grid: out of memory for %zu points", n);
		g->cap_n = cap;
	}
	if (ncells > g->cap_cells || !g->cell_start) {
		uint32_t *start = realloc(g->cell_start, (size_t)ncells * sizeof *start);
		if (start)
			g->cell_start = start;
		uint32_t *count = realloc(g->cell_count, (size_t)ncells * sizeof *count);
		if (count)
			g->cell_count = count;
		if (!start || !count)
			return dp_fail(err, DP_ERR_NOMEM, "grid: out of memory for %u cells", ncells);
		g->cap_cells = ncells;
	}
	return DP_OK;
}

dp_status dp_grid_build(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float cell,
			dp_error *err)
{
	return dp_grid_build_margin(g, n, x, y, z, cell, 1, err);
}

dp_status dp_grid_build_margin(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float cell,
			       int margin, dp_error *err)
{
	if (!(cell > 0.0f) || !isfinite(cell))
		return dp_fail(err, DP_ERR_ARG, "grid: cell size %g is not a positive number", (double)cell);
	if (margin < 1 || margin > DP_GRID_MAX_MARGIN)
		return dp_fail(err, DP_ERR_ARG, "grid: margin %d is outside [1, %d] cells", margin,
			       DP_GRID_MAX_MARGIN);
	if (n > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "grid: %zu points exceed the 32-bit index range", n);

	float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
	if (n) {
		lo[0] = hi[0] = x[0];
		lo[1] = hi[1] = y[0];
		lo[2] = hi[2] = z[0];
	}
	for (size_t i = 1; i < n; i++) {
		lo[0] = fminf(lo[0], x[i]);
		hi[0] = fmaxf(hi[0], x[i]);
		lo[1] = fminf(lo[1], y[i]);
		hi[1] = fmaxf(hi[1], y[i]);
		lo[2] = fminf(lo[2], z[i]);
		hi[2] = fmaxf(hi[2], z[i]);
	}
	/* Grow the cell until the grid fits the caps; cells only need to be >= radius. */
	double side = 2.0 * margin + 2.0; /* the margins alone need this many cells per axis */
	double cap = fmin((double)DP_GRID_MAX_CELLS,
			  fmax(fmax((double)DP_GRID_MIN_CELLS, side * side * side),
			       (double)DP_GRID_CELLS_PER_POINT * (double)n));
	/* Spans in double: finite float coordinates far apart (±3e38) overflow a
	 * float difference, and the growth would then never end. */
	double span[3];
	for (int a = 0; a < 3; a++)
		span[a] = (double)hi[a] - (double)lo[a];
	for (;;) {
		double cells = 1.0;
		for (int a = 0; a < 3; a++)
			cells *= floor(span[a] / cell) + 1.0 + 2.0 * margin;
		if (cells <= cap)
			break;
		cell *= 1.25f;
		if (!isfinite(cell))
			break;
	}
	for (int a = 0; a < 3; a++)
		if (!isfinite(cell) || !isfinite(lo[a] - (float)margin * cell) || !isfinite(hi[a] + (float)margin * cell))
			return dp_fail(err, DP_ERR_ARG, "grid: coordinates spanning %g are too far apart for float cells",
				       span[a]);
	g->cell = cell;
	g->margin = margin;
	g->ncells = 1;
	for (int a = 0; a < 3; a++) {
		g->dim[a] = (int)floor(span[a] / cell) + 1 + 2 * margin;
		g->origin[a] = lo[a] - (float)margin * cell;
		g->ncells *= (uint32_t)g->dim[a];
	}
	dp_status st = reserve(g, n, g->ncells, err);
	if (st != DP_OK)
		return st;
	g->n = n;

	memset(g->cell_count, 0, (size_t)g->ncells * sizeof *g->cell_count);
	for (size_t i = 0; i < n; i++) {
		uint32_t id = dp_grid_cell_id(g, dp_grid_coord(g, 0, x[i]), dp_grid_coord(g, 1, y[i]),
					      dp_grid_coord(g, 2, z[i]));
		g->scratch[i] = id;
		g->cell_count[id]++;
	}
	uint32_t acc = 0;
	for (uint32_t c = 0; c < g->ncells; c++) {
		g->cell_start[c] = acc;
		acc += g->cell_count[c];
	}
	/* Stable placement: cell_start is advanced while filling, then restored. */
	for (size_t i = 0; i < n; i++) {
		uint32_t k = g->cell_start[g->scratch[i]]++;
		g->perm[k] = (uint32_t)i;
		g->x[k] = x[i];
		g->y[k] = y[i];
		g->z[k] = z[i];
	}
	for (uint32_t c = 0; c < g->ncells; c++)
		g->cell_start[c] -= g->cell_count[c];
	return DP_OK;
}

void dp_grid_free(dp_grid *g)
{
	free(g->cell_start);
	free(g->cell_count);
	free(g->perm);
	free(g->x);
	free(g->y);
	free(g->z);
	free(g->scratch);
	memset(g, 0, sizeof *g);
}

void dp_grid_gather(const dp_grid *g, const float *src, float *dst)
{
	for (size_t k = 0; k < g->n; k++)
		dst[k] = src[g->perm[k]];
}

double dp_grid_candidates(const dp_grid *g, size_t nq, const float *qx, const float *qy, const float *qz)
{
	double total = 0.0;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < nq; i++) {
		dp_grid_rows(g, qx[i], qy[i], qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			total += (double)(end[r] - beg[r]);
	}
	return total;
}

double dp_grid_candidates_reach(const dp_grid *g, size_t nq, const float *qx, const float *qy, const float *qz,
				const float *reach)
{
	double total = 0.0;
	for (size_t i = 0; i < nq; i++) {
		int cx = dp_grid_coord(g, 0, qx[i]), cy = dp_grid_coord(g, 1, qy[i]), cz = dp_grid_coord(g, 2, qz[i]);
		int rx = dp_grid_reach_cells(g, reach[3 * i]), ry = dp_grid_reach_cells(g, reach[3 * i + 1]);
		int rz = dp_grid_reach_cells(g, reach[3 * i + 2]);
		for (int dz = -rz; dz <= rz; dz++)
			for (int dy = -ry; dy <= ry; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, cx, cy + dy, cz + dz, rx, &beg, &end);
				total += (double)(end - beg);
			}
	}
	return total;
}

double dp_grid_candidates_cells(const dp_grid *g, size_t nq, const float *qx, const float *qy, const float *qz,
				int cells)
{
	double total = 0.0;
	for (size_t i = 0; i < nq; i++) {
		int cx = dp_grid_coord(g, 0, qx[i]), cy = dp_grid_coord(g, 1, qy[i]), cz = dp_grid_coord(g, 2, qz[i]);
		for (int dz = -cells; dz <= cells; dz++)
			for (int dy = -cells; dy <= cells; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, cx, cy + dy, cz + dz, cells, &beg, &end);
				total += (double)(end - beg);
			}
	}
	return total;
}
