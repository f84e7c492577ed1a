/* Batches at scale, built on existing tools rather than a scheduler of our
 * own: a Slurm job array or GNU parallel starts one `consolidate --shard I/N`
 * per machine, every shard reads the same list and so names the same
 * folders, and --skip-done makes a resubmission redo only what is missing. */
#include "cli/batch.h"
#include "cli/json_read.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int dp_cli_list_add(dp_cli_list *l, const char *s)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? 2 * l->cap : 16;
		char **grown = realloc(l->items, cap * sizeof *grown);
		if (!grown)
			return -1;
		l->items = grown;
		l->cap = cap;
	}
	if (!(l->items[l->n] = strdup(s)))
		return -1;
	l->n++;
	return 0;
}

void dp_cli_list_free(dp_cli_list *l)
{
	for (size_t i = 0; i < l->n; i++)
		free(l->items[i]);
	free(l->items);
	memset(l, 0, sizeof *l);
}

int dp_cli_read_input_list(const char *cmd, const char *path, dp_cli_list *inputs)
{
	int is_stdin = strcmp(path, "-") == 0;
	FILE *f = is_stdin ? stdin : fopen(path, "r");
	if (!f) {
		fprintf(stderr, "dpoints %s: --inputs %s: cannot open: %s\n", cmd, path, strerror(errno));
		return DP_EXIT_INPUT;
	}
	char *line = NULL;
	size_t cap = 0, before = inputs->n;
	ssize_t len;
	int rc = 0;
	while (!rc && (len = getline(&line, &cap, f)) >= 0) {
		char *s = line, *e = line + len;
		while (s < e && isspace((unsigned char)*s))
			s++;
		while (e > s && isspace((unsigned char)e[-1]))
			e--;
		*e = '\0';
		if (*s == '\0' || *s == '#')
			continue;
		if (dp_cli_list_add(inputs, s)) {
			fprintf(stderr, "dpoints %s: --inputs %s: out of memory\n", cmd, path);
			rc = DP_EXIT_NOMEM;
		}
	}
	if (!rc && ferror(f)) {
		fprintf(stderr, "dpoints %s: --inputs %s: read error: %s\n", cmd, path, strerror(errno));
		rc = DP_EXIT_INPUT;
	}
	free(line);
	if (!is_stdin)
		fclose(f);
	if (!rc && inputs->n == before) {
		fprintf(stderr, "dpoints %s: --inputs %s: no input paths in the list\n", cmd, path);
		rc = DP_EXIT_INPUT;
	}
	return rc;
}

/* A whole non-negative decimal number, or -1. */
static long long whole(const char *s)
{
	if (!s || !isdigit((unsigned char)*s))
		return -1;
	char *end;
	errno = 0;
	long long v = strtoll(s, &end, 10);
	return *end || errno ? -1 : v;
}

int dp_cli_shard(const char *cmd, const char *text, size_t *index, size_t *count)
{
	*index = 0;
	*count = 1;
	if (text) {
		char buf[64];
		snprintf(buf, sizeof buf, "%s", text);
		char *slash = strchr(buf, '/');
		long long i = -1, n = -1;
		if (slash) {
			*slash = '\0';
			i = whole(buf);
			n = whole(slash + 1);
		}
		if (i < 0 || n < 1 || i >= n) {
			fprintf(stderr, "dpoints %s: --shard: '%s' is not I/N with 0 <= I < N (see dpoints %s --help)\n",
				cmd, text, cmd);
			return DP_EXIT_INPUT;
		}
		*index = (size_t)i;
		*count = (size_t)n;
		return 0;
	}
	const char *id_s = getenv("SLURM_ARRAY_TASK_ID"), *count_s = getenv("SLURM_ARRAY_TASK_COUNT");
	if (!id_s || !count_s)
		return 0;
	const char *min_s = getenv("SLURM_ARRAY_TASK_MIN"), *step_s = getenv("SLURM_ARRAY_TASK_STEP");
	long long id = whole(id_s), n = whole(count_s), min = min_s ? whole(min_s) : 0, step = step_s ? whole(step_s) : 1;
	long long i = id >= 0 && min >= 0 && step >= 1 && id >= min && (id - min) % step == 0 ? (id - min) / step : -1;
	if (n < 1 || i < 0 || i >= n) {
		fprintf(stderr,
			"dpoints %s: SLURM_ARRAY_TASK_ID=%s (min %s, step %s) and SLURM_ARRAY_TASK_COUNT=%s do not "
			"give a shard I/N with 0 <= I < N; give --shard I/N\n",
			cmd, id_s, min_s ? min_s : "0", step_s ? step_s : "1", count_s);
		return DP_EXIT_INPUT;
	}
	*index = (size_t)i;
	*count = (size_t)n;
	return 0;
}

static int file_nonempty(const char *dir, const char *name)
{
	char path[4096];
	struct stat sb;
	snprintf(path, sizeof path, "%s/%s", dir, name);
	return stat(path, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > 0;
}

int dp_cli_result_done(const char *dir, const char *input)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/report.json", dir);
	dp_json *report = dp_json_read_file(path);
	if (!report)
		return 0;
	const char *named = dp_json_string(report, "input");
	const dp_json *files = dp_json_get(report, "files");
	/* a report from before reports listed their files: its three PLY files */
	static const char *const core[] = {"surface.ply", "skeleton.ply", "dpoints.ply"};
	int done = named && strcmp(named, input) == 0;
	if (done && files && files->type == DP_JSON_ARRAY) {
		for (const dp_json *f = files->child; f && done; f = f->next)
			done = f->type == DP_JSON_STRING && !strchr(f->string, '/') && file_nonempty(dir, f->string);
	} else {
		for (size_t k = 0; k < 3 && done; k++)
			done = file_nonempty(dir, core[k]);
	}
	dp_json_free(report);
	return done;
}

int dp_cli_device_list(const char *cmd, const char *spec, dp_cli_list *devices)
{
	if (!spec || !*spec)
		spec = getenv("DPOINTS_DEVICE");
	if (!spec || !*spec || (strcmp(spec, "all") != 0 && !strchr(spec, ','))) {
		/* one worker on the device dp_context_create picks */
		if (dp_cli_list_add(devices, spec ? spec : ""))
			goto nomem;
		return 0;
	}
	if (strcmp(spec, "all") == 0) {
		dp_device_info *list = NULL;
		size_t n = 0;
		dp_error err = {0};
		if (dp_devices(&list, &n, &err) != DP_OK) {
			fprintf(stderr, "dpoints %s: --device all: %s\n", cmd, err.message);
			return dp_cli_exit_code(err.status);
		}
		dp_devices_free(list);
		if (n == 0) {
			fprintf(stderr, "dpoints %s: --device all: no OpenCL device found (dpoints devices lists them)\n",
				cmd);
			return DP_EXIT_DEVICE;
		}
		for (size_t i = 0; i < n; i++) {
			char index[32];
			snprintf(index, sizeof index, "%zu", i);
			if (dp_cli_list_add(devices, index))
				goto nomem;
		}
		return 0;
	}
	const char *s = spec;
	for (;;) {
		const char *comma = strchr(s, ',');
		size_t len = comma ? (size_t)(comma - s) : strlen(s);
		char item[256];
		if (len == 0 || len >= sizeof item) {
			fprintf(stderr, "dpoints %s: --device: '%s' has an empty or overlong entry (a list is like 0,1)\n",
				cmd, spec);
			return DP_EXIT_INPUT;
		}
		memcpy(item, s, len);
		item[len] = '\0';
		if (dp_cli_list_add(devices, item))
			goto nomem;
		if (!comma)
			return 0;
		s = comma + 1;
	}
nomem:
	fprintf(stderr, "dpoints %s: out of memory\n", cmd);
	return DP_EXIT_NOMEM;
}

void dp_cli_failure_path(const char *dir, char *out, size_t size)
{
	size_t len = strlen(dir);
	while (len > 1 && dir[len - 1] == '/')
		len--;
	snprintf(out, size, "%.*s.failed.json", (int)len, dir);
}

typedef struct failure_arg {
	const char *dir, *input, *device, *error;
} failure_arg;

static void fill_failure(json_writer *w, const void *varg)
{
	const failure_arg *a = varg;
	json_object(w, NULL);
	json_str(w, "command", "consolidate");
	json_str(w, "input", a->input);
	json_str(w, "output", a->dir);
	json_str(w, "device", a->device ? a->device : "");
	json_str(w, "error", a->error);
	json_end_object(w);
}

int dp_cli_write_failure(const char *cmd, const char *dir, const char *input, const char *device, const char *error)
{
	char path[4096];
	dp_cli_failure_path(dir, path, sizeof path);
	failure_arg a = {dir, input, device, error};
	return cli_write_json(cmd, path, fill_failure, &a);
}

void dp_cli_clear_failure(const char *dir)
{
	char path[4096];
	dp_cli_failure_path(dir, path, sizeof path);
	unlink(path);
}
