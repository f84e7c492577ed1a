/* The surface stage under another progress name (dpoints.h, dp_surface). */
#ifndef DP_STAGES_SURFACE_H
#define DP_STAGES_SURFACE_H

#include "dpoints.h"

/* dp_surface, reporting its iterations to the progress callback as `stage`
 * (a string that outlives the call: the callback may keep the pointer), so
 * that runs with another purpose (the even-spacing rounds) are told apart
 * from the surface levels. */
dp_status dp_surface_as(dp_context *ctx, const char *stage, const dp_cloud *input, const dp_cloud *samples,
			dp_cloud *skeleton, const dp_balls *balls, double r, const dp_surface_params *params,
			dp_cloud *surface, float *eta, dp_surface_stats *stats, dp_error *err);

#endif
