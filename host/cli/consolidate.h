#ifndef DP_CLI_CONSOLIDATE_H
#define DP_CLI_CONSOLIDATE_H

#include "cli/session.h"

/* What is the same for every input of a consolidate run (and the demo). */
typedef struct dp_consolidate_job {
	dp_params params;
	double samples_factor; /* --samples Fx: F times each input's point count (0: not given) */
	int save_stages, render, ascii;
	int up_axis; /* vertical axis of the renders: 0 x, 1 y, 2 z; -1: from each input */
	/* write into a staging sibling of the folder and swap it in (consolidate);
	 * 0 writes into the folder itself, beside files of the caller (demo) */
	int staged;
	const char *backend_name, *device_name;
	int json_stdout; /* stdout is one JSON document (--json): no per-input line there */
	struct dp_cli_progress_state *progress; /* the context's progress printer, NULL when quiet */
	const char *format, *columns;           /* --format, --columns: how inputs are read (NULL: by name, detected) */
	int threads; /* --threads: host threads per worker; 0: the CPUs the process may use, shared among the workers */
} dp_consolidate_job;

/* One row of the batch summary. */
typedef struct dp_consolidate_summary {
	int ok;
	char error[DP_ERROR_MESSAGE_MAX];
	size_t points_in, points_out;
	size_t points_run; /* the count the stages ran at: above points_out when those were kept from it */
	double r, seconds;
	int iterations[4]; /* wlop, sink, skeleton, surface */
	char capped[64];   /* the stages that stopped at their iteration cap, comma-separated, or "-" */
	int skipped;       /* --skip-done found the result complete */
	char device[64];   /* the --device entry of the worker that ran it ("" the default) */
} dp_consolidate_summary;

/* Reads `input`, runs the pipeline and writes every output into `dir`
 * (created). Returns 0 or the exit code, after printing one error line. */
int dp_cli_consolidate_one(const char *cmd, dp_context *ctx, const dp_consolidate_job *job, const char *input,
			   const char *dir, dp_consolidate_summary *summary);
/* The same, for an input already in memory (the demo), named `label`. */
int dp_cli_consolidate_cloud(const char *cmd, dp_context *ctx, const dp_consolidate_job *job, const dp_cloud *in,
			     const char *label, const char *dir, dp_result *result, dp_consolidate_summary *summary);


void dp_cli_print_batch_summary(FILE *out, const char *const *inputs, const dp_consolidate_summary *rows,
				size_t n);
/* Progress lines on stderr, at most one a second per stage, "iteration
 * k/cap" where the caps are known, and one line when a stage ends saying why.
 * `user` is a dp_cli_progress_state (one per context, as workers run side by
 * side). */
typedef struct dp_cli_progress_state {
	const char *stage;
	double last_print;
	char prefix[48];         /* before every line: which worker, in a batch over devices */
	const dp_params *params; /* the caps; NULL: unknown */
	int iteration, runs;     /* of the running stage; its runs in a row ("surface": later ones are refined
				    levels; "even", "coarser": numbered) */
	double value, elapsed;
} dp_cli_progress_state;
int dp_cli_progress(void *user, const char *stage, int iteration, double value, double elapsed);
/* The end line of the running stage once it is over: after the pipeline
 * returned, or before a step that reports no iterations (`ok`: it finished;
 * otherwise nothing is printed); readies `st` for the next stage or input. */
void dp_cli_progress_end(dp_cli_progress_state *st, int ok);
/* mkdir -p; 0 or an exit code after one error line. */
int dp_cli_mkdir(const char *cmd, const char *dir);

/* Every file a consolidate run writes into its folder, NULL-terminated. */
extern const char *const dp_cli_result_files[];
/* Removes temporaries of dead runs beside and inside `dir`, then fails (exit
 * code, one error line) unless `dir` is missing, empty or holds nothing but
 * result files: replacing it deletes what it holds. */
int dp_cli_check_result_dir(const char *cmd, const char *dir);
/* Creates the staging folder "<dir>.tmp.<pid>" (its path into `staging`). */
int dp_cli_stage_begin(const char *cmd, const char *dir, char *staging, size_t size);
/* Swaps the complete staging folder in for `dir` and removes the old one;
 * on failure removes staging and prints one error line. */
int dp_cli_stage_commit(const char *cmd, const char *dir, const char *staging);
void dp_cli_stage_abort(const char *staging);

#endif
