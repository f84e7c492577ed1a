/* Outputs that would replace an input: the rename that commits an output
 * puts it in the input's place, so `wlop X.xyz -o X.xyz` destroyed the input.
 * Paths are compared as files (device and inode), since "./X.xyz", a hard
 * link or a symbolic link name the same file with a different string. */
#include "cli/consolidate.h"

#include <libgen.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

int cli_check_not_input(const char *cmd, const char *output, const char *const *inputs, size_t ninputs)
{
	struct stat out;
	/* an output that does not exist yet cannot be an input */
	if (stat(output, &out) != 0)
		return 0;
	for (size_t i = 0; i < ninputs; i++) {
		struct stat in;
		if (stat(inputs[i], &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino) {
			fprintf(stderr, "dpoints %s: %s: the output is the input file %s; choose another output\n", cmd,
				output, inputs[i]);
			return DP_EXIT_INPUT;
		}
	}
	return 0;
}

int cli_check_folder_not_input(const char *cmd, const char *dir, const char *const *inputs, size_t ninputs)
{
	for (size_t k = 0; dp_cli_result_files[k]; k++) {
		char path[4096];
		snprintf(path, sizeof path, "%s/%s", dir, dp_cli_result_files[k]);
		int rc = cli_check_not_input(cmd, path, inputs, ninputs);
		if (rc)
			return rc;
	}
	return 0;
}

/* Whether two output paths name one file, existing or not: the same string,
 * the same existing file, or the same name in the same existing folder. */
static int same_output(const char *a, const char *b)
{
	if (strcmp(a, b) == 0)
		return 1;
	struct stat sa, sb;
	if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
		return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
	char ca[4096], cb[4096];
	snprintf(ca, sizeof ca, "%s", a);
	snprintf(cb, sizeof cb, "%s", b);
	if (strcmp(basename(ca), basename(cb)) != 0)
		return 0;
	snprintf(ca, sizeof ca, "%s", a);
	snprintf(cb, sizeof cb, "%s", b);
	const char *da = dirname(ca), *db = dirname(cb);
	return stat(da, &sa) == 0 && stat(db, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int cli_check_distinct_outputs(const char *cmd, const char *a, const char *b)
{
	if (!same_output(a, b))
		return 0;
	fprintf(stderr, "dpoints %s: %s: two outputs would be the one file %s; choose another name for one\n", cmd, a,
		b);
	return DP_EXIT_INPUT;
}
