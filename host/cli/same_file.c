/* Outputs that would replace an input: the rename that commits an output
 * puts it in the input's place, so `wlop X.xyz -o X.xyz` destroyed the input.
 * Paths are compared as files (device and inode), since "./X.xyz", a hard
 * link or a symbolic link name the same file with a different string. */
#include "cli/consolidate.h"

#include <libgen.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* Whether two paths name one existing file. */
static int same_file(const char *a, const char *b)
{
	struct stat sa, sb;
	return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int cli_check_not_input(const char *cmd, const char *output, const char *const *inputs, size_t ninputs)
{
	for (size_t i = 0; i < ninputs; i++)
		if (same_file(output, inputs[i])) {
			fprintf(stderr, "dpoints %s: %s: the output is the input file %s; choose another output\n", cmd,
				output, inputs[i]);
			return DP_EXIT_INPUT;
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
	if (strcmp(a, b) == 0 || same_file(a, b))
		return 1;
	char ca[4096], cb[4096];
	snprintf(ca, sizeof ca, "%s", a);
	snprintf(cb, sizeof cb, "%s", b);
	if (strcmp(basename(ca), basename(cb)) != 0)
		return 0;
	snprintf(ca, sizeof ca, "%s", a);
	snprintf(cb, sizeof cb, "%s", b);
	return same_file(dirname(ca), dirname(cb));
}

int cli_check_distinct_outputs(const char *cmd, const char *a, const char *b)
{
	if (!same_output(a, b))
		return 0;
	fprintf(stderr, "dpoints %s: %s: two outputs would be the one file %s; choose another name for one\n", cmd, a,
		b);
	return DP_EXIT_INPUT;
}
