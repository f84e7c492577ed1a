/* Checks at the ends of the whole pipeline: an input that spans a volume
 * going in, and results that stay near the input coming out. */
#ifndef DP_STAGES_INPUT_CHECK_H
#define DP_STAGES_INPUT_CHECK_H

#include "dpoints.h"

/* Fails (DP_ERR_ARG, the message starting with "consolidate:") when `in`
 * spans no volume: fewer than 4 points, or all of them on one line or in one
 * plane (thinner than DP_FLAT_RATIO of their extent). The meso-skeleton lies
 * inside a solid; such an input has none. */
dp_status dp_check_volume(const dp_cloud *in, dp_error *err);

/* A point set thinner than this fraction of its extent counts as flat: float
 * coordinates carry about 6e-8 relative error, real scans far more noise. */
#define DP_FLAT_RATIO 1e-5

/* Fails (DP_ERR_ARG, naming the stage and the point) when a point of the WLOP
 * samples, skeleton or surface of `res` lies outside the input's bounding box
 * grown by one box diagonal on every side: no stage moves a point that far on
 * an input it can handle (completing an unseen back side reaches about one
 * box depth). The anchors are not checked: unsettled points may sink far and
 * are only an intermediate. Measured: a 3-view torus scan at 91-100 deep
 * points had its whole skeleton 13-14 units below the 0.6-unit torus; at 200
 * none out. */
dp_status dp_check_result_bounds(const dp_cloud *in, const dp_result *res, dp_error *err);

#endif
