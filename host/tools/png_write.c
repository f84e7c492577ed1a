#include "tools/png_write.h"

#include "core/common.h"
#include "io/io.h"

#include <png.h>
#include <setjmp.h>
#include <stdio.h>

/* libpng reports errors through a callback that must not return; it keeps the
 * message here and jumps back to the setjmp in encode(). */
typedef struct png_failure {
	char message[256];
} png_failure;

static void on_png_error(png_structp png, png_const_charp message)
{
	png_failure *failure = png_get_error_ptr(png);
	snprintf(failure->message, sizeof failure->message, "%s", message);
	png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp message)
{
	(void)png;
	(void)message;
}

/* Encodes the image to `file`; returns 0, or -1 with failure->message set. */
static int encode(FILE *file, const unsigned char *rgb, int w, int h, png_failure *failure)
{
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, failure, on_png_error,
						  on_png_warning);
	if (!png) {
		snprintf(failure->message, sizeof failure->message, "out of memory in libpng");
		return -1;
	}
	png_infop info = png_create_info_struct(png);
	if (!info) {
		png_destroy_write_struct(&png, NULL);
		snprintf(failure->message, sizeof failure->message, "out of memory in libpng");
		return -1;
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		return -1;
	}
	png_init_io(png, file);
	png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_write_info(png, info);
	for (int y = 0; y < h; y++)
		png_write_row(png, rgb + (size_t)y * (size_t)w * 3);
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	return 0;
}

dp_status dp_png_write_rgb(const char *path, const unsigned char *rgb, int w, int h, dp_error *err)
{
	if (!path || !rgb || w <= 0 || h <= 0)
		return dp_fail(err, DP_ERR_ARG, "%s: no image to write", path ? path : "(null path)");
	dp_atomic_file af;
	dp_status st = dp_atomic_open(&af, path, err);
	if (st != DP_OK)
		return st;
	png_failure failure = { "" };
	if (encode(af.f, rgb, w, h, &failure) != 0) {
		dp_atomic_abort(&af);
		return dp_fail(err, DP_ERR_IO, "%s: PNG encoding failed: %s", path, failure.message);
	}
	return dp_atomic_commit(&af, err);
}
