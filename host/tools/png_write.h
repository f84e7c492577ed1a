/* Writing an RGB image as a PNG file. Internal to the library. */
#ifndef DP_TOOLS_PNG_WRITE_H
#define DP_TOOLS_PNG_WRITE_H

#include "dpoints_tools.h"

/* Writes w x h pixels (3 bytes each, rows top to bottom) as an 8-bit RGB PNG
 * at `path`, through a temporary file in the same folder that is renamed at
 * the end, so a failure leaves neither `path` nor the temporary behind.
 * Fails with DP_ERR_IO naming `path`. Reentrant. */
dp_status dp_png_write_rgb(const char *path, const unsigned char *rgb, int w, int h, dp_error *err);

#endif
