/* The dpoints command-line tool: subcommands, a table-driven option parser
 * (so --help lists every parameter with its default), exit codes, reports. */
#ifndef DP_CLI_CLI_H
#define DP_CLI_CLI_H

#include "dpoints_tools.h"
#include "io/json.h"

#include <stdio.h>

/* Exit statuses, documented in the README. */
enum {
	DP_EXIT_OK = 0,
	DP_EXIT_FAILURE = 1, /* anything not below */
	DP_EXIT_INPUT = 2,   /* bad usage or bad input file */
	DP_EXIT_DEVICE = 3,  /* OpenCL: no device, build failure, runtime error */
	DP_EXIT_NOMEM = 4    /* out of memory */
};

int dp_cli_exit_code(dp_status st);
/* Prints "dpoints <cmd>: <message>" on stderr and returns the exit code. */
int dp_cli_fail(const char *cmd, const dp_error *err);

typedef enum cli_opt_kind {
	CLI_STRING,  /* const char * */
	CLI_SIZE,    /* size_t, > 0 */
	CLI_COUNT,   /* size_t, >= 0 (0 has a meaning of its own) */
	CLI_INT,     /* int */
	CLI_U64,     /* uint64_t */
	CLI_DOUBLE,  /* double */
	CLI_FLAG,    /* int set to 1 */
	CLI_VEC3,    /* double[3] from "X,Y,Z" */
	CLI_CHOICE   /* int: index of the value in `choices` ("a|b|c") */
} cli_opt_kind;

typedef struct cli_opt {
	const char *name;    /* "--samples" */
	cli_opt_kind kind;
	void *target;
	const char *help;
	const char *choices; /* CLI_CHOICE only */
	int *seen;           /* optional: set to 1 when given */
} cli_opt;

/* Parses argv[first..argc): options from the table (as "--name value" or
 * "--name=value"), "-o" as an alias of "--output", the rest positional (up to
 * max_pos, collected into positional[]). "--help" prints the usage and sets
 * *help. Returns 0, or DP_EXIT_INPUT after printing one error line. */
int cli_parse(const char *cmd, const char *synopsis, int argc, char **argv, int first, const cli_opt *opts,
	      size_t nopts, const char **positional, size_t max_pos, size_t *npos, int *help);
void cli_usage(FILE *out, const char *cmd, const char *synopsis, const cli_opt *opts, size_t nopts);

/* The library's report writer (io/json.h), under the short names the
 * commands have always used. */
#define json_writer dp_json_writer
#define json_begin dp_json_begin
#define json_object dp_json_object
#define json_end_object dp_json_end_object
#define json_array dp_json_array
#define json_end_array dp_json_end_array
#define json_num dp_json_num
#define json_int dp_json_int
#define json_str dp_json_str
#define json_bool dp_json_bool
#define json_finish dp_json_finish

int dp_cmd_devices(int argc, char **argv);
int dp_cmd_wlop(int argc, char **argv);
int dp_cmd_consolidate(int argc, char **argv);
int dp_cmd_scan(int argc, char **argv);
int dp_cmd_eval(int argc, char **argv);
int dp_cmd_render(int argc, char **argv);
int dp_cmd_demo(int argc, char **argv);

#endif
