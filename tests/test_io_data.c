/* Every file of the shared third-party data folder loads with the count its
 * README (or its own header) states, and its first point matches the file's
 * text read independently here. Skips when the folder is absent. */
#include "testkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* How the test finds the first point's text in a file. */
enum first_line {
	FIRST_LINE,        /* the first non-blank line */
	AFTER_END_HEADER,  /* PLY ascii */
	AFTER_DATA,        /* PCD ascii */
	AFTER_OFF_COUNTS,  /* OFF: after the keyword and the count line */
	BINARY_DOUBLES     /* PLY binary little endian, x y z doubles first */
};

typedef struct data_file {
	const char *path;
	size_t n;          /* 0: the count the file's header declares */
	size_t nfaces;     /* read as a mesh when not 0 */
	int normals;
	int first;
} data_file;

static const data_file files[] = {
	{"paper/statue-fig12b-raw.xyz", 32614, 0, 0, FIRST_LINE},
	{"paper/loops-fig10t-raw.ply", 43545, 0, 1, AFTER_END_HEADER},
	{"stanford-bunny/bun000.ply", 0, 0, 0, AFTER_END_HEADER},
	{"stanford-bunny/bun090.ply", 0, 0, 0, AFTER_END_HEADER},
	{"stanford-bunny/bun180.ply", 0, 0, 0, AFTER_END_HEADER},
	{"stanford-bunny/bun270.ply", 0, 0, 0, AFTER_END_HEADER},
	{"stanford-bunny/bun_zipper_res2.ply", 8171, 16301, 0, AFTER_END_HEADER},
	{"cgal/sphere_20k.xyz", 21000, 0, 0, FIRST_LINE},
	{"cgal/kitten.xyz", 5210, 0, 1, FIRST_LINE},
	{"cgal/hippo1.ply", 6104, 0, 1, BINARY_DOUBLES},
	{"cgal/hippo2.ply", 4387, 0, 1, BINARY_DOUBLES},
	{"cgal/fin90_with_PCA_normals.xyz", 757, 0, 1, FIRST_LINE},
	{"cgal/knot1.off", 3200, 6400, 0, AFTER_OFF_COUNTS},
	{"cgal/anchor_dense.off", 3793, 7598, 0, AFTER_OFF_COUNTS},
	{"cloudcontr/fertility_1n.off", 4018, 0, 1, AFTER_OFF_COUNTS},
	{"cloudcontr/fertility_2n.off", 7218, 0, 1, AFTER_OFF_COUNTS},
	{"cloudcontr/corn_v12108.off", 12108, 19178, 0, AFTER_OFF_COUNTS},
	{"pcn/chair.pcd", 0, 0, 0, AFTER_DATA},
	{"pcn/lamp.pcd", 0, 0, 0, AFTER_DATA},
	{"pcn/airplane.pcd", 0, 0, 0, AFTER_DATA},
	{"pcl/lamppost.pcd", 1771, 0, 0, AFTER_DATA},
	{"adtree/tree7.xyz", 15130, 0, 0, FIRST_LINE},
};

/* The count in "element vertex N" (PLY) or "POINTS N" (PCD). */
static size_t header_count(const char *path)
{
	FILE *f = fopen(path, "rb");
	char line[512];
	size_t n = 0;
	assert_non_null(f);
	while (fgets(line, sizeof line, f)) {
		if (sscanf(line, "element vertex %zu", &n) == 1 || sscanf(line, "POINTS %zu", &n) == 1)
			break;
	}
	fclose(f);
	if (n == 0)
		fail_msg("%s: no count in the header", path);
	return n;
}

static int blank(const char *line)
{
	return strspn(line, " \t\r\n") == strlen(line);
}

/* The first point as written in the file, parsed with stdio. */
static void first_point(const char *path, int how, float p[3])
{
	FILE *f = fopen(path, "rb");
	char line[4096];
	assert_non_null(f);
	if (how == BINARY_DOUBLES) {
		while (fgets(line, sizeof line, f) && strcmp(line, "end_header\n") != 0)
			;
		unsigned char b[24];
		assert_int_equal(fread(b, 1, sizeof b, f), sizeof b);
		for (int k = 0; k < 3; k++) {
			uint64_t u = 0;
			double d;
			for (int i = 0; i < 8; i++)
				u |= (uint64_t)b[8 * k + i] << (8 * i);
			memcpy(&d, &u, sizeof d);
			p[k] = (float)d;
		}
		fclose(f);
		return;
	}
	int skip = 0; /* lines holding data still to pass */
	if (how == AFTER_OFF_COUNTS)
		skip = 2;
	if (how == AFTER_END_HEADER || how == AFTER_DATA) {
		const char *marker = how == AFTER_DATA ? "DATA" : "end_header";
		while (fgets(line, sizeof line, f) && strncmp(line, marker, strlen(marker)) != 0)
			;
	}
	while (fgets(line, sizeof line, f)) {
		if (blank(line) || line[0] == '#')
			continue;
		if (skip-- > 0)
			continue;
		break;
	}
	fclose(f);
	if (sscanf(line, "%f %f %f", &p[0], &p[1], &p[2]) != 3)
		fail_msg("%s: cannot parse the first point from '%s'", path, line);
}

static void test_data_files(void **state)
{
	(void)state;
	if (!tk_data_path("README.md"))
		skip();
	double total = 0;
	for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
		const data_file *d = &files[i];
		char path[4096];
		const char *found = tk_data_path(d->path);
		if (!found)
			fail_msg("%s is missing from the data folder", d->path);
		snprintf(path, sizeof path, "%s", found);
		size_t n = d->n ? d->n : header_count(path);
		for (int mesh = 0; mesh < 2; mesh++) {
			dp_cloud c;
			dp_error err = {0};
			double t0 = dp_seconds();
			if (dp_cloud_read(path, &c, mesh ? DP_READ_MESH : DP_READ_POINTS, &err) != DP_OK)
				fail_msg("%s: %s", d->path, err.message);
			total += dp_seconds() - t0;
			if (c.n != n)
				fail_msg("%s: %zu points, expected %zu", d->path, c.n, n);
			assert_int_equal(c.nx != NULL, d->normals);
			assert_int_equal(c.nfaces, mesh ? d->nfaces : 0);
			float p[3];
			first_point(path, d->first, p);
			if (c.x[0] != p[0] || c.y[0] != p[1] || c.z[0] != p[2])
				fail_msg("%s: first point %.9g %.9g %.9g, the file says %.9g %.9g %.9g", d->path,
					 (double)c.x[0], (double)c.y[0], (double)c.z[0], (double)p[0], (double)p[1],
					 (double)p[2]);
			dp_cloud_free(&c);
		}
	}
	printf("read %zu data files twice in %.3f s\n", sizeof files / sizeof files[0], total);
}

/* The README: 2828 of the loops scan's normals are (0,0,0). */
static void test_loops_zero_normals(void **state)
{
	(void)state;
	const char *path = tk_data_path("paper/loops-fig10t-raw.ply");
	if (!path)
		skip();
	dp_cloud c;
	dp_error err = {0};
	assert_int_equal(dp_cloud_read(path, &c, DP_READ_POINTS, &err), DP_OK);
	size_t zero = 0;
	for (size_t i = 0; i < c.n; i++)
		zero += c.nx[i] == 0 && c.ny[i] == 0 && c.nz[i] == 0;
	assert_int_equal(zero, 2828);
	dp_cloud_free(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_data_files),
		cmocka_unit_test(test_loops_zero_normals),
	};
	return tk_exit_status(cmocka_run_group_tests(tests, NULL, NULL));
}
