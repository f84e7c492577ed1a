#include "cli/batch_run.h"
#include "cli/cli.h"

#include <string.h>

static const struct {
	const char *name;
	int (*run)(int argc, char **argv);
	const char *summary;
} commands[] = {
	{"demo", dp_cmd_demo, "scan a built-in shape, consolidate, evaluate and render it"},
	{"consolidate", dp_cmd_consolidate, "the whole pipeline: raw scan -> surface, skeleton, deep points"},
	{"wlop", dp_cmd_wlop, "WLOP consolidation with oriented normals (stage 1)"},
	{"scan", dp_cmd_scan, "virtual range scan of a mesh or a built-in shape"},
	{"eval", dp_cmd_eval, "accuracy, completeness, coverage, normals against a ground-truth mesh"},
	{"render", dp_cmd_render, "render point sets and deep points to a PNG"},
	{"summary", dp_cmd_summary, "one table (or JSON lines) of every consolidate report under a folder"},
	{"devices", dp_cmd_devices, "list the OpenCL platforms and devices"},
};

static void usage(FILE *out)
{
	fprintf(out, "usage: dpoints COMMAND [options]   (dpoints COMMAND --help for its options)\n"
		     "       dpoints --version\n\ncommands:\n");
	for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
		fprintf(out, "  %-12s %s\n", commands[i].name, commands[i].summary);
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return DP_EXIT_INPUT;
	}
	if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "version") == 0) {
		/* the library's version: the tool is one of its clients */
		printf("dpoints %s\n", dp_version());
		return DP_EXIT_OK;
	}
	if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
		usage(stdout);
		return DP_EXIT_OK;
	}
	for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
		if (strcmp(argv[1], commands[i].name) == 0)
			return commands[i].run(argc, argv);
	fprintf(stderr, "dpoints: unknown command '%s'\n", argv[1]);
	usage(stderr);
	return DP_EXIT_INPUT;
}
