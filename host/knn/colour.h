#ifndef DP_KNN_COLOUR_H
#define DP_KNN_COLOUR_H

#include "dpoints.h"

/* Gives every point of `dst` the colour of its nearest point in `src`
 * (dst->rgb replaced); nothing when src has no colours or dst no points.
 * DP_ERR_NOMEM, or the kNN's errors; dst->rgb is then NULL. */
dp_status dp_transfer_colours(dp_cloud *dst, const dp_cloud *src, dp_error *err);

#endif
