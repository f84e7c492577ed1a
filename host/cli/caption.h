#ifndef DP_CLI_CAPTION_H
#define DP_CLI_CAPTION_H

/* Text in a 3x5 pixel font scaled by `scale` (glyphs 4*scale apart, 5*scale
 * high) into an RGB image of w x h pixels at (x, y), its top left; stops
 * before a glyph would cross max_x. */
void dp_cli_draw_text(unsigned char *rgb, int w, int h, int x, int y, int max_x, const char *text, int scale,
		      const unsigned char ink[3]);
/* The scale for a view `view_width` pixels wide: 1 up to 511 pixels, 2 at
 * 512, at most 4. */
int dp_cli_caption_scale(int view_width);
int dp_cli_caption_width(const char *text, int scale);

#include "dpoints.h"

/* The vertical axis (1 y, 2 z) of the union of n clouds, for renders not
 * told with --up. */
int dp_cli_detect_up(const dp_cloud *clouds, size_t n);

#endif
