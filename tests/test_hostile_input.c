/* Inputs built to hurt (issue 9): files whose headers are well formed but
 * whose counts or contents make reading never end or cost far more than the
 * answer needs. Each must be refused quickly, with one line naming the file. */
#include "files.h"
#include "testkit.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

static char dir[64];

/* A hang would stall the whole suite until ctest's timeout; an alarm turns it
 * into a failure of this test with a message. */
static void on_alarm(int sig)
{
	(void)sig;
	static const char msg[] = "FAIL: reading did not finish in time (hang)\n";
	if (write(2, msg, sizeof msg - 1) < 0) {
		/* nothing more to do on the way out */
	}
	_exit(1);
}

static int setup(void **state)
{
	(void)state;
	snprintf(dir, sizeof dir, "%s", tk_temp_dir());
	signal(SIGALRM, on_alarm);
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	tk_remove_dir(dir);
	return 0;
}

static void expect_refused(const char *path, const char *needle)
{
	dp_cloud c;
	dp_error err = {0};
	alarm(20);
	dp_status st = dp_cloud_read(path, &c, DP_READ_POINTS, &err);
	alarm(0);
	if (st != DP_ERR_FORMAT)
		fail_msg("%s: expected DP_ERR_FORMAT, got %d: %s", path, st, err.message);
	if (strncmp(err.message, path, strlen(path)) != 0 || strchr(err.message, '\n'))
		fail_msg("not one line starting with the path: %s", err.message);
	if (needle && !strstr(err.message, needle))
		fail_msg("message lacks '%s': %s", needle, err.message);
	assert_null(c.x);
	assert_int_equal(c.n, 0);
}

#define PLY_VERTEX(format) \
	"ply\nformat " format " 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"

/* Issue 9, defect 1: an element without properties has rows of no bytes, so
 * the file size bounds nothing and 2^64 rows were read for ever. */
static void test_element_without_properties(void **state)
{
	(void)state;
	const char *formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
	const char *counts[] = {"18446744073709551615", "1000000", "1"};
	for (size_t f = 0; f < 3; f++)
		for (size_t k = 0; k < 3; k++) {
			char text[512], name[64];
			int binary = f > 0;
			snprintf(text, sizeof text, PLY_VERTEX("%s") "element junk %s\nend_header\n%s", formats[f],
				 counts[k], binary ? "" : "1 2 3\n");
			snprintf(name, sizeof name, "empty_rows_%zu_%zu.ply", f, k);
			size_t len = strlen(text);
			if (binary) {
				/* one vertex of three floats after the header */
				memset(text + len, 0, 12);
				len += 12;
			}
			expect_refused(tk_write_file(dir, name, text, len), "junk");
		}
	/* the same element before the vertex one */
	expect_refused(tk_write_text(dir, "empty_first.ply",
				     "ply\nformat ascii 1.0\nelement junk 5\nelement vertex 1\nproperty float x\n"
				     "property float y\nproperty float z\nend_header\n1 2 3\n"),
		       "no properties");
	/* an empty element with no rows is harmless and stays readable */
	dp_cloud c;
	dp_error err = {0};
	const char *ok = tk_write_text(dir, "empty_none.ply",
				       PLY_VERTEX("ascii") "element junk 0\nend_header\n1 2 3\n");
	assert_int_equal(dp_cloud_read(ok, &c, DP_READ_POINTS, &err), DP_OK);
	assert_int_equal(c.n, 1);
	dp_cloud_free(&c);
}

#if defined(__SANITIZE_ADDRESS__)
#define SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SANITIZED 1
#endif
#endif
#ifndef SANITIZED
#define SANITIZED 0
#endif

static double peak_mb(void)
{
	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss / 1024.0;
}

/* Issue 9, defect 5: a valid header over a body of zeros (2 GB took 150 s and
 * 5.7 GB before "1 distinct position"). Reading holds the points once; WLOP
 * refuses after one pass, before its per-point buffers and sort (which cost
 * ~40 bytes a point, 110 MB here). Runs first: the peak resident size only
 * grows, so later tests would hide what this one spends. */
static void test_body_of_zeros(void **state)
{
	(void)state;
	enum { N = 3000000 };
	char head[256];
	int len = snprintf(head, sizeof head,
			   "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
			   "property float y\nproperty float z\nend_header\n",
			   N);
	size_t bytes = (size_t)len + 12 * (size_t)N;
	char *file = calloc(bytes, 1);
	assert_non_null(file);
	memcpy(file, head, (size_t)len);
	const char *path = tk_write_file(dir, "zeros.ply", file, bytes);
	free(file);
	dp_context *ctx = tk_ref_context();
	double points_mb = 12.0 * N / (1024 * 1024), before = peak_mb();

	dp_cloud c;
	dp_error err = {0};
	assert_int_equal(dp_cloud_read(path, &c, DP_READ_POINTS, &err), DP_OK);
	double after_read = peak_mb();
	/* AddressSanitizer's realloc always moves and quarantines the old block,
	 * so the peak measures the sanitizer there, not the reader. */
	if (!SANITIZED && after_read - before > 1.5 * points_mb)
		fail_msg("reading %d points (%.0f MB) raised the peak by %.0f MB", N, points_mb, after_read - before);

	dp_wlop_params p;
	dp_wlop_params_default(&p);
	dp_cloud s = {0};
	alarm(20);
	assert_int_equal(dp_wlop(ctx, &c, &p, &s, NULL, &err), DP_ERR_ARG);
	alarm(0);
	double after_wlop = peak_mb();
	if (after_wlop - after_read > 0.25 * points_mb)
		fail_msg("refusing %d copies of one point raised the peak by %.0f MB (the points are %.0f MB)", N,
			 after_wlop - after_read, points_mb);
	assert_non_null(strstr(err.message, "1 distinct position,"));
	dp_cloud_free(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_body_of_zeros),
		cmocka_unit_test(test_element_without_properties),
	};
	int failed = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return failed;
}
