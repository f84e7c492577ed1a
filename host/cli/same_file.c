/* Outputs that would replace an input: the rename that commits an output
 * puts it in the input's place, so `wlop X.xyz -o X.xyz` destroyed the input.
 * Paths are compared as files (device and inode), since "./X.xyz", a hard
 * link or a symbolic link name the same file with a different string. */
#include "cli/consolidate.h"

#include <stdio.h>
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
