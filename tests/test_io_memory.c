/* dp_cloud_read_memory: the same cloud, status and message as dp_cloud_read
 * on the same bytes, for every seed of the fuzz corpus (each a valid file)
 * and for damaged copies of them; its own argument errors. */
#include "files.h"
#include "testkit.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const formats[] = {"ply", "pcd", "off", "obj", "xyz"};

static void expect_same_floats(const float *a, const float *b, size_t n, const char *what, const char *path)
{
	if (!a != !b)
		fail_msg("%s: %s present in one cloud only", path, what);
	if (a && memcmp(a, b, n * sizeof *a) != 0)
		fail_msg("%s: %s differ between file and memory", path, what);
}

/* Reads `size` bytes as the file dir/name and from memory under the same
 * name; both must give the same outcome. Returns the status. */
static dp_status compare(const char *dir, const char *name, const unsigned char *data, size_t size, int flags)
{
	const char *path = tk_write_file(dir, name, data, size);
	dp_cloud a, b;
	dp_error ea = {0}, eb = {0};
	dp_status sa = dp_cloud_read(path, &a, flags, &ea);
	dp_status sb = dp_cloud_read_memory(data, size, path, &b, flags, &eb);
	if (sa != sb || strcmp(ea.message, eb.message) != 0)
		fail_msg("%s (%zu bytes, flags %d): file gives %d '%s', memory %d '%s'", path, size, flags, sa,
			 ea.message, sb, eb.message);
	if (sa == DP_OK) {
		assert_int_equal(a.n, b.n);
		assert_int_equal(a.nfaces, b.nfaces);
		expect_same_floats(a.x, b.x, a.n, "x", path);
		expect_same_floats(a.y, b.y, a.n, "y", path);
		expect_same_floats(a.z, b.z, a.n, "z", path);
		expect_same_floats(a.nx, b.nx, a.n, "nx", path);
		expect_same_floats(a.ny, b.ny, a.n, "ny", path);
		expect_same_floats(a.nz, b.nz, a.n, "nz", path);
		if (a.nfaces && memcmp(a.faces, b.faces, 3 * a.nfaces * sizeof *a.faces) != 0)
			fail_msg("%s: faces differ between file and memory", path);
	} else {
		dp_cloud zero = {0};
		assert_memory_equal(&b, &zero, sizeof zero);
	}
	dp_cloud_free(&a);
	dp_cloud_free(&b);
	return sa;
}

static void test_corpus_file_and_memory_agree(void **state)
{
	(void)state;
	const char *src = getenv("DP_SOURCE_DIR");
	const char *tmp = tk_temp_dir();
	size_t seeds = 0, damaged = 0;
	for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
		char dir[4096];
		snprintf(dir, sizeof dir, "%s/tests/fuzz/corpus/%s", src ? src : ".", formats[f]);
		DIR *d = opendir(dir);
		if (!d)
			fail_msg("%s: no seed corpus", dir);
		struct dirent *e;
		while ((e = readdir(d))) {
			if (e->d_name[0] == '.')
				continue;
			char seed[8192], copy[64];
			snprintf(seed, sizeof seed, "%s/%s", dir, e->d_name);
			snprintf(copy, sizeof copy, "seed.%s", formats[f]);
			size_t size;
			unsigned char *data = tk_read_file(seed, &size);
			for (int flags = DP_READ_POINTS; flags <= DP_READ_MESH; flags++) {
				if (compare(tmp, copy, data, size, flags) != DP_OK)
					fail_msg("seed %s is not a valid file", seed);
				/* every truncation and a flipped byte at every offset: the
				 * error paths must agree as well (as a mesh only: that reads
				 * all a points read does, and halves the time under ASan) */
				for (size_t cut = 0; flags == DP_READ_MESH && cut < size; cut++) {
					compare(tmp, copy, data, cut, flags);
					unsigned char keep = data[cut];
					data[cut] ^= (unsigned char)(cut * 37 + 1);
					compare(tmp, copy, data, size, flags);
					data[cut] = keep;
					damaged += 2;
				}
			}
			free(data);
			seeds++;
		}
		closedir(d);
	}
	printf("%zu seeds and %zu damaged copies read alike from files and memory\n", seeds, damaged);
	assert_true(seeds >= 15);
	tk_remove_dir(tmp);
}

static void test_memory_errors(void **state)
{
	(void)state;
	static const char xyz[] = "1 2 3\n";
	dp_cloud c;
	dp_error err = {0};
	assert_int_equal(dp_cloud_read_memory(xyz, 6, "a.xyz", NULL, 0, &err), DP_ERR_ARG);
	assert_int_equal(dp_cloud_read_memory(xyz, 6, NULL, &c, 0, &err), DP_ERR_ARG);
	assert_int_equal(dp_cloud_read_memory(NULL, 6, "a.xyz", &c, 0, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "a.xyz"));
	assert_int_equal(dp_cloud_read_memory(xyz, 6, "a.xyz", &c, 4, &err), DP_ERR_ARG);
	assert_int_equal(dp_cloud_read_memory(NULL, 0, "a.xyz", &c, 0, &err), DP_ERR_EMPTY);
	assert_int_equal(dp_cloud_read_memory(xyz, 6, "a.las", &c, 0, &err), DP_ERR_FORMAT);
	assert_non_null(strstr(err.message, "unknown point file format 'las'"));
	/* no NUL needed: the last line ends at `size`, not at a terminator */
	assert_int_equal(dp_cloud_read_memory(xyz, 5, "dir.d/A.XYZ", &c, 0, &err), DP_OK);
	assert_int_equal(c.n, 1);
	assert_true(c.x[0] == 1 && c.y[0] == 2 && c.z[0] == 3);
	dp_cloud_free(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_corpus_file_and_memory_agree),
		cmocka_unit_test(test_memory_errors),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
