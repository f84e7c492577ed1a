#ifndef DP_CLI_INPUT_H
#define DP_CLI_INPUT_H

#include "cli/cli.h"

/* The --format and --columns options of the commands that read a cloud. */
#define CLI_INPUT_OPTS(format, columns)                                                                    \
	{"--format", CLI_STRING, &(format),                                                                \
	 "format of the input when its name does not say (standard input '-', odd extensions): ply, xyz, pts, " \
	 "pcd, off, obj, ... (gzip is recognised by its bytes)",                                           \
	 NULL, NULL},                                                                                      \
	{"--columns", CLI_STRING, &(columns),                                                              \
	 "XYZ/PTS columns, e.g. x,y,z,nx,ny,nz,r,g,b (i: intensity, _: ignored); default: detected", NULL, NULL}

/* dp_cloud_read with `format` (NULL: from the name) and XYZ `columns` (NULL:
 * detected); path "-" is standard input. */
dp_status dp_cli_read_input(const char *path, const char *format, const char *columns, dp_cloud *cloud,
			    dp_error *err);
/* Colours and intensities of the input, when it has them, onto the surface
 * and the WLOP samples of `res` (each point takes its nearest input
 * point's). */
dp_status dp_cli_carry_colours(const dp_cloud *in, dp_result *res, dp_error *err);
/* An output named `-`: runs `write` into a temporary file, then copies it to stdout, so a
 * failure writes nothing there. 0 or an exit code after one error line. */
int dp_cli_write_stdout(const char *cmd, dp_status (*write)(const char *path, const void *arg, dp_error *err),
			const void *arg);

#endif
