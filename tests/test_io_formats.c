/* Files as people have them: gzip-compressed files of every format (each
 * fuzz seed read plain and compressed, from a file and from memory, as one
 * gzip member and as two), XYZ columns detected or named, Leica PTS, colours
 * from PLY, PCD and XYZ, written back to PLY and carried to other points. */
#include "files.h"
#include "testkit.h"

#include "io/io.h"
#include "knn/attributes.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static const char *const formats[] = {"ply", "pcd", "off", "obj", "xyz"};

/* One gzip member of data[0, size) appended to out (out_size updated). */
static void gzip_append(const unsigned char *data, size_t size, unsigned char **out, size_t *out_size)
{
	z_stream z;
	memset(&z, 0, sizeof z);
	assert_int_equal(deflateInit2(&z, 6, Z_DEFLATED, 16 + 15, 8, Z_DEFAULT_STRATEGY), Z_OK);
	size_t bound = deflateBound(&z, (uLong)size) + 64;
	*out = realloc(*out, *out_size + bound);
	assert_non_null(*out);
	z.next_in = (unsigned char *)data;
	z.avail_in = (uInt)size;
	z.next_out = *out + *out_size;
	z.avail_out = (uInt)bound;
	assert_int_equal(deflate(&z, Z_FINISH), Z_STREAM_END);
	*out_size += bound - z.avail_out;
	deflateEnd(&z);
}

static void expect_same_cloud(const dp_cloud *a, const dp_cloud *b, const char *what)
{
	if (a->n != b->n || !a->nx != !b->nx || !a->rgb != !b->rgb || a->nfaces != b->nfaces)
		fail_msg("%s: %zu points (normals %d, colours %d) against %zu (%d, %d)", what, b->n, !!b->nx, !!b->rgb,
			 a->n, !!a->nx, !!a->rgb);
	size_t bytes = a->n * sizeof(float);
	if (memcmp(a->x, b->x, bytes) || memcmp(a->y, b->y, bytes) || memcmp(a->z, b->z, bytes))
		fail_msg("%s: positions differ", what);
	if (a->nx && (memcmp(a->nx, b->nx, bytes) || memcmp(a->nz, b->nz, bytes)))
		fail_msg("%s: normals differ", what);
	if (a->rgb && memcmp(a->rgb, b->rgb, 3 * a->n))
		fail_msg("%s: colours differ", what);
	if (!a->intensity != !b->intensity || (a->intensity && memcmp(a->intensity, b->intensity, bytes)))
		fail_msg("%s: intensities differ", what);
}

/* Every seed of every format, compressed: the same cloud from a file named
 * .gz, from memory, and from two concatenated members. */
static void test_gzip_every_format(void **state)
{
	(void)state;
	const char *dir = tk_temp_dir();
	size_t checked = 0;
	for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
		char seeds[4096];
		snprintf(seeds, sizeof seeds, "%s/tests/fuzz/corpus/%s", getenv("DP_SOURCE_DIR"), formats[f]);
		DIR *d = opendir(seeds);
		assert_non_null(d);
		struct dirent *e;
		while ((e = readdir(d))) {
			if (e->d_name[0] == '.')
				continue;
			char path[8192], name[512];
			snprintf(path, sizeof path, "%s/%s", seeds, e->d_name);
			dp_error err = {0};
			dp_cloud plain = {0}, packed = {0};
			if (dp_cloud_read(path, &plain, DP_READ_POINTS, &err) != DP_OK)
				continue; /* the seeds that fail to read are covered by the fuzz replay */
			size_t size, gz_size = 0, two_size = 0;
			unsigned char *data = tk_read_file(path, &size), *gz = NULL, *two = NULL;
			if (size >= 2 && data[0] == 0x1f && data[1] == 0x8b) {
				/* a compressed seed: one layer of gzip is what is read */
				free(data);
				dp_cloud_free(&plain);
				continue;
			}
			gzip_append(data, size, &gz, &gz_size);
			gzip_append(data, size / 2, &two, &two_size);
			gzip_append(data + size / 2, size - size / 2, &two, &two_size);
			snprintf(name, sizeof name, "%s.gz", e->d_name);
			const char *gz_path = tk_write_file(dir, name, gz, gz_size);
			if (dp_cloud_read(gz_path, &packed, DP_READ_POINTS, &err) != DP_OK)
				fail_msg("%s: %s", gz_path, err.message);
			expect_same_cloud(&plain, &packed, gz_path);
			dp_cloud_free(&packed);
			if (dp_cloud_read_memory(gz, gz_size, name, &packed, DP_READ_POINTS, &err) != DP_OK)
				fail_msg("memory %s: %s", name, err.message);
			expect_same_cloud(&plain, &packed, name);
			dp_cloud_free(&packed);
			if (dp_cloud_read_memory(two, two_size, name, &packed, DP_READ_POINTS, &err) != DP_OK)
				fail_msg("two members %s: %s", name, err.message);
			expect_same_cloud(&plain, &packed, "two gzip members");
			dp_cloud_free(&packed);
			dp_cloud_free(&plain);
			free(data);
			free(gz);
			free(two);
			checked++;
		}
		closedir(d);
	}
	assert_true(checked >= 5);
	tk_remove_dir(dir);
}

static void expect_fail(const void *data, size_t size, const char *name, dp_status want, const char *needle)
{
	dp_error err = {0};
	dp_cloud c = {0};
	dp_status st = dp_cloud_read_memory(data, size, name, &c, DP_READ_POINTS, &err);
	if (st != want || !strstr(err.message, needle) || !strstr(err.message, name))
		fail_msg("%s: status %d (expected %d), message '%s' (expected '%s')", name, st, want, err.message,
			 needle);
	assert_int_equal(c.n, 0);
	assert_null(c.x);
}

static void test_gzip_errors(void **state)
{
	(void)state;
	const char text[] = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n";
	unsigned char *gz = NULL;
	size_t gz_size = 0;
	gzip_append((const unsigned char *)text, sizeof text - 1, &gz, &gz_size);
	expect_fail(gz, gz_size - 6, "cut.xyz.gz", DP_ERR_FORMAT, "truncated");
	unsigned char *bad = malloc(gz_size);
	memcpy(bad, gz, gz_size);
	for (size_t i = 10; i < gz_size - 8; i++)
		bad[i] ^= 0x5a;
	expect_fail(bad, gz_size, "bad.xyz.gz", DP_ERR_FORMAT, "gzip");
	/* the magic alone */
	expect_fail(gz, 2, "magic.xyz.gz", DP_ERR_FORMAT, "truncated");
	free(bad);
	free(gz);
}

static void read_text(const char *name, const char *text, const char *columns, dp_cloud *c)
{
	const char *dir = tk_temp_dir();
	dp_error err = {0};
	const char *path = tk_write_text(dir, name, text);
	if (dp_io_read_cloud(path, NULL, columns, c, DP_READ_POINTS, &err) != DP_OK)
		fail_msg("%s: %s", name, err.message);
	tk_remove_dir(dir);
}

static void read_text_fail(const char *name, const char *text, const char *columns, const char *needle)
{
	const char *dir = tk_temp_dir();
	dp_error err = {0};
	dp_cloud c = {0};
	const char *path = tk_write_text(dir, name, text);
	if (dp_io_read_cloud(path, NULL, columns, &c, DP_READ_POINTS, &err) == DP_OK || !strstr(err.message, needle))
		fail_msg("%s: expected an error with '%s', got '%s'", name, needle, err.message);
	assert_null(c.x);
	tk_remove_dir(dir);
}

static void expect_rgb(const dp_cloud *c, size_t i, int r, int g, int b)
{
	assert_non_null(c->rgb);
	if (c->rgb[3 * i] != r || c->rgb[3 * i + 1] != g || c->rgb[3 * i + 2] != b)
		fail_msg("point %zu: colour %d %d %d, expected %d %d %d", i, c->rgb[3 * i], c->rgb[3 * i + 1],
			 c->rgb[3 * i + 2], r, g, b);
}

static void test_xyz_columns(void **state)
{
	(void)state;
	dp_cloud c = {0};
	read_text("rgb.xyz", "0 0 0 255 0 0\n1 0 0 0 128 0\n0 1 0 1 0 0\n", NULL, &c);
	assert_int_equal(c.n, 3);
	assert_null(c.nx);
	expect_rgb(&c, 0, 255, 0, 0);
	expect_rgb(&c, 1, 0, 128, 0);
	expect_rgb(&c, 2, 1, 0, 0);
	dp_cloud_free(&c);
	read_text("unit.xyz", "0 0 0 0.5 0.2 0.2\n1 0 0 0 0 0.5\n", NULL, &c);
	assert_null(c.nx);
	expect_rgb(&c, 0, 128, 51, 51);
	expect_rgb(&c, 1, 0, 0, 128);
	dp_cloud_free(&c);
	read_text("normals.xyz", "0 0 0 0 0 1\n1 0 0 0.6 -0.8 0\n", NULL, &c);
	assert_non_null(c.nx);
	assert_null(c.rgb);
	assert_float_equal(c.ny[1], -0.8f, 1e-6f);
	dp_cloud_free(&c);
	read_text("nine.xyz", "0 0 0 10 20 30 0 0 1\n1 0 0 40 50 60 0 1 0\n", NULL, &c);
	assert_non_null(c.nx);
	assert_float_equal(c.nz[0], 1.0f, 0.0f);
	expect_rgb(&c, 1, 40, 50, 60);
	dp_cloud_free(&c);
	read_text("named.xyz", "7 0 0 0 9 10 11\n8 0 1 0 12 13 14\n", "_,x,y,z,r,g,b", &c);
	assert_float_equal(c.x[1], 0.0f, 0.0f);
	assert_float_equal(c.y[1], 1.0f, 0.0f);
	expect_rgb(&c, 1, 12, 13, 14);
	dp_cloud_free(&c);
	read_text("swap.xyz", "1 2 3 0 0 1\n", "z,y,x,nx,ny,nz", &c);
	assert_float_equal(c.x[0], 3.0f, 0.0f);
	dp_cloud_free(&c);
	/* unit-length colours read as normals unless named */
	read_text("primaries.xyz", "0 0 0 1 0 0\n1 0 0 0 1 0\n", "x,y,z,r,g,b", &c);
	assert_null(c.nx);
	expect_rgb(&c, 0, 255, 0, 0);
	dp_cloud_free(&c);

	read_text_fail("neither.xyz", "0 0 0 -3 2 7\n1 0 0 4 5 6\n", NULL, "--columns");
	read_text_fail("eleven.xyz", "1 2 3 4 5 6 7 8 9 10 11\n", NULL, "--columns");
	read_text_fail("badname.xyz", "1 2 3\n", "x,y,q", "unknown column 'q'");
	read_text_fail("twice.xyz", "1 2 3\n", "x,y,x", "named twice");
	read_text_fail("noz.xyz", "1 2 3\n", "x,y,_", "x, y and z");
	read_text_fail("halfnormal.xyz", "1 2 3 4 5\n", "x,y,z,nx,ny", "nx, ny, nz");
	read_text_fail("count.xyz", "1 2 3 4\n", "x,y,z", "--columns names 3");
}

/* Past the rows the columns are judged on, rows stream in; a later row that
 * contradicts the judgement is refused rather than read as garbage. */
static void test_xyz_long(void **state)
{
	(void)state;
	size_t rows = 70000, len = 0;
	char *text = malloc(rows * 32 + 64);
	assert_non_null(text);
	for (size_t i = 0; i < rows; i++)
		len += (size_t)sprintf(text + len, "%zu 0 1 %zu 7 200\n", i, i % 256);
	dp_cloud c = {0};
	read_text("long.xyz", text, NULL, &c);
	assert_int_equal(c.n, rows);
	assert_null(c.nx);
	expect_rgb(&c, rows - 1, (int)((rows - 1) % 256), 7, 200);
	assert_float_equal(c.x[rows - 1], (float)(rows - 1), 0.0f);
	dp_cloud_free(&c);
	len += (size_t)sprintf(text + len, "1 2 3 -0.5 0.25 0.5\n");
	read_text_fail("later.xyz", text, NULL, "--columns");
	free(text);
}

static void test_pts(void **state)
{
	(void)state;
	dp_cloud c = {0};
	read_text("scan.pts", "3\n0 0 0 -1200 255 0 0\n1 0 0 20 0 255 0\n0 1 0 5 0 0 255\n", NULL, &c);
	assert_int_equal(c.n, 3);
	assert_null(c.nx);
	expect_rgb(&c, 0, 255, 0, 0);
	expect_rgb(&c, 2, 0, 0, 255);
	assert_non_null(c.intensity);
	assert_float_equal(c.intensity[0], -1200.0f, 0.0f);
	dp_cloud_free(&c);
	/* two scans in one file, each with its count line; intensity only */
	read_text("two.pts", "2\n0 0 0 7\n1 0 0 8\n1\n0 1 0 9\n", NULL, &c);
	assert_int_equal(c.n, 3);
	assert_null(c.rgb);
	assert_float_equal(c.y[2], 1.0f, 0.0f);
	assert_float_equal(c.intensity[2], 9.0f, 0.0f);
	dp_cloud_free(&c);
	read_text_fail("nan.pts", "1\n0 0 0 nan\n", NULL, "intensity");
}

static void test_ply_pcd_colours(void **state)
{
	(void)state;
	dp_cloud c = {0};
	read_text("c.ply",
		  "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
		  "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\nend_header\n"
		  "0 0 0 255 10 0 255\n1 0 0 0 20 200 255\n",
		  NULL, &c);
	expect_rgb(&c, 0, 255, 10, 0);
	expect_rgb(&c, 1, 0, 20, 200);
	dp_cloud_free(&c);
	read_text("f.ply",
		  "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
		  "property float diffuse_red\nproperty float diffuse_green\nproperty float diffuse_blue\nend_header\n"
		  "0 0 0 1 0.5 0\n",
		  NULL, &c);
	expect_rgb(&c, 0, 255, 128, 0);
	dp_cloud_free(&c);
	read_text("i.ply",
		  "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
		  "property float scalar_Intensity\nend_header\n0 0 0 0.25\n1 0 0 12\n",
		  NULL, &c);
	assert_null(c.rgb);
	assert_float_equal(c.intensity[1], 12.0f, 0.0f);
	dp_cloud_free(&c);
	read_text("i.pcd",
		  "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\n"
		  "POINTS 1\nDATA ascii\n1 2 3 77.5\n",
		  NULL, &c);
	assert_float_equal(c.intensity[0], 77.5f, 0.0f);
	dp_cloud_free(&c);
	/* PCL packs rgb into a float's bits */
	uint32_t packed = 0x00ff8001u;
	float as_float;
	memcpy(&as_float, &packed, sizeof as_float);
	char pcd[512];
	snprintf(pcd, sizeof pcd,
		 "VERSION .7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\n"
		 "POINTS 1\nDATA ascii\n1 2 3 %.9g\n",
		 (double)as_float);
	read_text("rgb.pcd", pcd, NULL, &c);
	expect_rgb(&c, 0, 255, 128, 1);
	dp_cloud_free(&c);
	read_text("rgba.pcd",
		  "VERSION .7\nFIELDS x y z rgba\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\n"
		  "POINTS 1\nDATA ascii\n1 2 3 4278255360\n",
		  NULL, &c);
	expect_rgb(&c, 0, 0, 255, 0);
	dp_cloud_free(&c);
	/* binary: x y z then the packed colour */
	const char head[] = "VERSION .7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 1\n"
			    "HEIGHT 1\nPOINTS 1\nDATA binary\n";
	unsigned char bin[sizeof head - 1 + 16];
	float xyz[3] = {1, 2, 3};
	memcpy(bin, head, sizeof head - 1);
	memcpy(bin + sizeof head - 1, xyz, 12);
	unsigned char le[4] = {0x30, 0x20, 0x10, 0};
	memcpy(bin + sizeof head - 1 + 12, le, 4);
	dp_error err = {0};
	assert_int_equal(dp_cloud_read_memory(bin, sizeof bin, "b.pcd", &c, DP_READ_POINTS, &err), DP_OK);
	expect_rgb(&c, 0, 0x10, 0x20, 0x30);
	dp_cloud_free(&c);
}

static void test_write_and_carry(void **state)
{
	(void)state;
	const char *dir = tk_temp_dir();
	dp_error err = {0};
	dp_cloud c = {0}, back = {0}, near = {0};
	assert_int_equal(dp_cloud_alloc(&c, 4, 1, &err), DP_OK);
	c.rgb = malloc(12);
	c.intensity = malloc(4 * sizeof(float));
	for (size_t i = 0; i < 4; i++) {
		c.intensity[i] = 0.5f * (float)i;
		c.x[i] = (float)i;
		c.y[i] = c.z[i] = 0;
		c.nx[i] = c.ny[i] = 0;
		c.nz[i] = 1;
		c.rgb[3 * i] = (unsigned char)(60 * i);
		c.rgb[3 * i + 1] = 7;
		c.rgb[3 * i + 2] = (unsigned char)(250 - i);
	}
	for (int ascii = 0; ascii < 2; ascii++) {
		char path[4096];
		snprintf(path, sizeof path, "%s/c%d.ply", dir, ascii);
		assert_int_equal(dp_cloud_write_ply(path, &c, ascii, &err), DP_OK);
		assert_int_equal(dp_cloud_read(path, &back, DP_READ_POINTS, &err), DP_OK);
		expect_same_cloud(&c, &back, ascii ? "ascii PLY" : "binary PLY");
		dp_cloud_free(&back);
	}
	assert_int_equal(dp_cloud_copy(&back, &c, &err), DP_OK);
	expect_same_cloud(&c, &back, "dp_cloud_copy");
	dp_cloud_free(&back);
	/* points near 2.9 and 0.2 take the colours of points 3 and 0 */
	assert_int_equal(dp_cloud_alloc(&near, 2, 0, &err), DP_OK);
	near.x[0] = 2.9f;
	near.x[1] = 0.2f;
	near.y[0] = near.y[1] = near.z[0] = near.z[1] = 0.1f;
	assert_int_equal(dp_transfer_attributes(&near, &c, &err), DP_OK);
	expect_rgb(&near, 0, 180, 7, 247);
	expect_rgb(&near, 1, 0, 7, 250);
	assert_float_equal(near.intensity[0], 1.5f, 0.0f);
	assert_float_equal(near.intensity[1], 0.0f, 0.0f);
	dp_cloud_free(&near);
	dp_cloud_free(&c);
	tk_remove_dir(dir);
}

static void test_format_override(void **state)
{
	(void)state;
	const char *dir = tk_temp_dir();
	dp_error err = {0};
	dp_cloud c = {0};
	const char *path = tk_write_text(dir, "points.dat", "0 0 0\n1 0 0\n");
	assert_int_equal(dp_io_read_cloud(path, "xyz", NULL, &c, DP_READ_POINTS, &err), DP_OK);
	assert_int_equal(c.n, 2);
	dp_cloud_free(&c);
	assert_int_equal(dp_io_read_cloud(path, "las", NULL, &c, DP_READ_POINTS, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "unknown format 'las'"));
	assert_int_equal(dp_io_read_cloud("-", NULL, NULL, &c, DP_READ_POINTS, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "--format"));
	assert_int_equal(dp_cloud_read(path, &c, DP_READ_POINTS, &err), DP_ERR_FORMAT);
	assert_non_null(strstr(err.message, "--format"));
	path = tk_write_text(dir, "p.ply", "ply\n");
	assert_int_equal(dp_io_read_cloud(path, NULL, "x,y,z", &c, DP_READ_POINTS, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "XYZ"));
	assert_string_equal(dp_io_format_of("a/b.c/scan.PLY.gz"), "ply");
	assert_string_equal(dp_io_format_of("scan.xyz"), "xyz");
	assert_string_equal(dp_io_format_of("scan.gz"), "gz");
	tk_remove_dir(dir);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_gzip_every_format), cmocka_unit_test(test_gzip_errors),
		cmocka_unit_test(test_xyz_columns),	  cmocka_unit_test(test_xyz_long),
		cmocka_unit_test(test_pts),
		cmocka_unit_test(test_ply_pcd_colours),	  cmocka_unit_test(test_write_and_carry),
		cmocka_unit_test(test_format_override),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
