/* The surface stage under another progress name (dpoints.h, dp_surface). */
#ifndef DP_STAGES_SURFACE_H
#define DP_STAGES_SURFACE_H

#include "dpoints.h"

/* dp_surface, reporting its iterations to the progress callback as `stage`
 * (a string that outlives the call: the callback may keep the pointer), so
 * that runs with another purpose (the even-spacing rounds) are told apart
 * from the surface levels, and taking the scan's edge (where it faces the
 * scanner: silhouette_edge_margin_r) from the normals of `scan`, samples on
 * the scan with unit normals (dp_surface: `samples`; a refined level's
 * samples are the completed surface, whose normals face every way, so
 * dp_consolidate passes the coarse level's WLOP samples). */
dp_status dp_surface_as(dp_context *ctx, const char *stage, const dp_cloud *input, const dp_cloud *samples,
			const dp_cloud *scan, dp_cloud *skeleton, const dp_balls *balls, double r,
			const dp_surface_params *params, dp_cloud *surface, float *eta, dp_surface_stats *stats,
			dp_error *err);

#endif
