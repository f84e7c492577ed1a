#ifndef DP_CLI_SESSION_H
#define DP_CLI_SESSION_H

#include "cli/cli.h"

/* The options every computing command takes, as table rows. */
#define CLI_BACKEND_OPTS(backend, device)                                                              \
	{"--backend", CLI_CHOICE, &(backend), "kernels on an OpenCL device, or the scalar reference", "cl|ref", \
	 NULL},                                                                                        \
	{"--device", CLI_STRING, &(device),                                                            \
	 "OpenCL device: index or name substring from `dpoints devices` (env DPOINTS_DEVICE)", NULL, NULL}

/* backend: 0 = cl, 1 = ref (the order of CLI_BACKEND_OPTS's choices). Returns
 * 0 or an exit code after printing the error. */
int cli_open_context(const char *cmd, int backend, const char *device, dp_context **ctx);
/* Prefixes err's message with the input's name: errors from the library name
 * the stage ("wlop: ..."), and in a batch the line must say which input. */
void dp_cli_name_input(dp_error *err, const char *input);
/* Fails early (exit code) when the folder of `path` is not writable, so a long
 * run does not end in an unwritable output. */
int cli_check_output(const char *cmd, const char *path);
/* Fails (exit code, after one error line) when `output` exists and is the
 * same file as one of the inputs, which writing it would replace. */
int cli_check_not_input(const char *cmd, const char *output, const char *const *inputs, size_t ninputs);
/* Fails (exit code, after one error line) when the outputs `a` and `b` are
 * one file, existing or not, which the second write would replace. */
int cli_check_distinct_outputs(const char *cmd, const char *a, const char *b);
/* The same for every file a consolidate run writes into folder `dir`. */
int cli_check_folder_not_input(const char *cmd, const char *dir, const char *const *inputs, size_t ninputs);
/* Whether an output path names standard output ("-"), which scan, render and
 * wlop (its points and its report) accept for their one-file outputs. */
int cli_is_stdout(const char *path);
/* Refuses "-" as an output folder (consolidate, demo), `hint` ending the
 * line. 0, or an exit code after one error line. */
int cli_check_folder(const char *cmd, const char *dir, const char *hint);
/* Runs `write` on `path`, or for "-" into a temporary file copied to stdout
 * (dp_cli_write_stdout). 0, or an exit code after one error line. */
int cli_write_file(const char *cmd, const char *path, dp_status (*write)(const char *path, const void *arg, dp_error *err),
		   const void *arg);
/* A PLY file of `cloud` (ascii or binary) through cli_write_file. */
int cli_write_ply(const char *cmd, const char *path, const dp_cloud *cloud, int ascii);
/* Writes a JSON document through a temporary file and a rename, or to
 * stdout for "-" (cli_write_file). */
int cli_write_json(const char *cmd, const char *path, void (*fill)(json_writer *w, const void *arg),
		   const void *arg);

#endif
