/* Inputs as people have them, outputs where they want them: a format named
 * for standard input or an odd extension, XYZ columns named, colours carried
 * from the input to what is made from it, and a PLY written to stdout. */
#include "cli/input.h"

#include "io/io.h"
#include "knn/attributes.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

dp_status dp_cli_read_input(const char *path, const char *format, const char *columns, dp_cloud *cloud, dp_error *err)
{
	return dp_io_read_cloud(path, format, columns, cloud, DP_READ_POINTS, err);
}

dp_status dp_cli_carry_colours(const dp_cloud *in, dp_result *res, dp_error *err)
{
	dp_status st = dp_transfer_attributes(&res->surface, in, err);
	if (st == DP_OK && res->wlop.n)
		st = dp_transfer_attributes(&res->wlop, in, err);
	return st;
}

int dp_cli_write_stdout(const char *cmd, dp_status (*write)(const char *path, const void *arg, dp_error *err),
			const void *arg)
{
	/* written whole to a file first, so a failure leaves stdout empty */
	const char *dir = getenv("TMPDIR");
	char path[4096];
	snprintf(path, sizeof path, "%s/dpoints-stdout-XXXXXX", dir && *dir ? dir : "/tmp");
	int fd = mkstemp(path);
	if (fd < 0) {
		fprintf(stderr, "dpoints %s: standard output: cannot create a temporary file %s: %s\n", cmd, path, strerror(errno));
		return DP_EXIT_FAILURE;
	}
	close(fd);
	dp_error err = {0};
	if (write(path, arg, &err) != DP_OK) {
		unlink(path);
		return dp_cli_fail(cmd, &err);
	}
	FILE *f = fopen(path, "rb");
	int rc = 0;
	if (!f) {
		fprintf(stderr, "dpoints %s: standard output: cannot reopen %s: %s\n", cmd, path, strerror(errno));
		rc = DP_EXIT_FAILURE;
	} else {
		char buf[1 << 16];
		size_t got;
		while ((got = fread(buf, 1, sizeof buf, f)) > 0)
			if (fwrite(buf, 1, got, stdout) != got)
				break;
		if (ferror(f) || fflush(stdout) != 0 || ferror(stdout)) {
			fprintf(stderr, "dpoints %s: writing to standard output failed: %s\n", cmd, strerror(errno));
			rc = DP_EXIT_FAILURE;
		}
		fclose(f);
	}
	unlink(path);
	return rc;
}
