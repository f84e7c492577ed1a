#ifndef DP_KNN_ATTRIBUTES_H
#define DP_KNN_ATTRIBUTES_H

#include "dpoints.h"

/* Gives every point of `dst` the colour and intensity of its nearest point
 * in `src` (dst->rgb and dst->intensity replaced; left NULL where src has
 * none). DP_ERR_NOMEM, or the kNN's errors; both are then NULL. */
dp_status dp_transfer_attributes(dp_cloud *dst, const dp_cloud *src, dp_error *err);

#endif
