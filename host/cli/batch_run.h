#ifndef DP_CLI_BATCH_RUN_H
#define DP_CLI_BATCH_RUN_H

#include "cli/batch.h"
#include "cli/consolidate.h"
#include "cli/json_read.h"

/* The inputs of one consolidate run (this shard's), their folders and rows. */
typedef struct dp_batch {
	const char *cmd;
	const char *const *inputs;
	char *const *dirs;
	dp_consolidate_summary *summary; /* rows marked skipped are not run */
	size_t n, todo;
	int quiet;
	int records; /* write "<dir>.failed.json" on failure (batches, whose folders are per input) */
	size_t failed;
	int first_failure;
} dp_batch;

/* Opens one context per entry of `devices` and runs every input not skipped,
 * one worker thread per context. Returns 0, or an exit code when a context
 * could not be opened (nothing run); failures of inputs are counted in b. */
int dp_cli_batch_run(dp_batch *b, const dp_consolidate_job *job, int backend, const dp_cli_list *devices);

/* One input's row as JSON (no newline): input, output, device, status,
 * error, points, deep points, seconds and stop reason per stage, from its
 * report (NULL for a failure); with_results also copies the report's
 * "results" object whole. */
void dp_cli_summary_row_json(FILE *f, const dp_json *report, const char *input, const char *output,
			     const char *device, const char *status, const char *error, int with_results);

int dp_cmd_summary(int argc, char **argv);

#endif
