#include "ops/operators.h"

#include "core/common.h"

dp_status dp_peak_grid(dp_grid *g, size_t n, const float *x, const float *y, const float *z, float radius,
		       int reach, int *cells_reach, dp_error *err)
{
	if (reach < 1 || reach > DP_GRID_MAX_MARGIN || !(radius > 0.0f))
		return dp_fail(err, DP_ERR_ARG, "peak: reach %d outside 1..%d or radius %g not positive", reach,
			       DP_GRID_MAX_MARGIN, (double)radius);
	dp_status st = dp_grid_build_margin(g, n, x, y, z, radius / (float)reach, reach, err);
	if (st == DP_OK)
		*cells_reach = dp_grid_reach_cells(g, radius);
	return st;
}
