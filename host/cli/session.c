/* What every computing subcommand shares: the backend and device options,
 * opening the context, checking outputs up front, and atomic JSON reports. */
#include "cli/session.h"
#include "cli/input.h"

#include "io/io.h"

#include <libgen.h>
#include <string.h>
#include <unistd.h>

int cli_open_context(const char *cmd, int backend, const char *device, dp_context **ctx)
{
	dp_error err = {0};
	if (dp_context_create(ctx, backend == 1 ? DP_BACKEND_REF : DP_BACKEND_CL, device, &err) != DP_OK)
		return dp_cli_fail(cmd, &err);
	return 0;
}

void dp_cli_name_input(dp_error *err, const char *input)
{
	size_t plen = strlen(input) + 2, mlen = strlen(err->message);
	if (plen >= sizeof err->message)
		return;
	if (plen + mlen >= sizeof err->message)
		mlen = sizeof err->message - 1 - plen;
	memmove(err->message + plen, err->message, mlen);
	memcpy(err->message, input, plen - 2);
	memcpy(err->message + plen - 2, ": ", 2);
	err->message[plen + mlen] = '\0';
}

int cli_check_output(const char *cmd, const char *path)
{
	char copy[4096];
	snprintf(copy, sizeof copy, "%s", path);
	const char *dir = dirname(copy);
	if (access(dir, W_OK) != 0) {
		fprintf(stderr, "dpoints %s: %s: cannot write into folder '%s'\n", cmd, path, dir);
		return DP_EXIT_INPUT;
	}
	return 0;
}

int cli_is_stdout(const char *path)
{
	return strcmp(path, "-") == 0;
}

int cli_check_folder(const char *cmd, const char *dir, const char *hint)
{
	if (!cli_is_stdout(dir))
		return 0;
	fprintf(stderr, "dpoints %s: -o -: the output is a folder of files, not standard output%s\n", cmd, hint);
	return DP_EXIT_INPUT;
}

int cli_write_file(const char *cmd, const char *path, dp_status (*write)(const char *path, const void *arg, dp_error *err),
		   const void *arg)
{
	if (cli_is_stdout(path))
		return dp_cli_write_stdout(cmd, write, arg);
	dp_error err = {0};
	if (write(path, arg, &err) != DP_OK)
		return dp_cli_fail(cmd, &err);
	return 0;
}

typedef struct ply_job {
	const dp_cloud *cloud;
	int ascii;
} ply_job;

static dp_status write_ply(const char *path, const void *varg, dp_error *err)
{
	const ply_job *job = varg;
	return dp_cloud_write_ply(path, job->cloud, job->ascii, err);
}

int cli_write_ply(const char *cmd, const char *path, const dp_cloud *cloud, int ascii)
{
	ply_job job = {cloud, ascii};
	return cli_write_file(cmd, path, write_ply, &job);
}

typedef struct json_job {
	void (*fill)(json_writer *w, const void *arg);
	const void *arg;
} json_job;

static dp_status write_json(const char *path, const void *varg, dp_error *err)
{
	const json_job *job = varg;
	dp_atomic_file af;
	dp_status st = dp_atomic_open(&af, path, err);
	if (st != DP_OK)
		return st;
	json_writer w;
	json_begin(&w, af.f);
	job->fill(&w, job->arg);
	json_finish(&w);
	return dp_atomic_commit(&af, err);
}

int cli_write_json(const char *cmd, const char *path, void (*fill)(json_writer *w, const void *arg), const void *arg)
{
	json_job job = {fill, arg};
	return cli_write_file(cmd, path, write_json, &job);
}
