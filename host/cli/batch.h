/* Batches at scale: input lists, shards of a collection, results already
 * done, failure records, and the devices a batch spreads over. */
#ifndef DP_CLI_BATCH_H
#define DP_CLI_BATCH_H

#include "cli/session.h"

/* A growable list of strings (each malloc'ed). */
typedef struct dp_cli_list {
	char **items;
	size_t n, cap;
} dp_cli_list;

int dp_cli_list_add(dp_cli_list *l, const char *s);
void dp_cli_list_free(dp_cli_list *l);

/* Appends the inputs named in file `path` ("-": standard input): one path a
 * line, blank lines and lines starting with '#' ignored, surrounding blanks
 * removed. 0 or an exit code after one error line naming the file. */
int dp_cli_read_input_list(const char *cmd, const char *path, dp_cli_list *inputs);

/* The shard this run does: `text` "I/N" (0 <= I < N), or when NULL the Slurm
 * array variables (SLURM_ARRAY_TASK_ID minus SLURM_ARRAY_TASK_MIN, over
 * SLURM_ARRAY_TASK_STEP, of SLURM_ARRAY_TASK_COUNT), or else 0/1 (all).
 * 0 or an exit code after one error line. */
int dp_cli_shard(const char *cmd, const char *text, size_t *index, size_t *count);

/* 1 when `dir` holds the complete result of `input`: a report.json naming
 * that input whose listed files are all there and not empty. */
int dp_cli_result_done(const char *dir, const char *input);

/* The devices a batch spreads over, one worker each: NULL -> one (NULL, the
 * default device); "all" -> every OpenCL device by index; "0,2" -> those
 * indices or names. 0 or an exit code after one error line. */
int dp_cli_device_list(const char *cmd, const char *spec, dp_cli_list *devices);

/* "<dir>.failed.json", the record of an input that failed in a batch, which
 * `summary` lists; cleared by the next success. */
void dp_cli_failure_path(const char *dir, char *out, size_t size);
int dp_cli_write_failure(const char *cmd, const char *dir, const char *input, const char *device,
			 const char *error);
void dp_cli_clear_failure(const char *dir);

#endif
