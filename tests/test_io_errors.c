/* Bad input: every case gets its status, one line naming the file, a zeroed
 * cloud, and no crash (random and mutated files); failed writes leave no
 * partial file. */
#include "files.h"
#include "testkit.h"

#include "io/io.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

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

static int is_zeroed(const dp_cloud *c)
{
	static const dp_cloud zero;
	return memcmp(c, &zero, sizeof zero) == 0;
}

/* Reads `path` expecting `status` and a message naming the file that holds
 * `needle` (when not NULL). */
static void expect_fail_at(const char *path, int flags, dp_status status, const char *needle, int line)
{
	dp_cloud c;
	dp_error err = {0};
	memset(&c, 0xab, sizeof c);
	dp_status st = dp_cloud_read(path, &c, flags, &err);
	if (st != status || err.status != status)
		fail_msg("line %d: %s: expected status %d (%s), got %d: %s", line, path, status, dp_status_string(status),
			 st, err.message);
	if (!strstr(err.message, path))
		fail_msg("line %d: message does not name the file: %s", line, err.message);
	if (strncmp(err.message, path, strlen(path)) != 0 || err.message[strlen(path)] != ':')
		fail_msg("line %d: message does not start with '<path>:': %s", line, err.message);
	if (strchr(err.message, '\n'))
		fail_msg("line %d: message has more than one line: %s", line, err.message);
	if (needle && !strstr(err.message, needle))
		fail_msg("line %d: message lacks '%s': %s", line, needle, err.message);
	if (!is_zeroed(&c))
		fail_msg("line %d: the cloud is not zeroed after an error", line);
}

#define expect_fail(path, flags, status, needle) expect_fail_at(path, flags, status, needle, __LINE__)

/* Writes text to dir/name and expects reading it to fail. */
#define expect_text_fail(name, text, flags, status, needle) \
	expect_fail(tk_write_text(dir, name, text), flags, status, needle)

static const char *const extensions[] = {"ply", "xyz", "txt", "pts", "pcd", "off", "obj"};
#define NEXT (sizeof extensions / sizeof extensions[0])

static void test_missing_and_unknown(void **state)
{
	(void)state;
	char path[256];
	snprintf(path, sizeof path, "%s/nothere.ply", dir);
	expect_fail(path, DP_READ_POINTS, DP_ERR_IO, strerror(ENOENT));
	snprintf(path, sizeof path, "%s/folder.xyz", dir);
	assert_int_equal(mkdir(path, 0700), 0);
	expect_fail(path, DP_READ_POINTS, DP_ERR_IO, NULL);
	assert_int_equal(rmdir(path), 0);

	expect_text_fail("points.foo", "1 2 3\n", DP_READ_POINTS, DP_ERR_FORMAT, "unknown");
	expect_text_fail("points", "1 2 3\n", DP_READ_POINTS, DP_ERR_FORMAT, "unknown");
	expect_text_fail(".xyz", "1 2 3\n", DP_READ_POINTS, DP_ERR_FORMAT, "unknown");
	snprintf(path, sizeof path, "%s/v1.ply", dir);
	assert_int_equal(mkdir(path, 0700), 0);
	expect_text_fail("v1.ply/points", "1 2 3\n", DP_READ_POINTS, DP_ERR_FORMAT, "unknown");

	dp_error err = {0};
	assert_int_equal(dp_cloud_read(path, NULL, 0, &err), DP_ERR_ARG);
	dp_cloud c;
	assert_int_equal(dp_cloud_read(NULL, &c, 0, &err), DP_ERR_ARG);
	assert_true(is_zeroed(&c));
	assert_int_equal(dp_cloud_read(path, &c, 0x10, &err), DP_ERR_ARG);
	assert_true(is_zeroed(&c));
}

static void test_empty(void **state)
{
	(void)state;
	char name[32];
	for (size_t e = 0; e < NEXT; e++) {
		snprintf(name, sizeof name, "empty.%s", extensions[e]);
		expect_text_fail(name, "", DP_READ_MESH, DP_ERR_EMPTY, "empty");
	}
	expect_text_fail("none.ply",
			 "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
			 "property float z\nend_header\n",
			 DP_READ_POINTS, DP_ERR_EMPTY, "no points");
	expect_text_fail("none.xyz", "# only a comment\n\n   \n", DP_READ_POINTS, DP_ERR_EMPTY, "no points");
	expect_text_fail("none.off", "OFF\n0 0 0\n", DP_READ_MESH, DP_ERR_EMPTY, "no points");
	expect_text_fail("none.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 0\nDATA ascii\n", DP_READ_POINTS,
			 DP_ERR_EMPTY, "no points");
	expect_text_fail("nan.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA ascii\nnan 0 0\n0 nan 0\n",
			 DP_READ_POINTS, DP_ERR_EMPTY, "no points");
	expect_text_fail("none.obj", "# nothing\ng x\nvn 0 0 1\n", DP_READ_MESH, DP_ERR_EMPTY, "no points");
	expect_text_fail("comment.off", "# just a comment\n", DP_READ_MESH, DP_ERR_EMPTY, NULL);
}

#define PLY_XYZ_HEADER(format, count) \
	"ply\nformat " format " 1.0\nelement vertex " count "\nproperty float x\nproperty float y\n" \
	"property float z\nend_header\n"

static void test_truncated(void **state)
{
	(void)state;
	/* Rows long enough that the count fits the size: the end comes first. */
	expect_text_fail("short.ply", PLY_XYZ_HEADER("ascii", "5") "1.000000 2.000000 3.000000\n"
				      "1.000000 2.000000 3.000000\n1.000000 2.000000 3.000000\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "truncated");
	expect_text_fail("short_row.ply", PLY_XYZ_HEADER("ascii", "2") "1.000000 2.000000 3.000000\n"
					  "1.000000 2.000000\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "truncated");
	/* A list element cut short, after complete vertices. */
	unsigned char bin[512];
	const char head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
			    "property float y\nproperty float z\nelement range_grid 2\n"
			    "property list uchar int vertex_indices\nend_header\n";
	size_t n = strlen(head);
	memcpy(bin, head, n);
	memset(bin + n, 0, 12);
	n += 12;
	bin[n++] = 50; /* a list of 50 ints, of which only 2 follow */
	memset(bin + n, 0, 8);
	n += 8;
	bin[n++] = 0;
	expect_fail(tk_write_file(dir, "short_list.ply", bin, n), DP_READ_POINTS, DP_ERR_FORMAT, "truncated");

	expect_text_fail("short.off", "OFF\n3 1 0\n1.000000 2.000000 3.000000\n4.000000 5.000000 6.000000\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "truncated");
	expect_text_fail("short_faces.off", "OFF\n3 2 0\n1 2 3\n4 5 6\n7 8 9\n3 0 1 2\n", DP_READ_MESH, DP_ERR_FORMAT,
			 "truncated");
	expect_text_fail("short.pcd",
			 "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 3\nDATA ascii\n1.000000 2.000000 3.000000\n"
			 "1.000000 2.000000 3.000000\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "truncated");
	expect_text_fail("short_line.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA ascii\n1.000000 2.000000 3.000000\n1 2\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "fewer values");
}

/* Counts no file of this size could hold are refused before any allocation:
 * 10^15 points would fail with DP_ERR_NOMEM if the reader tried, and 5·10^7
 * (an allocation that would succeed) must be refused by the size check, not
 * found truncated after allocating. */
static void test_lying_counts(void **state)
{
	(void)state;
	const char *counts[] = {"1000000000000000", "50000000"};
	char text[1024], name[64];
	for (int k = 0; k < 2; k++) {
		const char *formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
		for (int f = 0; f < 3; f++) {
			snprintf(text, sizeof text,
				 "ply\nformat %s 1.0\nelement vertex %s\nproperty float x\nproperty float y\n"
				 "property float z\nend_header\n1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18\n",
				 formats[f], counts[k]);
			snprintf(name, sizeof name, "lie%d_%d.ply", k, f);
			expect_text_fail(name, text, DP_READ_POINTS, DP_ERR_FORMAT, "bytes follow");
		}
		snprintf(text, sizeof text, "OFF\n%s 0 0\n1 2 3\n4 5 6\n", counts[k]);
		snprintf(name, sizeof name, "lie%d.off", k);
		expect_text_fail(name, text, DP_READ_POINTS, DP_ERR_FORMAT, "bytes follow");
		snprintf(text, sizeof text, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS %s\nDATA binary\n0123456789ab",
			 counts[k]);
		snprintf(name, sizeof name, "lie%d.pcd", k);
		expect_text_fail(name, text, DP_READ_POINTS, DP_ERR_FORMAT, "bytes follow");
		snprintf(text, sizeof text, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH %s\nDATA ascii\n1 2 3\n", counts[k]);
		snprintf(name, sizeof name, "lie%d_ascii.pcd", k);
		expect_text_fail(name, text, DP_READ_POINTS, DP_ERR_FORMAT, "bytes follow");
	}
	/* A list element whose rows cannot fit either. */
	expect_text_fail("lie_list.ply",
			 "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
			 "property float z\nelement face 99999999999\nproperty list uchar int vertex_indices\n"
			 "end_header\n0123456789ab\3",
			 DP_READ_MESH, DP_ERR_FORMAT, "bytes follow");
	/* Counts smaller than the data: the header lies the other way. */
	expect_text_fail("more.ply", PLY_XYZ_HEADER("ascii", "1") "1 2 3\n4 5 6\n", DP_READ_POINTS, DP_ERR_FORMAT,
			 "continues");
	expect_text_fail("more_bin.ply", PLY_XYZ_HEADER("binary_little_endian", "1") "0123456789abXYZ",
			 DP_READ_POINTS, DP_ERR_FORMAT, "continues");
	expect_text_fail("more.off", "OFF\n2 0 0\n1 2 3\n4 5 6\n7 8 9\n", DP_READ_POINTS, DP_ERR_FORMAT, "continues");
	expect_text_fail("more.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n4 5 6\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "continues");
	expect_text_fail("more_bin.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA binary\n0123456789abX",
			 DP_READ_POINTS, DP_ERR_FORMAT, "continues");
}

static void test_non_finite(void **state)
{
	(void)state;
	expect_text_fail("nan.xyz", "1 2 3\n4 5 6\nnan 0 0\n", DP_READ_POINTS, DP_ERR_FORMAT, "point 2 ");
	expect_text_fail("inf.xyz", "1 2 3\n4 5 -inf\n", DP_READ_POINTS, DP_ERR_FORMAT, "point 1 ");
	expect_text_fail("huge.xyz", "1 2 3\n4 1e39 6\n", DP_READ_POINTS, DP_ERR_FORMAT, "point 1 ");
	expect_text_fail("nan_normal.xyz", "1 2 3 0 0 1\n4 5 6 0 nan 1\n", DP_READ_POINTS, DP_ERR_FORMAT, "normal");
	expect_text_fail("nan.ply", PLY_XYZ_HEADER("ascii", "2") "1 2 3\nNaN 5 6\n", DP_READ_POINTS, DP_ERR_FORMAT,
			 "point 1 ");
	unsigned char bin[256];
	const char head[] = PLY_XYZ_HEADER("binary_little_endian", "1");
	size_t n = strlen(head);
	const unsigned char inf_le[] = {0, 0, 0x80, 0x7f};
	memcpy(bin, head, n);
	memset(bin + n, 0, 8);
	memcpy(bin + n + 8, inf_le, 4);
	expect_fail(tk_write_file(dir, "inf.ply", bin, n + 12), DP_READ_POINTS, DP_ERR_FORMAT, "point 0 ");
	expect_text_fail("inf.off", "OFF\n2 0 0\n1 2 3\n4 inf 6\n", DP_READ_POINTS, DP_ERR_FORMAT, "point 1 ");
	expect_text_fail("nan.obj", "v 1 2 3\nv nan 0 0\n", DP_READ_POINTS, DP_ERR_FORMAT, "point 1 ");
	/* PCD drops NaN points but an infinite one is an error. */
	expect_text_fail("inf.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 3\nDATA ascii\nnan 0 0\n1 2 3\n1 inf 3\n",
			 DP_READ_POINTS, DP_ERR_FORMAT, "point 2 ");
}

static void test_face_range(void **state)
{
	(void)state;
	const char ply[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
			   "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
			   "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
	const char *path = tk_write_text(dir, "face.ply", ply);
	expect_fail(path, DP_READ_MESH, DP_ERR_FORMAT, "out of range");
	/* Faces are not read when only points are asked for. */
	dp_cloud c;
	dp_error err = {0};
	assert_int_equal(dp_cloud_read(path, &c, DP_READ_POINTS, &err), DP_OK);
	assert_int_equal(c.n, 3);
	dp_cloud_free(&c);
	expect_text_fail("negative.ply",
			 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
			 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
			 "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
			 DP_READ_MESH, DP_ERR_FORMAT, "out of range");
	expect_text_fail("face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", DP_READ_MESH, DP_ERR_FORMAT,
			 "out of range");
	expect_text_fail("face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", DP_READ_MESH, DP_ERR_FORMAT, "vertex 8");
	expect_text_fail("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", DP_READ_MESH, DP_ERR_FORMAT, "index");
	expect_text_fail("back.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", DP_READ_MESH, DP_ERR_FORMAT, "index");
}

/* Edges read back: an index past the vertices, or a broken file, fails with
 * no array returned. */
static void test_edge_errors(void **state)
{
	(void)state;
	const char *head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
			   "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
			   "end_header\n0 0 0\n1 1 1\n";
	char text[512];
	const char *bad_ends[] = {"0 2\n", "-1 0\n", "0000000\n", "0 1 1\n"};
	const char *needles[] = {"out of range", "out of range", "truncated", "continues"};
	for (int k = 0; k < 4; k++) {
		snprintf(text, sizeof text, "%s%s", head, bad_ends[k]);
		const char *path = tk_write_text(dir, "bad_edges.ply", text);
		uint32_t *edges = (uint32_t *)text;
		size_t nedges = 7;
		dp_error err = {0};
		assert_int_equal(dp_ply_read_edges(path, &edges, &nedges, &err), DP_ERR_FORMAT);
		assert_null(edges);
		assert_int_equal(nedges, 0);
		if (!strstr(err.message, path) || !strstr(err.message, needles[k]))
			fail_msg("edge case %d: %s", k, err.message);
	}
	const char *half = tk_write_text(dir, "half_edge.ply",
					 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
					 "property float z\nelement edge 1\nproperty int vertex1\nend_header\n0 0 0\n0\n");
	uint32_t *edges;
	size_t nedges;
	dp_error err = {0};
	assert_int_equal(dp_ply_read_edges(half, &edges, &nedges, &err), DP_ERR_FORMAT);
	assert_non_null(strstr(err.message, "vertex2"));
	/* one end named twice and the other not at all: refused, not read as
	 * edges to vertex 0 */
	const char *twice = tk_write_text(dir, "twice_edge.ply",
					  "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
					  "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex1\n"
					  "end_header\n0 0 0\n1 0 0\n1 1\n");
	assert_int_equal(dp_ply_read_edges(twice, &edges, &nedges, &err), DP_ERR_FORMAT);
	assert_non_null(strstr(err.message, "vertex2"));
	char missing[256];
	snprintf(missing, sizeof missing, "%s/absent.ply", dir);
	assert_int_equal(dp_ply_read_edges(missing, &edges, &nedges, &err), DP_ERR_IO);
	assert_null(edges);
	assert_int_equal(dp_ply_read_edges(NULL, &edges, &nedges, &err), DP_ERR_ARG);
}

static void test_malformed(void **state)
{
	(void)state;
	const int P = DP_READ_POINTS;
	const dp_status F = DP_ERR_FORMAT;
	expect_text_fail("magic.ply", "plx\nformat ascii 1.0\nend_header\n", P, F, "not a PLY");
	expect_text_fail("noformat.ply", "ply\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
					 "end_header\n1 2 3\n", P, F, "format");
	expect_text_fail("badformat.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", P, F, "unknown format");
	expect_text_fail("noz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
				    "end_header\n1 2\n", P, F, "x, y or z");
	expect_text_fail("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", P, F, "end_header");
	expect_text_fail("badtype.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
			 P, F, "unknown type");
	expect_text_fail("orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", P, F, "before any element");
	expect_text_fail("negcount.ply", "ply\nformat ascii 1.0\nelement vertex -5\nend_header\n", P, F, "count");
	expect_text_fail("wordcount.ply", "ply\nformat ascii 1.0\nelement vertex abc\nend_header\n", P, F, "count");
	expect_text_fail("floatlist.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
					  "property float y\nproperty float z\nproperty list float int l\nend_header\n",
			 P, F, "integer");
	expect_text_fail("keyword.ply", "ply\nformat ascii 1.0\nelephant vertex 1\nend_header\n", P, F, "keyword");
	expect_text_fail("noverts.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n", P, F, "no vertex");
	expect_text_fail("word.ply", PLY_XYZ_HEADER("ascii", "2") "1 2 3\n1 abc 3\n", P, F, "line 9");
	expect_text_fail("neglist.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
					"property float z\nproperty list char int l\nend_header\n1 2 3 -2 0 0\n",
			 P, F, "negative");

	expect_text_fail("two.xyz", "1 2\n", P, F, "at least 3");
	expect_text_fail("five.xyz", "1 2 3 4 5\n", P, F, "--columns");
	expect_text_fail("eight.xyz", "1 2 3 4 5 6 7 8\n", P, F, "--columns");
	/* neither unit normals nor colours: the columns must be named */
	expect_text_fail("unsure.xyz", "1 2 3 -4 5 6\n1 2 3 7 8 9\n", P, F, "--columns");
	expect_text_fail("mixed.xyz", "1 2 3\n1 2 3 0 0 1\n", P, F, "line 2");
	expect_text_fail("fewer.xyz", "1 2 3 0 0 1\n1 2 3\n", P, F, "line 2");
	expect_text_fail("word.xyz", "1 2 3\n\n1 2 x3\n", P, F, "line 3");
	expect_text_fail("comma.xyz", "1,2,3\n", P, F, "not a number");

	expect_text_fail("nokeyword.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", P, F, "not an OFF");
	expect_text_fail("four.off", "4OFF\n1 0 0\n0 0 0 1\n", P, F, "unsupported");
	expect_text_fail("binary.off", "OFF BINARY\n", P, F, "unsupported");
	expect_text_fail("onecount.off", "OFF\n3\n0 0 0\n1 0 0\n0 1 0\n", P, F, "counts");
	expect_text_fail("fourcounts.off", "OFF\n3 0 0 9\n0 0 0\n1 0 0\n0 1 0\n", P, F, "counts");
	expect_text_fail("shortvertex.off", "OFF\n2 0 0\n0.000000 0.000000 0.000000\n1 0\n", P, F, "line 4");
	expect_text_fail("shortnormal.off", "NOFF\n1 0\n0.000000 0.000000 0.000000 1 0\n", P, F, "needs 6");
	expect_text_fail("shortface.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", DP_READ_MESH, F, "fewer");

	expect_text_fail("compressed.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA binary_compressed\nxx",
			 P, F, "unsupported");
	expect_text_fail("nodata.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\n", P, F, "DATA");
	expect_text_fail("sizes.pcd", "FIELDS x y z\nSIZE 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", P, F, "SIZE");
	expect_text_fail("noz.pcd", "FIELDS x y w\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", P, F, "no z");
	expect_text_fail("wh.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n"
				   "1 2 3\n1 2 3\n1 2 3\n", P, F, "WIDTH");
	expect_text_fail("type.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nPOINTS 1\nDATA ascii\n1 2 3\n", P, F, "TYPE");
	expect_text_fail("size3.pcd", "FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", P, F, "SIZE");
	expect_text_fail("extra.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3 4\n", P, F,
			 "more values");
	expect_text_fail("keyword.pcd", "FIELDS x y z\nBOGUS 1\nDATA ascii\n", P, F, "keyword");

	expect_text_fail("short.obj", "v 1 2 3\nv 1 2\n", P, F, "line 2");
	expect_text_fail("word.obj", "v 1 2 3\nv 0 0 0\nv 1 1 1\nf 1 2 x\n", DP_READ_MESH, F, "line 4");
}

/* --------------------------------------------------------------- fuzzing */

/* Words the parsers look for, so random text gets past the first line. */
static const char *const words[] = {
	"ply\n", "format ascii 1.0\n", "format binary_little_endian 1.0\n", "format binary_big_endian 1.0\n",
	"element vertex 3\n", "element face 2\n", "element vertex 99999999\n", "property float x\n",
	"property float y\n", "property float z\n", "property double nx\n", "property list uchar int vertex_indices\n",
	"property list uint int x\n", "end_header\n", "OFF\n", "NOFF\n", "COFF ", "3 1 0\n", "4 0 1 2 3\n", "v ", "f ",
	"1//2 ", "-1/3 ", "VERSION 0.7\n", "FIELDS x y z normal_x normal_y normal_z\n", "SIZE 4 4 4 4 4 4\n",
	"TYPE F F F F F F\n", "COUNT 1 1 1 1 1 1\n", "POINTS 2\n", "WIDTH 2\n", "DATA ascii\n", "DATA binary\n",
	"nan ", "inf ", "-0 ", "1e38 ", "1e-45 ", "0.5 ", "3 ", "255 ", "-1 ", "4294967295 ", "#", "\n", "\r\n", " ",
	"\t", "\0", "\xff",
};

typedef struct fuzz_stats {
	size_t runs, ok;
} fuzz_stats;

/* Reads a file with both flags; whatever happens must be a clean success or
 * a clean failure. */
static void fuzz_read(const char *path, fuzz_stats *stats)
{
	for (int flags = 0; flags < 2; flags++) {
		dp_cloud c;
		dp_error err = {0};
		memset(&c, 0xab, sizeof c);
		dp_status st = dp_cloud_read(path, &c, flags, &err);
		stats->runs++;
		if (st == DP_OK) {
			stats->ok++;
			assert_true(c.n > 0);
			for (size_t i = 0; i < c.n; i++)
				assert_true(isfinite(c.x[i]) && isfinite(c.y[i]) && isfinite(c.z[i]));
			for (size_t i = 0; i < 3 * c.nfaces; i++)
				assert_true(c.faces[i] < c.n);
			if (!flags)
				assert_int_equal(c.nfaces, 0);
			dp_cloud_free(&c);
			continue;
		}
		if (st != DP_ERR_FORMAT && st != DP_ERR_EMPTY)
			fail_msg("%s: unexpected status %d: %s", path, st, err.message);
		if (!strstr(err.message, path) || strchr(err.message, '\n'))
			fail_msg("%s: bad message: %s", path, err.message);
		assert_true(is_zeroed(&c));
	}
}

#define FUZZ_FILES 150
#define FUZZ_MAX_BYTES 600

static void test_fuzz_random(void **state)
{
	(void)state;
	dp_rng rng;
	dp_rng_seed(&rng, 20151102);
	unsigned char data[FUZZ_MAX_BYTES + 64];
	char name[32];
	fuzz_stats stats = {0, 0};
	for (size_t e = 0; e < NEXT; e++) {
		snprintf(name, sizeof name, "fuzz.%s", extensions[e]);
		for (int k = 0; k < FUZZ_FILES; k++) {
			size_t n = 0, len = (size_t)(dp_rng_uniform(&rng) * FUZZ_MAX_BYTES);
			if (k % 2 == 0) {
				for (; n < len; n++)
					data[n] = (unsigned char)dp_rng_next(&rng);
			} else {
				/* Random sentences of parser keywords and numbers. */
				while (n < len) {
					const char *w = words[dp_rng_next(&rng) % (sizeof words / sizeof words[0])];
					size_t wl = w[0] ? strlen(w) : 1;
					memcpy(data + n, w, wl);
					n += wl;
				}
			}
			fuzz_read(tk_write_file(dir, name, data, n), &stats);
		}
	}
	printf("random fuzz: %zu reads, %zu succeeded\n", stats.runs, stats.ok);
}

/* Valid files of every format, mutated: bytes flipped, cut short, a slice
 * repeated. */
static void test_fuzz_mutations(void **state)
{
	(void)state;
	/* The binary seeds hold NULs: lengths come from sizeof. */
#define SEED(name, text) {name, text, sizeof text - 1}
	static const struct {
		const char *name;
		const char *text;
		size_t len;
	} seeds[] = {
		SEED("m.ply", "ply\nformat ascii 1.0\ncomment c\nelement vertex 4\nproperty float x\nproperty float y\n"
			      "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
			      "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
			      "0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n4 0 1 2 3\n"),
		SEED("b.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
			      "property float y\nproperty float z\nelement face 1\n"
			      "property list uchar int vertex_indices\nend_header\n"
			      "\0\0\0\0\0\0\x80\x3f\0\0\0\0\0\0\0\0\0\0\0\x40\0\0\0\0"
			      "\3\0\0\0\0\1\0\0\0\1\0\0\0"),
		SEED("m.xyz", "# c\n1 2 3 0 0 1\n4 5 6 0 1 0\n7 8 9 1 0 0\n"),
		SEED("m.pcd", "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\n"
			      "TYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
			      "POINTS 3\nDATA ascii\n1 2 3 0 0 1\nnan nan nan 0 0 1\n4 5 6 1 0 0\n"),
		SEED("b.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA binary\n"
			      "\0\0\x80\x3f\0\0\0\x40\0\0\x40\x40\0\0\x80\x40\0\0\xa0\x40\0\0\xc0\x40"),
		SEED("m.off", "NOFF\n# c\n4 2 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"
			      "4 0 1 2 3\n"),
		SEED("m.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf -4 -3 -2 -1\n"),
	};
#undef SEED
	dp_rng rng;
	dp_rng_seed(&rng, 77);
	unsigned char data[2048];
	fuzz_stats stats = {0, 0};
	for (size_t s = 0; s < sizeof seeds / sizeof seeds[0]; s++) {
		const char *text = seeds[s].text;
		size_t len = seeds[s].len;
		fuzz_stats seed_stats = {0, 0};
		fuzz_read(tk_write_file(dir, seeds[s].name, text, len), &seed_stats);
		assert_int_equal(seed_stats.ok, 2); /* the seeds themselves are valid */
		for (int k = 0; k < FUZZ_FILES; k++) {
			size_t n = len;
			memcpy(data, text, len);
			int kind = k % 3;
			if (kind == 0) {
				int flips = 1 + (int)(dp_rng_next(&rng) % 4);
				for (int f = 0; f < flips; f++)
					data[dp_rng_next(&rng) % n] = (unsigned char)dp_rng_next(&rng);
			} else if (kind == 1) {
				n = (size_t)(dp_rng_next(&rng) % len);
			} else {
				size_t a = (size_t)(dp_rng_next(&rng) % len), b = a + (size_t)(dp_rng_next(&rng) % (len - a));
				size_t at = (size_t)(dp_rng_next(&rng) % len);
				memmove(data + at + (b - a), data + at, len - at);
				memcpy(data + at, text + a, b - a);
				n = len + (b - a);
			}
			fuzz_read(tk_write_file(dir, seeds[s].name, data, n), &stats);
		}
	}
	printf("mutation fuzz: %zu reads, %zu succeeded\n", stats.runs, stats.ok);
}

/* ---------------------------------------------------------------- writer */

static void expect_write_fail_at(const char *path, dp_status got, dp_status status, const dp_error *err, int line)
{
	if (got != status)
		fail_msg("line %d: writing %s: expected status %d, got %d: %s", line, path, status, got, err->message);
	if (!strstr(err->message, path) || strchr(err->message, '\n'))
		fail_msg("line %d: bad message: %s", line, err->message);
}

#define expect_write_fail(path, got, status, err) expect_write_fail_at(path, got, status, err, __LINE__)

static void test_write_errors(void **state)
{
	(void)state;
	const float x[] = {0, 1, 2};
	const dp_ply_property props[] = {{"x", x}, {"y", x}, {"z", x}};
	const uint32_t good_edges[] = {0, 1}, bad_edges[] = {0, 3}, bad_faces[] = {0, 1, 7};
	char path[256];
	dp_error err = {0};
	char wdir[128];
	snprintf(wdir, sizeof wdir, "%s/writes", dir);
	assert_int_equal(mkdir(wdir, 0700), 0);

	snprintf(path, sizeof path, "%s/missing/out.ply", wdir);
	expect_write_fail(path, dp_ply_write(path, 3, props, 3, NULL, 0, NULL, 0, 0, &err), DP_ERR_IO, &err);
	assert_non_null(strstr(err.message, strerror(ENOENT)));

	/* The target is a folder: the rename fails and the temporary file goes. */
	snprintf(path, sizeof path, "%s/folder.ply", wdir);
	assert_int_equal(mkdir(path, 0700), 0);
	expect_write_fail(path, dp_ply_write(path, 3, props, 3, NULL, 0, NULL, 0, 1, &err), DP_ERR_IO, &err);
	assert_int_equal(tk_count_files(wdir, NULL), 1);
	assert_int_equal(rmdir(path), 0);

	snprintf(path, sizeof path, "%s/bad.ply", wdir);
	expect_write_fail(path, dp_ply_write(path, 3, props, 3, bad_edges, 1, NULL, 0, 0, &err), DP_ERR_ARG, &err);
	expect_write_fail(path, dp_ply_write(path, 3, props, 3, NULL, 0, bad_faces, 1, 0, &err), DP_ERR_ARG, &err);
	expect_write_fail(path, dp_ply_write(path, 3, props, 3, NULL, 2, NULL, 0, 0, &err), DP_ERR_ARG, &err);
	const dp_ply_property spaced[] = {{"x", x}, {"my y", x}, {"z", x}};
	expect_write_fail(path, dp_ply_write(path, 3, spaced, 3, NULL, 0, NULL, 0, 0, &err), DP_ERR_ARG, &err);
	const dp_ply_property novalues[] = {{"x", x}, {"y", NULL}, {"z", x}};
	expect_write_fail(path, dp_ply_write(path, 3, novalues, 3, NULL, 0, NULL, 0, 0, &err), DP_ERR_ARG, &err);
	expect_write_fail(path, dp_ply_write(path, 3, props, 0, NULL, 0, NULL, 0, 0, &err), DP_ERR_ARG, &err);
	assert_int_equal(dp_cloud_write_ply(path, NULL, 0, &err), DP_ERR_ARG);
	assert_int_equal(dp_ply_write(NULL, 3, props, 3, NULL, 0, NULL, 0, 0, &err), DP_ERR_ARG);
	assert_int_equal(tk_count_files(wdir, NULL), 0);

	/* A write that fails midway (file size limit) leaves the old file whole. */
	snprintf(path, sizeof path, "%s/keep.ply", wdir);
	assert_int_equal(dp_ply_write(path, 3, props, 3, good_edges, 1, NULL, 0, 1, &err), DP_OK);
	struct stat before;
	assert_int_equal(stat(path, &before), 0);
	enum { BIG = 100000 };
	float *big = calloc(BIG, sizeof *big);
	assert_non_null(big);
	const dp_ply_property big_props[] = {{"x", big}, {"y", big}, {"z", big}};
	struct rlimit old_limit, limit;
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
	limit = old_limit;
	limit.rlim_cur = 4096;
	void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &limit), 0);
	dp_status st = dp_ply_write(path, BIG, big_props, 3, NULL, 0, NULL, 0, 0, &err);
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
	signal(SIGXFSZ, old_handler);
	free(big);
	expect_write_fail(path, st, DP_ERR_IO, &err);
	struct stat after;
	assert_int_equal(stat(path, &after), 0);
	assert_int_equal(after.st_size, before.st_size);
	assert_int_equal(tk_count_files(wdir, NULL), 1);
	dp_cloud c;
	assert_int_equal(dp_cloud_read(path, &c, DP_READ_POINTS, &err), DP_OK);
	assert_int_equal(c.n, 3);
	dp_cloud_free(&c);
}

/* Out of memory while collecting points names the file like every other
 * read error (a count beyond what any allocation can hold is refused before
 * trying). */
static void test_out_of_memory_names_file(void **state)
{
	(void)state;
	dp_io_builder b;
	dp_io_builder_init(&b, "scan.xyz");
	dp_error err = {0};
	assert_int_equal(dp_io_builder_reserve(&b, SIZE_MAX / 4, &err), DP_ERR_NOMEM);
	printf("%s\n", err.message);
	assert_true(strncmp(err.message, "scan.xyz: out of memory", strlen("scan.xyz: out of memory")) == 0);
	assert_null(strchr(err.message, '\n'));
	dp_io_builder_free(&b);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_missing_and_unknown),
		cmocka_unit_test(test_empty),
		cmocka_unit_test(test_truncated),
		cmocka_unit_test(test_lying_counts),
		cmocka_unit_test(test_non_finite),
		cmocka_unit_test(test_face_range),
		cmocka_unit_test(test_edge_errors),
		cmocka_unit_test(test_malformed),
		cmocka_unit_test(test_fuzz_random),
		cmocka_unit_test(test_fuzz_mutations),
		cmocka_unit_test(test_write_errors),
		cmocka_unit_test(test_out_of_memory_names_file),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
