/* WLOP under another progress name (dpoints.h, dp_wlop). */
#ifndef DP_STAGES_WLOP_H
#define DP_STAGES_WLOP_H

#include "dpoints.h"

/* dp_wlop, reporting its iterations to the progress callback as `stage` (a
 * string that outlives the call: the callback may keep the pointer), so that
 * runs with another purpose (the coarser levels a one-sided scan tries, the
 * denser samples that sign a small count's normals) are told apart from the
 * samples the caller asked for. */
dp_status dp_wlop_as(dp_context *ctx, const char *stage, const dp_cloud *input, const dp_wlop_params *params,
		     dp_cloud *samples, dp_wlop_stats *stats, dp_error *err);

#endif
