/* Reading every supported format and variant from files written here, with
 * exact values; writing PLY and reading it back. */
#include "files.h"
#include "testkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char dir[64];

static int setup(void **state)
{
	(void)state;
	snprintf(dir, sizeof dir, "%s", tk_temp_dir());
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	tk_remove_dir(dir);
	return 0;
}

static void read_ok(const char *path, int flags, dp_cloud *c)
{
	dp_error err = {0};
	dp_status st = dp_cloud_read(path, c, flags, &err);
	if (st != DP_OK)
		fail_msg("reading %s failed: %s", path, err.message);
}

/* Expected point i: position and (when normals) normal. */
static void expect_point(const dp_cloud *c, size_t i, float x, float y, float z)
{
	assert_true(i < c->n);
	assert_true(c->x[i] == x && c->y[i] == y && c->z[i] == z);
}

static void expect_normal(const dp_cloud *c, size_t i, float nx, float ny, float nz)
{
	assert_non_null(c->nx);
	assert_true(c->nx[i] == nx && c->ny[i] == ny && c->nz[i] == nz);
}

static void expect_faces(const dp_cloud *c, const uint32_t *faces, size_t nfaces)
{
	assert_int_equal(c->nfaces, nfaces);
	assert_non_null(c->faces);
	assert_memory_equal(c->faces, faces, 3 * nfaces * sizeof *faces);
}

/* ------------------------------------------------------------------ PLY */

static const char ply_ascii[] =
	"ply\n"
	"format ascii 1.0\n"
	"comment made by test_io_read\n"
	"obj_info scanner none\n"
	"element vertex 4\n"
	"property float x\n"
	"property float y\n"
	"property float z\n"
	"property uchar red\n"
	"property float nx\n"
	"property float ny\n"
	"property float nz\n"
	"element range_grid 3\n"
	"property list uchar int vertex_indices\n"
	"element face 2\n"
	"property uchar flags\n"
	"property list uchar int vertex_indices\n"
	"end_header\n"
	"0.125 -3.5 2e-3 255 0 0 1\n"
	"1 0 0 128 0.6 0.8 0\n"
	"1 1 0 0 0 -1 0\n"
	"-7.25 1 0.5 7 1 0 0\n"
	"1 0\n"
	"0\n"
	"2 1 2\n"
	"9 4 0 1 2 3\n"
	"0 3 3 2 1\n";

static void test_ply_ascii(void **state)
{
	(void)state;
	const char *path = tk_write_text(dir, "ascii.ply", ply_ascii);
	dp_cloud c;
	read_ok(path, DP_READ_POINTS, &c);
	assert_int_equal(c.n, 4);
	expect_point(&c, 0, 0.125f, -3.5f, 2e-3f);
	expect_point(&c, 1, 1, 0, 0);
	expect_point(&c, 3, -7.25f, 1, 0.5f);
	expect_normal(&c, 0, 0, 0, 1);
	expect_normal(&c, 1, 0.6f, 0.8f, 0);
	expect_normal(&c, 2, 0, -1, 0);
	assert_int_equal(c.nfaces, 0);
	assert_null(c.faces);
	dp_cloud_free(&c);

	read_ok(path, DP_READ_MESH, &c);
	assert_int_equal(c.n, 4);
	const uint32_t faces[] = {0, 1, 2, 0, 2, 3, 3, 2, 1};
	expect_faces(&c, faces, 3);
	dp_cloud_free(&c);
}

static void test_ply_crlf_header(void **state)
{
	(void)state;
	const char text[] = "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty double x\r\n"
			    "property double y\r\nproperty double z\r\nend_header\r\n1 2 3\r\n4 5 6\r\n";
	dp_cloud c;
	read_ok(tk_write_text(dir, "crlf.ply", text), DP_READ_POINTS, &c);
	assert_int_equal(c.n, 2);
	assert_null(c.nx);
	expect_point(&c, 1, 4, 5, 6);
	dp_cloud_free(&c);
}

/* Binary PLY bytes built by the test. */
typedef struct bytes {
	unsigned char d[4096];
	size_t n;
} bytes;

static void put_text(bytes *b, const char *text)
{
	size_t len = strlen(text);
	assert_true(b->n + len <= sizeof b->d);
	memcpy(b->d + b->n, text, len);
	b->n += len;
}

static const struct {
	const char *name;
	int kind; /* 0 signed, 1 unsigned, 2 float */
	size_t size;
} types[] = {
	{"char", 0, 1},    {"int8", 0, 1},     {"uchar", 1, 1},   {"uint8", 1, 1},   {"short", 0, 2},
	{"int16", 0, 2},   {"ushort", 1, 2},   {"uint16", 1, 2},  {"int", 0, 4},     {"int32", 0, 4},
	{"uint", 1, 4},    {"uint32", 1, 4},   {"float", 2, 4},   {"float32", 2, 4}, {"double", 2, 8},
	{"float64", 2, 8},
};

static void put_value(bytes *b, int type, double v, int big)
{
	uint64_t u;
	size_t size = types[type].size;
	if (types[type].kind == 2 && size == 4) {
		float f = (float)v;
		uint32_t bits;
		memcpy(&bits, &f, 4);
		u = bits;
	} else if (types[type].kind == 2) {
		memcpy(&u, &v, 8);
	} else {
		u = (uint64_t)(int64_t)v;
	}
	assert_true(b->n + size <= sizeof b->d);
	for (size_t i = 0; i < size; i++)
		b->d[b->n++] = (unsigned char)(u >> (8 * (big ? size - 1 - i : i)));
}

static int type_index(const char *name)
{
	for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
		if (strcmp(types[i].name, name) == 0)
			return (int)i;
	fail_msg("no type %s", name);
	return -1;
}

/* Every scalar type as x, y, z, in both byte orders, with a skipped property
 * of the same type and a skipped list property in between. */
static void test_ply_binary_types(void **state)
{
	(void)state;
	for (int big = 0; big < 2; big++) {
		for (int t = 0; t < (int)(sizeof types / sizeof types[0]); t++) {
			double v[2][3];
			if (types[t].kind == 0) {
				double s[2][3] = {{-7, 100, 3}, {5, -1, 0}};
				memcpy(v, s, sizeof v);
			} else if (types[t].kind == 1) {
				double s[2][3] = {{7, 100, 3}, {5, 255, 0}};
				memcpy(v, s, sizeof v);
			} else {
				double s[2][3] = {{1.5, -2.25, 1e-3}, {-1e10, 0.1, 3.0 / 7.0}};
				memcpy(v, s, sizeof v);
			}
			bytes b = {.n = 0};
			char header[512];
			snprintf(header, sizeof header,
				 "ply\nformat binary_%s_endian 1.0\nelement vertex 2\nproperty %s x\nproperty %s junk\n"
				 "property list uint8 float32 extra\nproperty %s y\nproperty %s z\nend_header\n",
				 big ? "big" : "little", types[t].name, types[t].name, types[t].name, types[t].name);
			put_text(&b, header);
			for (int i = 0; i < 2; i++) {
				put_value(&b, t, v[i][0], big);
				put_value(&b, t, 42, big);
				put_value(&b, type_index("uchar"), 2, big);
				put_value(&b, type_index("float"), 9.5, big);
				put_value(&b, type_index("float"), -9.5, big);
				put_value(&b, t, v[i][1], big);
				put_value(&b, t, v[i][2], big);
			}
			dp_cloud c;
			read_ok(tk_write_file(dir, "types.ply", b.d, b.n), DP_READ_POINTS, &c);
			assert_int_equal(c.n, 2);
			for (int i = 0; i < 2; i++) {
				/* A float32 property holds the float nearest the value. */
				float e[3];
				for (int k = 0; k < 3; k++)
					e[k] = (float)v[i][k];
				if (c.x[i] != e[0] || c.y[i] != e[1] || c.z[i] != e[2])
					fail_msg("type %s %s-endian point %d: %g %g %g", types[t].name, big ? "big" : "little",
						 i, (double)c.x[i], (double)c.y[i], (double)c.z[i]);
			}
			dp_cloud_free(&c);
		}
	}
}

/* Doubles with normals (as hippo1.ply), an extra list element (as bun000's
 * range_grid) and faces with uint8/uint32 lists, big endian. */
static void test_ply_binary_mesh(void **state)
{
	(void)state;
	int d = type_index("double"), u8 = type_index("uint8"), i32 = type_index("int"), u32 = type_index("uint32");
	for (int big = 0; big < 2; big++) {
		bytes b = {.n = 0};
		char header[512];
		snprintf(header, sizeof header,
			 "ply\nformat binary_%s_endian 1.0\ncomment x\nelement vertex 4\nproperty double x\n"
			 "property double y\nproperty double z\nproperty double nx\nproperty double ny\n"
			 "property double nz\nelement range_grid 3\nproperty list uchar int vertex_indices\n"
			 "element face 2\nproperty list uint8 uint32 vertex_index\nend_header\n",
			 big ? "big" : "little");
		put_text(&b, header);
		const double p[4][6] = {{0.1, 0.2, 0.3, 0, 0, 1}, {1, 0, 0, 0, 1, 0},
					{1, 1, 0, 1, 0, 0}, {0, 1, 1e-30, -1, 0, 0}};
		for (int i = 0; i < 4; i++)
			for (int k = 0; k < 6; k++)
				put_value(&b, d, p[i][k], big);
		const int grid[3][3] = {{1, 3, 0}, {0, 0, 0}, {2, 1, 2}};
		for (int r = 0; r < 3; r++) {
			put_value(&b, u8, grid[r][0], big);
			for (int k = 0; k < grid[r][0]; k++)
				put_value(&b, i32, grid[r][1 + k], big);
		}
		put_value(&b, u8, 4, big);
		for (int k = 0; k < 4; k++)
			put_value(&b, u32, k, big);
		put_value(&b, u8, 3, big);
		put_value(&b, u32, 3, big);
		put_value(&b, u32, 1, big);
		put_value(&b, u32, 2, big);
		const char *path = tk_write_file(dir, "mesh.ply", b.d, b.n);
		dp_cloud c;
		read_ok(path, DP_READ_MESH, &c);
		assert_int_equal(c.n, 4);
		for (int i = 0; i < 4; i++) {
			expect_point(&c, i, (float)p[i][0], (float)p[i][1], (float)p[i][2]);
			expect_normal(&c, i, (float)p[i][3], (float)p[i][4], (float)p[i][5]);
		}
		const uint32_t faces[] = {0, 1, 2, 0, 2, 3, 3, 1, 2};
		expect_faces(&c, faces, 3);
		dp_cloud_free(&c);
		read_ok(path, DP_READ_POINTS, &c);
		assert_int_equal(c.n, 4);
		assert_int_equal(c.nfaces, 0);
		dp_cloud_free(&c);
	}
}

/* ------------------------------------------------------------------ XYZ */

static void test_xyz(void **state)
{
	(void)state;
	const char three[] = "# a comment\n\n0.5 -1 2 # trailing comment\r\n\t3e2  4 -5.25\n   \n1e-3 0 7";
	const char *names[] = {"three.xyz", "THREE.XYZ", "three.txt", "three.pts", "three.Xyz"};
	for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
		dp_cloud c;
		read_ok(tk_write_text(dir, names[k], three), DP_READ_MESH, &c);
		assert_int_equal(c.n, 3);
		assert_null(c.nx);
		assert_null(c.faces);
		expect_point(&c, 0, 0.5f, -1, 2);
		expect_point(&c, 1, 300, 4, -5.25f);
		expect_point(&c, 2, 1e-3f, 0, 7);
		dp_cloud_free(&c);
	}
	const char six[] = "1 2 3 0 0 1\n4 5 6 0.6 -0.8 0\n";
	dp_cloud c;
	read_ok(tk_write_text(dir, "six.xyz", six), DP_READ_POINTS, &c);
	assert_int_equal(c.n, 2);
	expect_point(&c, 1, 4, 5, 6);
	expect_normal(&c, 0, 0, 0, 1);
	expect_normal(&c, 1, 0.6f, -0.8f, 0);
	dp_cloud_free(&c);
}

/* ------------------------------------------------------------------ PCD */

static void test_pcd_ascii(void **state)
{
	(void)state;
	const char text[] =
		"# .PCD v0.7 - Point Cloud Data file format\n"
		"VERSION 0.7\n"
		"FIELDS x y z rgb normal_x normal_y normal_z curvature hist\n"
		"SIZE 4 4 4 4 4 4 4 4 4\n"
		"TYPE F F F F F F F F F\n"
		"COUNT 1 1 1 1 1 1 1 1 3\n"
		"WIDTH 2\n"
		"HEIGHT 2\n"
		"VIEWPOINT 0 0 0 1 0 0 0\n"
		"POINTS 4\n"
		"DATA ascii\n"
		"1 2 3 4.2e-38 0 0 1 0.5 1 2 3\n"
		"nan nan nan 0 nan nan nan 0 0 0 0\n"
		"-1.5 0.25 8 0 0 1 0 0 0 0 0\n"
		"4 5 6 0 nan nan nan 0 0 0 0\n";
	dp_cloud c;
	read_ok(tk_write_text(dir, "organised.pcd", text), DP_READ_POINTS, &c);
	/* The NaN position is a "no return" and is dropped; the NaN normal of a
	 * real point becomes the zero "unknown" normal. */
	assert_int_equal(c.n, 3);
	expect_point(&c, 0, 1, 2, 3);
	expect_point(&c, 1, -1.5f, 0.25f, 8);
	expect_point(&c, 2, 4, 5, 6);
	expect_normal(&c, 0, 0, 0, 1);
	expect_normal(&c, 1, 0, 1, 0);
	expect_normal(&c, 2, 0, 0, 0);
	dp_cloud_free(&c);

	const char plain[] = "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA ascii\n1 2 3\n4 5 6\n";
	read_ok(tk_write_text(dir, "plain.PCD", plain), DP_READ_POINTS, &c);
	assert_int_equal(c.n, 2);
	assert_null(c.nx);
	expect_point(&c, 1, 4, 5, 6);
	dp_cloud_free(&c);
}

static void test_pcd_binary(void **state)
{
	(void)state;
	bytes b = {.n = 0};
	put_text(&b, "# binary\nVERSION 0.7\nFIELDS intensity x y z normal_x normal_y normal_z ring\n"
		     "SIZE 2 4 4 8 4 4 4 1\nTYPE U F F F F F F I\nCOUNT 1 1 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
		     "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA binary\n");
	int u16 = type_index("ushort"), f32 = type_index("float"), f64 = type_index("double"), i8 = type_index("char");
	const double p[3][6] = {{0.5, -2, 1e-7, 0, 0, 1}, {NAN, 1, 2, 0, 1, 0}, {3, 4, 5, 1, 0, 0}};
	for (int i = 0; i < 3; i++) {
		put_value(&b, u16, 1000 + i, 0);
		put_value(&b, f32, p[i][0], 0);
		put_value(&b, f32, p[i][1], 0);
		put_value(&b, f64, p[i][2], 0);
		for (int k = 3; k < 6; k++)
			put_value(&b, f32, p[i][k], 0);
		put_value(&b, i8, -3, 0);
	}
	dp_cloud c;
	read_ok(tk_write_file(dir, "binary.pcd", b.d, b.n), DP_READ_POINTS, &c);
	assert_int_equal(c.n, 2);
	expect_point(&c, 0, 0.5f, -2, 1e-7f);
	expect_normal(&c, 0, 0, 0, 1);
	expect_point(&c, 1, 3, 4, 5);
	expect_normal(&c, 1, 1, 0, 0);
	dp_cloud_free(&c);
}

/* ------------------------------------------------------------------ OFF */

static void test_off_variants(void **state)
{
	(void)state;
	dp_cloud c;
	const char off[] = "OFF\n# comment\n\n4 2 0\n0 0 0\n1.5 0 0\n1 1 0\n0 1 -2\n4 0 1 2 3\n3 0 2 3\n";
	read_ok(tk_write_text(dir, "quad.off", off), DP_READ_MESH, &c);
	assert_int_equal(c.n, 4);
	assert_null(c.nx);
	expect_point(&c, 1, 1.5f, 0, 0);
	expect_point(&c, 3, 0, 1, -2);
	const uint32_t faces[] = {0, 1, 2, 0, 2, 3, 0, 2, 3};
	expect_faces(&c, faces, 3);
	dp_cloud_free(&c);
	read_ok(tk_write_text(dir, "quad.OFF", off), DP_READ_POINTS, &c);
	assert_int_equal(c.n, 4);
	assert_int_equal(c.nfaces, 0);
	dp_cloud_free(&c);

	/* Counts on the keyword line, two numbers, trailing spaces. */
	const char same_line[] = "OFF 3 1   \n1 2 3\n4 5 6\n7 8 9\n3 2 1 0\n\n";
	read_ok(tk_write_text(dir, "same.off", same_line), DP_READ_MESH, &c);
	assert_int_equal(c.n, 3);
	expect_point(&c, 2, 7, 8, 9);
	const uint32_t tri[] = {2, 1, 0};
	expect_faces(&c, tri, 1);
	dp_cloud_free(&c);

	/* Counts glued to the keyword, as in ModelNet. */
	const char glued[] = "OFF3 1 0\n1 2 3\n4 5 6\n7 8 9\n3 0 1 2\n";
	read_ok(tk_write_text(dir, "glued.off", glued), DP_READ_MESH, &c);
	assert_int_equal(c.n, 3);
	assert_int_equal(c.nfaces, 1);
	dp_cloud_free(&c);

	const char noff[] = "NOFF\n2 0\n1 2 3 0 0 1\n4 5 6 0.6 0.8 0\n";
	read_ok(tk_write_text(dir, "normals.off", noff), DP_READ_POINTS, &c);
	assert_int_equal(c.n, 2);
	expect_point(&c, 1, 4, 5, 6);
	expect_normal(&c, 0, 0, 0, 1);
	expect_normal(&c, 1, 0.6f, 0.8f, 0);
	dp_cloud_free(&c);

	const char coff[] = "COFF\n3 1 0\n1 2 3 255 0 0 255\n4 5 6 0 255 0 255\n7 8 9 0 0 255 255\n3 0 1 2 1 0 0\n";
	read_ok(tk_write_text(dir, "colour.off", coff), DP_READ_MESH, &c);
	assert_int_equal(c.n, 3);
	assert_null(c.nx);
	expect_point(&c, 2, 7, 8, 9);
	const uint32_t tri2[] = {0, 1, 2};
	expect_faces(&c, tri2, 1);
	dp_cloud_free(&c);
}

/* ------------------------------------------------------------------ OBJ */

static void test_obj(void **state)
{
	(void)state;
	const char obj[] =
		"# comment\n"
		"mtllib x.mtl\n"
		"o thing\n"
		"v 0 0 0\n"
		"v 1.5 0 0 1.0\n"
		"v 1 1 0 0.5 0.5 0.5\n"
		"vn 0 0 1\n"
		"vt 0 0\n"
		"v\t0 1 -2\n"
		"g group\n"
		"usemtl m\n"
		"s off\n"
		"f 1 2 3\n"
		"f 1/1 3/1 4/1\n"
		"f 1//1 2//1 3//1 4//1\n"
		"f -4/1/1 -3/1/1 -2/1/1\n"
		"l 1 2\n";
	dp_cloud c;
	const char *path = tk_write_text(dir, "thing.obj", obj);
	read_ok(path, DP_READ_MESH, &c);
	assert_int_equal(c.n, 4);
	assert_null(c.nx);
	expect_point(&c, 1, 1.5f, 0, 0);
	expect_point(&c, 3, 0, 1, -2);
	const uint32_t faces[] = {0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3, 0, 1, 2};
	expect_faces(&c, faces, 5);
	dp_cloud_free(&c);
	read_ok(path, DP_READ_POINTS, &c);
	assert_int_equal(c.n, 4);
	assert_null(c.faces);
	dp_cloud_free(&c);
}

/* ----------------------------------------------------------- round trips */

static void random_cloud(dp_cloud *c, size_t n, int normals, size_t nfaces, uint64_t seed)
{
	dp_rng rng;
	dp_error err = {0};
	dp_rng_seed(&rng, seed);
	assert_int_equal(dp_cloud_alloc(c, n, normals, &err), DP_OK);
	for (size_t i = 0; i < n; i++) {
		/* Wide exponents and signs, so text round trips need every digit. */
		c->x[i] = (float)(dp_rng_normal(&rng) * pow(10.0, 6 * dp_rng_uniform(&rng) - 3));
		c->y[i] = (float)dp_rng_normal(&rng);
		c->z[i] = (float)(dp_rng_uniform(&rng) * 1e5);
		if (normals) {
			c->nx[i] = (float)dp_rng_normal(&rng);
			c->ny[i] = (float)dp_rng_normal(&rng);
			c->nz[i] = (float)dp_rng_normal(&rng);
		}
	}
	if (nfaces) {
		c->faces = malloc(3 * nfaces * sizeof *c->faces);
		assert_non_null(c->faces);
		for (size_t i = 0; i < 3 * nfaces; i++)
			c->faces[i] = (uint32_t)(dp_rng_next(&rng) % n);
		c->nfaces = nfaces;
	}
}

static void assert_same_cloud(const dp_cloud *a, const dp_cloud *b)
{
	assert_int_equal(a->n, b->n);
	size_t bytes = a->n * sizeof(float);
	assert_memory_equal(a->x, b->x, bytes);
	assert_memory_equal(a->y, b->y, bytes);
	assert_memory_equal(a->z, b->z, bytes);
	assert_int_equal(a->nx != NULL, b->nx != NULL);
	if (a->nx) {
		assert_memory_equal(a->nx, b->nx, bytes);
		assert_memory_equal(a->ny, b->ny, bytes);
		assert_memory_equal(a->nz, b->nz, bytes);
	}
	assert_int_equal(a->nfaces, b->nfaces);
	if (a->nfaces)
		assert_memory_equal(a->faces, b->faces, 3 * a->nfaces * sizeof(uint32_t));
}

static void test_round_trip(void **state)
{
	(void)state;
	char path[256];
	for (int ascii = 0; ascii < 2; ascii++) {
		for (int normals = 0; normals < 2; normals++) {
			dp_cloud out, in;
			dp_error err = {0};
			random_cloud(&out, 1000 + 17 * (size_t)normals, normals, normals ? 300 : 0, 7 + (uint64_t)ascii);
			snprintf(path, sizeof path, "%s/round_%d_%d.ply", dir, ascii, normals);
			assert_int_equal(dp_cloud_write_ply(path, &out, ascii, &err), DP_OK);
			read_ok(path, DP_READ_MESH, &in);
			assert_same_cloud(&out, &in);
			dp_cloud_free(&in);
			/* Writing over an existing file replaces it. */
			out.n = 10;
			out.nfaces = 0;
			assert_int_equal(dp_cloud_write_ply(path, &out, ascii, &err), DP_OK);
			read_ok(path, DP_READ_MESH, &in);
			assert_same_cloud(&out, &in);
			dp_cloud_free(&in);
			dp_cloud_free(&out);
		}
	}
}

/* Edges: the header MeshLab and CloudCompare expect, little-endian int pairs
 * after the vertices, and readers skip the element. */
static void test_write_edges(void **state)
{
	(void)state;
	const float x[] = {0, 1, 2}, y[] = {3, 4, 5}, z[] = {6, 7, 8}, r[] = {0.5f, 0.25f, 1};
	const dp_ply_property props[] = {{"x", x}, {"y", y}, {"z", z}, {"radius", r}};
	const uint32_t edges[] = {0, 1, 1, 2};
	char path[256];
	for (int ascii = 0; ascii < 2; ascii++) {
		dp_error err = {0};
		snprintf(path, sizeof path, "%s/edges_%d.ply", dir, ascii);
		assert_int_equal(dp_ply_write(path, 3, props, 4, edges, 2, NULL, 0, ascii, &err), DP_OK);
		FILE *f = fopen(path, "rb");
		assert_non_null(f);
		char data[1024];
		size_t len = fread(data, 1, sizeof data - 1, f);
		fclose(f);
		data[len] = '\0';
		const char *expected_header =
			ascii ? "ply\nformat ascii 1.0\n" : "ply\nformat binary_little_endian 1.0\n";
		assert_memory_equal(data, expected_header, strlen(expected_header));
		assert_non_null(strstr(data, "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
					     "property float radius\nelement edge 2\nproperty int vertex1\n"
					     "property int vertex2\nend_header\n"));
		const char *body = strstr(data, "end_header\n") + strlen("end_header\n");
		if (ascii) {
			assert_string_equal(body, "0 3 6 0.5\n1 4 7 0.25\n2 5 8 1\n0 1\n1 2\n");
		} else {
			size_t at = (size_t)(body - data);
			assert_int_equal(len, at + 3 * 4 * 4 + 2 * 2 * 4);
			const unsigned char *e = (const unsigned char *)body + 3 * 4 * 4;
			const unsigned char expected_edges[] = {0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0};
			assert_memory_equal(e, expected_edges, sizeof expected_edges);
			const unsigned char *radius = (const unsigned char *)body + 16 + 12;
			uint32_t bits = radius[0] | radius[1] << 8 | radius[2] << 16 | (uint32_t)radius[3] << 24;
			float second_radius;
			memcpy(&second_radius, &bits, sizeof bits);
			assert_true(second_radius == 0.25f);
		}
		dp_cloud c;
		read_ok(path, DP_READ_MESH, &c);
		assert_int_equal(c.n, 3);
		expect_point(&c, 2, 2, 5, 8);
		assert_int_equal(c.nfaces, 0);
		dp_cloud_free(&c);
		uint32_t *back;
		size_t nback;
		assert_int_equal(dp_ply_read_edges(path, &back, &nback, &err), DP_OK);
		assert_int_equal(nback, 2);
		assert_memory_equal(back, edges, sizeof edges);
		free(back);
	}
	/* No edge element, or not a PLY file: no edges and no error. */
	uint32_t *none = (uint32_t *)x;
	size_t nnone = 99;
	dp_error err = {0};
	const char *plain = tk_write_text(dir, "no_edges.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
				     "property float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n");
	assert_int_equal(dp_ply_read_edges(plain, &none, &nnone, &err), DP_OK);
	assert_null(none);
	assert_int_equal(nnone, 0);
	none = (uint32_t *)x;
	assert_int_equal(dp_ply_read_edges(tk_write_text(dir, "edges.xyz", "1 2 3\n"), &none, &nnone, &err), DP_OK);
	assert_null(none);
	assert_int_equal(nnone, 0);
	/* Ascii edges of another integer type, in a file with faces too. */
	const char *mixed = tk_write_text(dir, "mixed_edges.ply",
					  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
					  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
					  "element edge 3\nproperty uchar vertex2\nproperty float weight\nproperty ushort vertex1\n"
					  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n1 0.5 0\n2 0.5 1\n0 0.5 2\n");
	uint32_t *mixed_edges;
	assert_int_equal(dp_ply_read_edges(mixed, &mixed_edges, &nnone, &err), DP_OK);
	const uint32_t expected_mixed[] = {0, 1, 1, 2, 2, 0};
	assert_int_equal(nnone, 3);
	assert_memory_equal(mixed_edges, expected_mixed, sizeof expected_mixed);
	free(mixed_edges);
	/* Every write renamed its temporary file away. */
	assert_true(tk_count_files(dir, "edges_") == 2);
	assert_int_equal(tk_count_files(dir, ".tmp."), 0);
}

/* ----------------------------------------------------------- large files */

/* 500K points of ascii round-trip exactly; the read times are printed, not
 * asserted (timings belong in bench/). */
#define PERF_POINTS 500000

static void test_large_ascii(void **state)
{
	(void)state;
	dp_cloud out, in;
	dp_error err = {0};
	char path[256];
	random_cloud(&out, PERF_POINTS, 1, 0, 99);
	snprintf(path, sizeof path, "%s/large.ply", dir);
	assert_int_equal(dp_cloud_write_ply(path, &out, 1, &err), DP_OK);
	double t0 = dp_seconds();
	read_ok(path, DP_READ_POINTS, &in);
	double ply_seconds = dp_seconds() - t0;
	assert_same_cloud(&out, &in);
	dp_cloud_free(&in);

	snprintf(path, sizeof path, "%s/large.xyz", dir);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	for (size_t i = 0; i < out.n; i++)
		fprintf(f, "%.9g %.9g %.9g\n", (double)out.x[i], (double)out.y[i], (double)out.z[i]);
	assert_int_equal(fclose(f), 0);
	t0 = dp_seconds();
	read_ok(path, DP_READ_POINTS, &in);
	double xyz_seconds = dp_seconds() - t0;
	assert_int_equal(in.n, out.n);
	assert_memory_equal(in.x, out.x, out.n * sizeof(float));
	assert_memory_equal(in.z, out.z, out.n * sizeof(float));
	dp_cloud_free(&in);
	dp_cloud_free(&out);
	printf("ascii read of %d points: PLY with normals %.3f s, XYZ %.3f s\n", PERF_POINTS, ply_seconds,
	       xyz_seconds);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_ply_ascii),
		cmocka_unit_test(test_ply_crlf_header),
		cmocka_unit_test(test_ply_binary_types),
		cmocka_unit_test(test_ply_binary_mesh),
		cmocka_unit_test(test_xyz),
		cmocka_unit_test(test_pcd_ascii),
		cmocka_unit_test(test_pcd_binary),
		cmocka_unit_test(test_off_variants),
		cmocka_unit_test(test_obj),
		cmocka_unit_test(test_round_trip),
		cmocka_unit_test(test_write_edges),
		cmocka_unit_test(test_large_ascii),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
