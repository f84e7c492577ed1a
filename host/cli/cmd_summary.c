/* dpoints summary DIR: every report.json (and failure record) under DIR in
 * one table, or JSON lines, so the shards of a collection that ran on many
 * machines read as one batch. */
#include "cli/batch_run.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const stages[5] = {"wlop", "normals", "sink", "skeleton", "surface"};

/* Why each stage stopped: its own test, or the iteration cap. */
static const char *stop_reason(const dp_json *report, int k)
{
	char path[64];
	if (k == 1)
		return NULL;
	if (k == 2) {
		/* reports written before the sinking's converged: the anchors' count */
		int none_unsettled = dp_json_number(report, "results.sink.unsettled", 0) == 0;
		return dp_json_number(report, "results.sink.converged", none_unsettled) ? "settled" : "cap";
	}
	snprintf(path, sizeof path, "results.%s.converged", stages[k]);
	if (!dp_json_number(report, path, 0))
		return "cap";
	return k == 0 && dp_json_number(report, "results.wlop.stalled", 0) ? "stalled" : "converged";
}

/* The count the stages ran at; reports written before 0.10 have only the
 * count kept, which was the count run. */
static double deep_points_run(const dp_json *report)
{
	double kept = dp_json_number(report, "results.deep_points", 0);
	return dp_json_number(report, "results.deep_points_run", kept);
}

static double stage_seconds(const dp_json *report, int k)
{
	char path[64];
	snprintf(path, sizeof path, "results.%s.seconds", stages[k]);
	return dp_json_number(report, path, 0);
}

void dp_cli_summary_row_json(FILE *f, const dp_json *report, const char *input, const char *output,
			     const char *device, const char *status, const char *error, int with_results)
{
	fputs("{\"input\":", f);
	dp_json_write_string(f, input);
	fputs(",\"output\":", f);
	dp_json_write_string(f, output);
	fputs(",\"device\":", f);
	dp_json_write_string(f, device);
	fputs(",\"status\":", f);
	dp_json_write_string(f, status);
	fputs(",\"error\":", f);
	dp_json_write_string(f, error);
	if (report) {
		fprintf(f, ",\"points\":%.0f,\"deep_points\":%.0f,\"deep_points_run\":%.0f,\"seconds\":{",
			dp_json_number(report, "results.points_in", 0), dp_json_number(report, "results.deep_points", 0),
			deep_points_run(report));
		for (int k = 0; k < 5; k++)
			fprintf(f, "\"%s\":%.6g,", stages[k], stage_seconds(report, k));
		fprintf(f, "\"total\":%.6g},\"stop\":{", dp_json_number(report, "results.seconds_total", 0));
		for (int k = 0, first = 1; k < 5; k++) {
			if (!stop_reason(report, k))
				continue;
			fprintf(f, "%s\"%s\":\"%s\"", first ? "" : ",", stages[k], stop_reason(report, k));
			first = 0;
		}
		fputc('}', f);
		const dp_json *results = dp_json_get(report, "results");
		if (with_results && results) {
			fputs(",\"results\":", f);
			dp_json_write_compact(f, results);
		}
	}
	fputc('}', f);
}

typedef struct found {
	char *path;
	int failure; /* a "<dir>.failed.json" record rather than a report */
} found;

typedef struct found_list {
	found *items;
	size_t n, cap;
} found_list;

static int add_found(found_list *l, const char *path, int failure)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? 2 * l->cap : 64;
		found *grown = realloc(l->items, cap * sizeof *grown);
		if (!grown)
			return -1;
		l->items = grown;
		l->cap = cap;
	}
	if (!(l->items[l->n].path = strdup(path)))
		return -1;
	l->items[l->n++].failure = failure;
	return 0;
}

static int ends_with(const char *s, const char *suffix)
{
	size_t a = strlen(s), b = strlen(suffix);
	return a >= b && strcmp(s + a - b, suffix) == 0;
}

/* Staging and old folders of a run in progress (or killed) hold reports
 * that are not results: "<name>.tmp.<pid>", "<name>.old.<pid>". */
static int transient(const char *name)
{
	const char *p = strstr(name, ".tmp.");
	if (!p)
		p = strstr(name, ".old.");
	if (!p || !p[5])
		return 0;
	for (p += 5; *p; p++)
		if (*p < '0' || *p > '9')
			return 0;
	return 1;
}

static int walk(const char *dir, found_list *out, int depth)
{
	DIR *d = opendir(dir);
	if (!d)
		return depth == 0 ? -1 : 0;
	struct dirent *e;
	int rc = 0;
	while (!rc && (e = readdir(d))) {
		if (e->d_name[0] == '.' || transient(e->d_name))
			continue;
		char path[4096];
		if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= sizeof path)
			continue;
		struct stat sb;
		if (stat(path, &sb) != 0)
			continue;
		if (S_ISDIR(sb.st_mode) && depth < 32)
			rc = walk(path, out, depth + 1);
		else if (S_ISREG(sb.st_mode) && strcmp(e->d_name, "report.json") == 0)
			rc = add_found(out, path, 0);
		else if (S_ISREG(sb.st_mode) && ends_with(e->d_name, ".failed.json"))
			rc = add_found(out, path, 1);
	}
	closedir(d);
	return rc;
}

/* "Platform / device": the device part, which is what tells devices apart. */
static const char *short_device(const char *name)
{
	const char *slash = name ? strstr(name, " / ") : NULL;
	return slash ? slash + 3 : name ? name : "-";
}

static int by_path(const void *a, const void *b)
{
	return strcmp(((const found *)a)->path, ((const found *)b)->path);
}

int dp_cmd_summary(int argc, char **argv)
{
	const char *cmd = "summary";
	int as_json = 0;
	cli_opt opts[] = {
		{"--json", CLI_FLAG, &as_json, "one JSON object a line (JSON lines) instead of the table", NULL, NULL},
	};
	const char *dirs[1];
	size_t ndirs;
	int help;
	int rc = cli_parse(cmd, "DIR [--json]", argc, argv, 2, opts, 1, dirs, 1, &ndirs, &help);
	if (rc || help)
		return rc;
	if (ndirs != 1) {
		fprintf(stderr, "dpoints %s: needs DIR, a consolidate output folder (see dpoints %s --help)\n", cmd, cmd);
		return DP_EXIT_INPUT;
	}
	found_list list = {0};
	if (walk(dirs[0], &list, 0) != 0) {
		fprintf(stderr, "dpoints %s: %s: cannot read the folder (or out of memory)\n", cmd, dirs[0]);
		rc = DP_EXIT_INPUT;
		goto done;
	}
	if (list.n == 0) {
		fprintf(stderr, "dpoints %s: %s: no report.json or .failed.json under it\n", cmd, dirs[0]);
		rc = DP_EXIT_INPUT;
		goto done;
	}
	qsort(list.items, list.n, sizeof *list.items, by_path);
	dp_json **docs = calloc(list.n, sizeof *docs);
	if (!docs) {
		fprintf(stderr, "dpoints %s: out of memory\n", cmd);
		rc = DP_EXIT_NOMEM;
		goto done;
	}
	int width = (int)strlen("input"), dwidth = (int)strlen("device");
	for (size_t i = 0; i < list.n; i++) {
		docs[i] = dp_json_read_file(list.items[i].path);
		const char *in = dp_json_string(docs[i], "input");
		const char *dev = short_device(dp_json_string(docs[i], "device"));
		int len = (int)strlen(in ? in : list.items[i].path);
		width = len > width ? len : width;
		if ((int)strlen(dev) > dwidth)
			dwidth = (int)strlen(dev);
	}
	if (!as_json)
		printf("%-*s %8s %8s %8s %-*s %34s %8s %-24s  %s\n", width, "input", "points", "dpoints", "run", dwidth,
		       "device", "seconds wlop/normals/sink/skel/surf", "total", "capped", "status");
	size_t ok = 0, failed = 0;
	double total = 0;
	for (size_t i = 0; i < list.n; i++) {
		const dp_json *doc = docs[i];
		const char *in = dp_json_string(doc, "input"), *dev = dp_json_string(doc, "device");
		const char *out = dp_json_string(doc, "output");
		const char *error = list.items[i].failure ? dp_json_string(doc, "error") : NULL;
		int good = doc && in && !list.items[i].failure && dp_json_get(doc, "results");
		if (!good && !error)
			error = doc ? "not a consolidate report" : "unreadable JSON";
		if (!in)
			in = list.items[i].path;
		good ? ok++ : failed++;
		if (as_json) {
			dp_cli_summary_row_json(stdout, good ? doc : NULL, in, out, dev, good ? "ok" : "failed", error, 0);
			fputc('\n', stdout);
			continue;
		}
		if (!good) {
			printf("%-*s %8s %8s %8s %-*s %34s %8s %-24s  FAILED: %s\n", width, in, "-", "-", "-", dwidth,
			       short_device(dev), "-", "-", "-", error);
			continue;
		}
		char secs[128], capped[64] = "";
		snprintf(secs, sizeof secs, "%.2f/%.2f/%.2f/%.2f/%.2f", stage_seconds(doc, 0), stage_seconds(doc, 1),
			 stage_seconds(doc, 2), stage_seconds(doc, 3), stage_seconds(doc, 4));
		for (int k = 0; k < 5; k++) {
			const char *why = stop_reason(doc, k);
			if (why && strcmp(why, "cap") == 0)
				snprintf(capped + strlen(capped), sizeof capped - strlen(capped), "%s%s", *capped ? "," : "",
					 stages[k]);
		}
		double t = dp_json_number(doc, "results.seconds_total", 0);
		total += t;
		printf("%-*s %8.0f %8.0f %8.0f %-*s %34s %8.2f %-24s  ok\n", width, in,
		       dp_json_number(doc, "results.points_in", 0), dp_json_number(doc, "results.deep_points", 0),
		       deep_points_run(doc), dwidth, short_device(dev), secs, t, *capped ? capped : "-");
	}
	if (!as_json)
		printf("%zu input%s: %zu ok, %zu failed; %.2f s in the pipeline\n", list.n, list.n == 1 ? "" : "s", ok,
		       failed, total);
	for (size_t i = 0; i < list.n; i++)
		dp_json_free(docs[i]);
	free(docs);
	/* a script can tell a collection with failures from a finished one */
	rc = failed ? DP_EXIT_FAILURE : 0;
done:
	for (size_t i = 0; i < list.n; i++)
		free(list.items[i].path);
	free(list.items);
	return rc;
}
