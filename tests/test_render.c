/* PNG renders: image layout, shading, segments, z-buffer, colours, and that
 * failures name the path and leave no file. Images are read back with
 * libpng, so every check also proves the file is a valid PNG. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "dpoints_tools.h"

#include <dirent.h>
#include <limits.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SPHERE_POINTS 4000
#define VIEW 96

typedef struct image {
	int w, h;
	unsigned char *rgb;
} image;

static const unsigned char white[3] = { 255, 255, 255 };
static const unsigned char red[3] = { 200, 30, 30 };
static const unsigned char green[3] = { 30, 190, 30 };
static const unsigned char blue[3] = { 20, 40, 220 };

static void on_png_error(png_structp png, png_const_charp message)
{
	print_error("libpng: %s\n", message);
	png_longjmp(png, 1);
}

/* Reads an 8-bit RGB PNG; fails the test if libpng rejects it or it has
 * another format. */
static image read_png(const char *path)
{
	image img = { 0, 0, NULL };
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, on_png_error, NULL);
	png_infop info = png_create_info_struct(png);
	assert_non_null(png);
	assert_non_null(info);
	unsigned char *volatile rgb = NULL;
	if (setjmp(png_jmpbuf(png))) {
		free(rgb);
		png_destroy_read_struct(&png, &info, NULL);
		fclose(f);
		fail_msg("%s is not a valid PNG", path);
	}
	png_init_io(png, f);
	png_read_info(png, info);
	assert_int_equal(png_get_color_type(png, info), PNG_COLOR_TYPE_RGB);
	assert_int_equal(png_get_bit_depth(png, info), 8);
	img.w = (int)png_get_image_width(png, info);
	img.h = (int)png_get_image_height(png, info);
	rgb = malloc((size_t)img.w * (size_t)img.h * 3);
	assert_non_null(rgb);
	for (int y = 0; y < img.h; y++)
		png_read_row(png, rgb + (size_t)y * (size_t)img.w * 3, NULL);
	png_read_end(png, NULL);
	png_destroy_read_struct(&png, &info, NULL);
	fclose(f);
	img.rgb = rgb;
	return img;
}

static const unsigned char *pixel(const image *img, int x, int y)
{
	assert_true(x >= 0 && x < img->w && y >= 0 && y < img->h);
	return img->rgb + 3 * ((size_t)y * (size_t)img->w + (size_t)x);
}

static int same_colour(const unsigned char *a, const unsigned char *b)
{
	return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* Shading scales a colour, so its dominant channel stays dominant. */
static int dominant(const unsigned char *p, int channel)
{
	for (int c = 0; c < 3; c++)
		if (c != channel && !(p[channel] > 2 * p[c] + 10))
			return 0;
	return 1;
}

static char *temp_dir(void)
{
	char *dir = strdup("/tmp/dp_test_render_XXXXXX");
	assert_non_null(dir);
	assert_non_null(mkdtemp(dir));
	return dir;
}

static int count_entries(const char *dir)
{
	DIR *d = opendir(dir);
	assert_non_null(d);
	int n = 0;
	struct dirent *e;
	while ((e = readdir(d)))
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
			n++;
	closedir(d);
	return n;
}

static void join(char *out, size_t size, const char *dir, const char *name)
{
	assert_true((size_t)snprintf(out, size, "%s/%s", dir, name) < size);
}

/* Evenly spread points on a sphere (Fibonacci spiral), normals outwards. */
static void make_sphere(dp_cloud *c, size_t n, const double centre[3], double radius, int with_normals)
{
	assert_int_equal(dp_cloud_alloc(c, n, with_normals, NULL), DP_OK);
	const double golden = M_PI * (3.0 - sqrt(5.0));
	for (size_t i = 0; i < n; i++) {
		double y = 1.0 - 2.0 * ((double)i + 0.5) / (double)n;
		double ring = sqrt(1.0 - y * y);
		double n3[3] = { ring * cos(golden * (double)i), y, ring * sin(golden * (double)i) };
		c->x[i] = (float)(centre[0] + radius * n3[0]);
		c->y[i] = (float)(centre[1] + radius * n3[1]);
		c->z[i] = (float)(centre[2] + radius * n3[2]);
		if (with_normals) {
			c->nx[i] = (float)n3[0];
			c->ny[i] = (float)n3[1];
			c->nz[i] = (float)n3[2];
		}
	}
}

/* A k x k grid of points filling the square |x|,|y| <= half at height z. */
static void make_patch(dp_cloud *c, int k, double half, double z)
{
	assert_int_equal(dp_cloud_alloc(c, (size_t)k * (size_t)k, 0, NULL), DP_OK);
	for (int i = 0; i < k; i++)
		for (int j = 0; j < k; j++) {
			size_t at = (size_t)i * (size_t)k + (size_t)j;
			c->x[at] = (float)(-half + 2.0 * half * i / (k - 1));
			c->y[at] = (float)(-half + 2.0 * half * j / (k - 1));
			c->z[at] = (float)z;
		}
}

static dp_render_layer layer_of(const dp_cloud *c, const unsigned char rgb[3])
{
	dp_render_layer l;
	memset(&l, 0, sizeof l);
	l.cloud = c;
	memcpy(l.rgb, rgb, 3);
	return l;
}

/* Along row y of the view starting at x0, the first and last column that is
 * not background; -1 when the row is empty. */
static void row_extent(const image *img, int x0, int y, const unsigned char bg[3], int *first, int *last)
{
	*first = *last = -1;
	for (int x = x0; x < x0 + VIEW; x++)
		if (!same_colour(pixel(img, x, y), bg)) {
			if (*first < 0)
				*first = x;
			*last = x;
		}
}

static void test_sphere_views(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512];
	join(path, sizeof path, dir, "sphere.png");
	dp_cloud sphere;
	const double centre[3] = { 3.0, -2.0, 5.0 };
	make_sphere(&sphere, SPHERE_POINTS, centre, 1.5, 1);
	dp_render_layer layer = layer_of(&sphere, red);
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = VIEW;
	p.views = 3;
	dp_error err = { 0 };
	assert_int_equal(dp_render_png(path, &layer, 1, &p, &err), DP_OK);

	image img = read_png(path);
	assert_int_equal(img.w, 3 * VIEW);
	assert_int_equal(img.h, VIEW);
	for (int k = 0; k < 3; k++) {
		int x0 = k * VIEW, cx = x0 + VIEW / 2, cy = VIEW / 2;
		assert_true(same_colour(pixel(&img, x0, 0), white));
		assert_true(same_colour(pixel(&img, x0 + VIEW - 1, 0), white));
		assert_true(same_colour(pixel(&img, x0, VIEW - 1), white));
		assert_true(same_colour(pixel(&img, x0 + VIEW - 1, VIEW - 1), white));
		assert_true(dominant(pixel(&img, cx, cy), 0));

		/* Centred, sizeable, no holes inside with the automatic splat size. */
		int first, last;
		row_extent(&img, x0, cy, white, &first, &last);
		assert_true(first > x0 && last < x0 + VIEW - 1);
		int radius = (last - first) / 2;
		assert_true(radius > VIEW / 6);
		assert_true(abs((first + last) / 2 - cx) <= 2);
		for (int y = cy - radius * 8 / 10; y <= cy + radius * 8 / 10; y++)
			for (int x = cx - radius * 8 / 10; x <= cx + radius * 8 / 10; x++)
				if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= radius * radius * 64 / 100)
					assert_true(dominant(pixel(&img, x, y), 0));

		/* Lambert: facing the viewer bright, edge-on dark. */
		const unsigned char *middle = pixel(&img, cx, cy), *rim = pixel(&img, last, cy);
		assert_true(dominant(rim, 0));
		assert_true(middle[0] > rim[0] * 3 / 2);
	}
	free(img.rgb);
	dp_cloud_free(&sphere);
	unlink(path);
	rmdir(dir);
	free(dir);
}

static void test_depth_shading_without_normals(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512];
	join(path, sizeof path, dir, "plain.png");
	dp_cloud sphere;
	const double centre[3] = { 0.0, 0.0, 0.0 };
	make_sphere(&sphere, SPHERE_POINTS, centre, 1.0, 0);
	dp_render_layer layer = layer_of(&sphere, green);
	const unsigned char navy[3] = { 0, 0, 64 };
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = VIEW;
	p.views = 1;
	p.elevation_deg = 0.0;
	memcpy(p.background, navy, 3);
	assert_int_equal(dp_render_png(path, &layer, 1, &p, NULL), DP_OK);

	image img = read_png(path);
	assert_int_equal(img.w, VIEW);
	assert_int_equal(img.h, VIEW);
	assert_true(same_colour(pixel(&img, 0, 0), navy));
	assert_true(same_colour(pixel(&img, VIEW - 1, VIEW - 1), navy));
	int first, last;
	row_extent(&img, 0, VIEW / 2, navy, &first, &last);
	assert_true(first > 0);
	const unsigned char *middle = pixel(&img, VIEW / 2, VIEW / 2), *rim = pixel(&img, last, VIEW / 2);
	assert_true(dominant(middle, 1));
	assert_true(dominant(rim, 1));
	/* The nearest point is brighter than the silhouette. */
	assert_true(middle[1] > rim[1] * 6 / 5);
	free(img.rgb);
	dp_cloud_free(&sphere);
	unlink(path);
	rmdir(dir);
	free(dir);
}

static void test_segment_is_a_thin_line(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512];
	join(path, sizeof path, dir, "segment.png");
	dp_cloud ends;
	assert_int_equal(dp_cloud_alloc(&ends, 2, 0, NULL), DP_OK);
	ends.x[0] = -1.0f, ends.y[0] = -0.5f, ends.z[0] = 0.0f;
	ends.x[1] = 1.0f, ends.y[1] = 0.5f, ends.z[1] = 0.0f;
	const uint32_t edge[2] = { 0, 1 };
	dp_render_layer layer = layer_of(&ends, blue);
	layer.edges = edge;
	layer.nedges = 1;
	layer.segments_only = 1;
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = VIEW;
	p.views = 1;
	p.elevation_deg = 0.0;
	assert_int_equal(dp_render_png(path, &layer, 1, &p, NULL), DP_OK);

	/* Seen from +z with x to the right: a line rising to the right with
	 * slope 1/2, one or two pixels per column, no gaps. */
	image img = read_png(path);
	int columns = 0, first = -1, last = -1;
	double sx = 0, sy = 0, sxx = 0, sxy = 0;
	for (int x = 0; x < VIEW; x++) {
		int hits = 0;
		double ysum = 0;
		for (int y = 0; y < VIEW; y++) {
			const unsigned char *q = pixel(&img, x, y);
			if (same_colour(q, white))
				continue;
			assert_true(dominant(q, 2));
			hits++;
			ysum += y;
		}
		assert_true(hits <= 2);
		if (!hits)
			continue;
		if (first < 0)
			first = x;
		assert_true(last < 0 || last == x - 1);
		last = x;
		columns++;
		double ymean = ysum / hits;
		sx += x, sy += ymean, sxx += (double)x * x, sxy += x * ymean;
	}
	assert_true(columns >= VIEW * 8 / 10);
	double slope = (columns * sxy - sx * sy) / (columns * sxx - sx * sx);
	assert_true(fabs(slope - -0.5) < 0.03);
	free(img.rgb);
	dp_cloud_free(&ends);
	unlink(path);
	rmdir(dir);
	free(dir);
}

/* Along the centre row: how many pixels are red and green, and whether the
 * red ones form one run with green on both sides. */
static void classify_centre_row(const image *img, int *nred, int *ngreen, int *red_enclosed)
{
	int y = VIEW / 2, red_first = -1, red_last = -1, green_left = 0, green_right = 0;
	*nred = *ngreen = 0;
	for (int x = 0; x < VIEW; x++) {
		const unsigned char *q = pixel(img, x, y);
		if (dominant(q, 0)) {
			(*nred)++;
			if (red_first < 0)
				red_first = x;
			red_last = x;
		} else if (dominant(q, 1)) {
			(*ngreen)++;
			green_left += red_first < 0;
			green_right += red_first >= 0;
		}
	}
	*red_enclosed = *nred > 0 && *nred == red_last - red_first + 1 && green_left > 0 && green_right > 0;
}

static void test_zbuffer_front_wins(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512];
	join(path, sizeof path, dir, "depth.png");
	dp_cloud near_patch, far_patch;
	make_patch(&near_patch, 40, 0.5, 0.5);
	make_patch(&far_patch, 80, 1.0, -0.5);
	dp_render_layer both[2] = { layer_of(&near_patch, red), layer_of(&far_patch, green) };
	dp_render_layer reversed[2] = { both[1], both[0] };
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = VIEW;
	p.views = 1;
	p.elevation_deg = 0.0;

	/* The camera sits on +z (azimuth 0, up y): the small red patch is in
	 * front, whichever layer is drawn last. */
	for (int order = 0; order < 2; order++) {
		assert_int_equal(dp_render_png(path, order ? reversed : both, 2, &p, NULL), DP_OK);
		image img = read_png(path);
		int nred, ngreen, enclosed;
		classify_centre_row(&img, &nred, &ngreen, &enclosed);
		assert_true(enclosed);
		double red_share = (double)nred / (nred + ngreen);
		assert_true(red_share > 0.4 && red_share < 0.6);
		free(img.rgb);
	}
	/* From behind the big green patch hides the red one completely. */
	p.azimuth_deg = 180.0;
	for (int order = 0; order < 2; order++) {
		assert_int_equal(dp_render_png(path, order ? reversed : both, 2, &p, NULL), DP_OK);
		image img = read_png(path);
		int nred, ngreen, enclosed;
		classify_centre_row(&img, &nred, &ngreen, &enclosed);
		assert_int_equal(nred, 0);
		assert_true(ngreen > VIEW / 2);
		free(img.rgb);
	}
	dp_cloud_free(&near_patch);
	dp_cloud_free(&far_patch);
	unlink(path);
	rmdir(dir);
	free(dir);
}

static void test_single_point(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512];
	join(path, sizeof path, dir, "one.png");
	dp_cloud one;
	assert_int_equal(dp_cloud_alloc(&one, 1, 0, NULL), DP_OK);
	one.x[0] = 7.0f, one.y[0] = 7.0f, one.z[0] = 7.0f;
	dp_render_layer layer = layer_of(&one, red);
	layer.point_size_px = 9.0f;
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = VIEW;
	p.views = 2;
	assert_int_equal(dp_render_png(path, &layer, 1, &p, NULL), DP_OK);
	image img = read_png(path);
	int drawn = 0;
	for (int y = 0; y < img.h; y++)
		for (int x = 0; x < img.w; x++)
			drawn += !same_colour(pixel(&img, x, y), white);
	assert_true(dominant(pixel(&img, VIEW / 2, VIEW / 2), 0));
	assert_true(dominant(pixel(&img, VIEW + VIEW / 2, VIEW / 2), 0));
	/* Two discs of diameter 9: about 2 * 64 pixels. */
	assert_true(drawn > 2 * 50 && drawn < 2 * 80);
	free(img.rgb);
	dp_cloud_free(&one);
	unlink(path);
	rmdir(dir);
	free(dir);
}

static void test_unwritable_paths_leave_nothing(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512], sub[512];
	dp_cloud sphere;
	const double centre[3] = { 0.0, 0.0, 0.0 };
	make_sphere(&sphere, 500, centre, 1.0, 0);
	dp_render_layer layer = layer_of(&sphere, red);
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = 32;
	dp_error err = { 0 };

	join(path, sizeof path, dir, "missing/out.png");
	assert_int_equal(dp_render_png(path, &layer, 1, &p, &err), DP_ERR_IO);
	assert_non_null(strstr(err.message, path));
	assert_int_equal(count_entries(dir), 0);

	/* The target is a folder: the temporary is written, the rename fails
	 * and the temporary must go. */
	join(sub, sizeof sub, dir, "folder.png");
	assert_int_equal(mkdir(sub, 0755), 0);
	memset(&err, 0, sizeof err);
	assert_int_equal(dp_render_png(sub, &layer, 1, &p, &err), DP_ERR_IO);
	assert_non_null(strstr(err.message, sub));
	assert_int_equal(count_entries(dir), 1);
	assert_int_equal(count_entries(sub), 0);
	rmdir(sub);

	/* A success leaves exactly the picture. */
	join(path, sizeof path, dir, "ok.png");
	assert_int_equal(dp_render_png(path, &layer, 1, &p, &err), DP_OK);
	assert_int_equal(count_entries(dir), 1);
	image img = read_png(path);
	assert_int_equal(img.w, 3 * 32);
	free(img.rgb);
	unlink(path);
	dp_cloud_free(&sphere);
	rmdir(dir);
	free(dir);
}

static void expect_refused(const char *path, const dp_render_layer *layers, size_t n,
			   const dp_render_params *p, dp_status status)
{
	dp_error err = { 0 };
	assert_int_equal(dp_render_png(path, layers, n, p, &err), status);
	assert_int_equal(err.status, status);
	assert_non_null(strstr(err.message, path));
	assert_int_equal(access(path, F_OK), -1);
}

static void test_bad_input_refused(void **state)
{
	(void)state;
	char *dir = temp_dir(), path[512];
	join(path, sizeof path, dir, "bad.png");
	dp_cloud pair;
	assert_int_equal(dp_cloud_alloc(&pair, 2, 0, NULL), DP_OK);
	pair.x[0] = pair.y[0] = pair.z[0] = 0.0f;
	pair.x[1] = pair.y[1] = pair.z[1] = 1.0f;
	dp_render_layer layer = layer_of(&pair, red);
	dp_render_params good, p;
	dp_render_params_default(&good);
	good.width = 32;

	const int widths[] = { 0, -4, 100000, INT_MAX };
	for (size_t i = 0; i < sizeof widths / sizeof widths[0]; i++) {
		p = good;
		p.width = widths[i];
		expect_refused(path, &layer, 1, &p, DP_ERR_ARG);
	}
	const int views[] = { 0, -1, 65 };
	for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
		p = good;
		p.views = views[i];
		expect_refused(path, &layer, 1, &p, DP_ERR_ARG);
	}
	p = good;
	p.views = 64;
	p.width = 725;	/* 64 * 725^2 is just above 2^25 pixels */
	expect_refused(path, &layer, 1, &p, DP_ERR_ARG);
	p = good;
	p.up_axis = 3;
	expect_refused(path, &layer, 1, &p, DP_ERR_ARG);
	p = good;
	p.elevation_deg = NAN;
	expect_refused(path, &layer, 1, &p, DP_ERR_ARG);

	dp_render_layer bad = layer;
	bad.point_size_px = -1.0f;
	expect_refused(path, &bad, 1, &good, DP_ERR_ARG);
	const uint32_t out_of_range[2] = { 0, 2 };
	bad = layer;
	bad.edges = out_of_range;
	bad.nedges = 1;
	expect_refused(path, &bad, 1, &good, DP_ERR_ARG);
	bad = layer;
	bad.cloud = NULL;
	expect_refused(path, &bad, 1, &good, DP_ERR_ARG);
	expect_refused(path, NULL, 1, &good, DP_ERR_ARG);

	/* Nothing finite to look at. */
	expect_refused(path, NULL, 0, &good, DP_ERR_EMPTY);
	pair.x[0] = NAN;
	pair.y[1] = INFINITY;
	expect_refused(path, &layer, 1, &good, DP_ERR_EMPTY);

	assert_int_equal(count_entries(dir), 0);
	dp_cloud_free(&pair);
	rmdir(dir);
	free(dir);
}

static void test_non_finite_points_skipped(void **state)
{
	(void)state;
	dp_cloud c;
	assert_int_equal(dp_cloud_alloc(&c, 3, 0, NULL), DP_OK);
	c.x[0] = c.y[0] = c.z[0] = 0.0f;
	c.x[1] = c.y[1] = c.z[1] = 1.0f;
	c.x[2] = NAN, c.y[2] = 0.5f, c.z[2] = 0.5f;
	const uint32_t edges[4] = { 0, 1, 1, 2 };
	dp_render_layer layer = layer_of(&c, blue);
	layer.edges = edges;
	layer.nedges = 2;
	dp_render_params p;
	dp_render_params_default(&p);
	p.width = 48;
	unsigned char *rgb = NULL;
	int w = 0, h = 0;
	assert_int_equal(dp_render_rgb(&layer, 1, &p, &rgb, &w, &h, NULL), DP_OK);
	assert_int_equal(w, 3 * 48);
	assert_int_equal(h, 48);
	size_t drawn = 0;
	for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
		drawn += !same_colour(rgb + 3 * i, white);
	assert_true(drawn > 0);
	free(rgb);
	dp_cloud_free(&c);
}

static void test_colours(void **state)
{
	(void)state;
	unsigned char rgb[3];
	assert_int_equal(dp_parse_colour("#ff8800", rgb, NULL), DP_OK);
	assert_true(rgb[0] == 255 && rgb[1] == 0x88 && rgb[2] == 0);
	assert_int_equal(dp_parse_colour("#F80", rgb, NULL), DP_OK);
	assert_true(rgb[0] == 255 && rgb[1] == 0x88 && rgb[2] == 0);
	assert_int_equal(dp_parse_colour("#0a0B0c", rgb, NULL), DP_OK);
	assert_true(rgb[0] == 10 && rgb[1] == 11 && rgb[2] == 12);

	unsigned char named[3];
	assert_int_equal(dp_parse_colour("red", named, NULL), DP_OK);
	assert_true(dominant(named, 0));
	assert_int_equal(dp_parse_colour("RED", rgb, NULL), DP_OK);
	assert_memory_equal(rgb, named, 3);
	assert_int_equal(dp_parse_colour("Green", rgb, NULL), DP_OK);
	assert_true(dominant(rgb, 1));
	assert_int_equal(dp_parse_colour("blue", rgb, NULL), DP_OK);
	assert_true(rgb[2] > rgb[0] && rgb[2] > rgb[1]);
	assert_int_equal(dp_parse_colour("grey", named, NULL), DP_OK);
	assert_int_equal(dp_parse_colour("gray", rgb, NULL), DP_OK);
	assert_memory_equal(rgb, named, 3);

	const char *bad[] = { "", "#", "#ff88", "#ff88000", "#gg0000", "ff8800", "reddish", "re", "#12345z" };
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		unsigned char keep[3] = { 1, 2, 3 };
		dp_error err = {0};
		assert_int_equal(dp_parse_colour(bad[i], keep, &err), DP_ERR_ARG);
		assert_non_null(strstr(err.message, bad[i]));
		assert_true(keep[0] == 1 && keep[1] == 2 && keep[2] == 3);
	}
	assert_int_equal(dp_parse_colour(NULL, rgb, NULL), DP_ERR_ARG);

	/* Default colours: distinct, and none vanishes on the white background. */
	unsigned char a[3], b[3];
	for (size_t i = 0; i < 8; i++) {
		dp_render_default_colour(i, a);
		assert_true(a[0] < 200 || a[1] < 200 || a[2] < 200);
		for (size_t j = 0; j < i; j++) {
			dp_render_default_colour(j, b);
			assert_true(abs(a[0] - b[0]) + abs(a[1] - b[1]) + abs(a[2] - b[2]) > 60);
		}
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_sphere_views),
		cmocka_unit_test(test_depth_shading_without_normals),
		cmocka_unit_test(test_segment_is_a_thin_line),
		cmocka_unit_test(test_zbuffer_front_wins),
		cmocka_unit_test(test_single_point),
		cmocka_unit_test(test_unwritable_paths_leave_nothing),
		cmocka_unit_test(test_bad_input_refused),
		cmocka_unit_test(test_non_finite_points_skipped),
		cmocka_unit_test(test_colours),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
