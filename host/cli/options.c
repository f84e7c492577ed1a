#include "cli/cli.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int dp_cli_exit_code(dp_status st)
{
	switch (st) {
	case DP_OK:
		return DP_EXIT_OK;
	case DP_ERR_ARG:
	case DP_ERR_IO:
	case DP_ERR_FORMAT:
	case DP_ERR_EMPTY:
		return DP_EXIT_INPUT;
	case DP_ERR_NO_DEVICE:
	case DP_ERR_CL:
	case DP_ERR_KERNEL_BUILD:
		return DP_EXIT_DEVICE;
	case DP_ERR_NOMEM:
		return DP_EXIT_NOMEM;
	case DP_ERR_INTERNAL:
	case DP_ERR_CANCELLED: /* the tool never asks to stop; a library caller does */
		break;
	}
	return DP_EXIT_FAILURE;
}

int dp_cli_fail(const char *cmd, const dp_error *err)
{
	fprintf(stderr, "dpoints %s: %s\n", cmd, err->message[0] ? err->message : dp_status_string(err->status));
	return dp_cli_exit_code(err->status);
}

static int bad_value(const char *cmd, const char *opt, const char *value, const char *what)
{
	fprintf(stderr, "dpoints %s: %s: '%s' is not %s (see dpoints %s --help)\n", cmd, opt, value, what, cmd);
	return DP_EXIT_INPUT;
}

static int set_value(const char *cmd, const cli_opt *o, const char *v)
{
	char *end = NULL;
	errno = 0;
	switch (o->kind) {
	case CLI_STRING:
		*(const char **)o->target = v;
		return 0;
	case CLI_SIZE:
	case CLI_COUNT: {
		unsigned long long x = strtoull(v, &end, 10);
		int zero_ok = o->kind == CLI_COUNT;
		if (errno || end == v || *end || (x == 0 && !zero_ok) || strchr(v, '-') || x > SIZE_MAX)
			return bad_value(cmd, o->name, v, zero_ok ? "a non-negative integer" : "a positive integer");
		*(size_t *)o->target = (size_t)x;
		return 0;
	}
	case CLI_INT: {
		long x = strtol(v, &end, 10);
		if (errno || end == v || *end || x < INT32_MIN || x > INT32_MAX)
			return bad_value(cmd, o->name, v, "an integer");
		*(int *)o->target = (int)x;
		return 0;
	}
	case CLI_U64: {
		unsigned long long x = strtoull(v, &end, 10);
		if (errno || end == v || *end || strchr(v, '-'))
			return bad_value(cmd, o->name, v, "a non-negative integer");
		*(uint64_t *)o->target = (uint64_t)x;
		return 0;
	}
	case CLI_DOUBLE: {
		double x = strtod(v, &end);
		if (errno || end == v || *end || !isfinite(x))
			return bad_value(cmd, o->name, v, "a number");
		*(double *)o->target = x;
		return 0;
	}
	case CLI_VEC3: {
		double *t = o->target, x[3];
		const char *p = v;
		for (int k = 0; k < 3; k++) {
			x[k] = strtod(p, &end);
			if (end == p || !isfinite(x[k]) || (k < 2 && *end != ',') || (k == 2 && *end))
				return bad_value(cmd, o->name, v, "three numbers X,Y,Z");
			p = end + 1;
		}
		memcpy(t, x, sizeof x);
		return 0;
	}
	case CLI_CHOICE: {
		size_t len = strlen(v);
		int index = 0;
		for (const char *c = o->choices; *c; index++) {
			const char *bar = strchr(c, '|');
			size_t clen = bar ? (size_t)(bar - c) : strlen(c);
			if (clen == len && strncmp(c, v, len) == 0) {
				*(int *)o->target = index;
				return 0;
			}
			if (!bar)
				break;
			c = bar + 1;
		}
		char what[256];
		snprintf(what, sizeof what, "one of %s", o->choices);
		return bad_value(cmd, o->name, v, what);
	}
	case CLI_FLAG:
		break;
	}
	return DP_EXIT_FAILURE;
}

int cli_parse(const char *cmd, const char *synopsis, int argc, char **argv, int first, const cli_opt *opts,
	      size_t nopts, const char **positional, size_t max_pos, size_t *npos, int *help)
{
	*npos = 0;
	*help = 0;
	for (int i = first; i < argc; i++) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			cli_usage(stdout, cmd, synopsis, opts, nopts);
			*help = 1;
			return 0;
		}
		if (a[0] != '-' || a[1] == '\0') {
			if (*npos == max_pos) {
				fprintf(stderr, "dpoints %s: unexpected argument '%s' (see dpoints %s --help)\n", cmd, a,
					cmd);
				return DP_EXIT_INPUT;
			}
			positional[(*npos)++] = a;
			continue;
		}
		char name[64];
		const char *value = NULL;
		const char *eq = strchr(a, '=');
		size_t nlen = eq ? (size_t)(eq - a) : strlen(a);
		if (nlen >= sizeof name)
			nlen = sizeof name - 1;
		memcpy(name, a, nlen);
		name[nlen] = '\0';
		if (eq)
			value = eq + 1;
		if (strcmp(name, "-o") == 0)
			snprintf(name, sizeof name, "--output");
		const cli_opt *o = NULL;
		for (size_t k = 0; k < nopts; k++)
			if (strcmp(opts[k].name, name) == 0)
				o = &opts[k];
		if (!o) {
			fprintf(stderr, "dpoints %s: unknown option '%s' (see dpoints %s --help)\n", cmd, a, cmd);
			return DP_EXIT_INPUT;
		}
		if (o->seen)
			*o->seen = 1;
		if (o->kind == CLI_FLAG) {
			/* a flag takes no value: "--quiet=0" would otherwise turn it on */
			if (value) {
				fprintf(stderr, "dpoints %s: %s takes no value, got '%s' (see dpoints %s --help)\n",
					cmd, o->name, value, cmd);
				return DP_EXIT_INPUT;
			}
			*(int *)o->target = 1;
			continue;
		}
		if (!value) {
			if (i + 1 >= argc) {
				fprintf(stderr, "dpoints %s: %s needs a value (see dpoints %s --help)\n", cmd, o->name,
					cmd);
				return DP_EXIT_INPUT;
			}
			value = argv[++i];
		}
		int rc = set_value(cmd, o, value);
		if (rc)
			return rc;
	}
	return 0;
}

static void print_default(FILE *out, const cli_opt *o)
{
	switch (o->kind) {
	case CLI_STRING: {
		const char *s = *(const char **)o->target;
		if (s)
			fprintf(out, " [default: %s]", s);
		break;
	}
	case CLI_SIZE:
		if (*(size_t *)o->target)
			fprintf(out, " [default: %zu]", *(size_t *)o->target);
		break;
	case CLI_COUNT:
		fprintf(out, " [default: %zu]", *(size_t *)o->target);
		break;
	case CLI_INT:
		fprintf(out, " [default: %d]", *(int *)o->target);
		break;
	case CLI_U64:
		fprintf(out, " [default: %llu]", (unsigned long long)*(uint64_t *)o->target);
		break;
	case CLI_DOUBLE:
		fprintf(out, " [default: %g]", *(double *)o->target);
		break;
	case CLI_CHOICE: {
		int want = *(int *)o->target, index = 0;
		const char *c = o->choices;
		while (index < want && strchr(c, '|')) {
			c = strchr(c, '|') + 1;
			index++;
		}
		const char *bar = strchr(c, '|');
		fprintf(out, " [default: %.*s]", bar ? (int)(bar - c) : (int)strlen(c), c);
		break;
	}
	case CLI_FLAG:
	case CLI_VEC3:
		break;
	}
}

void cli_usage(FILE *out, const char *cmd, const char *synopsis, const cli_opt *opts, size_t nopts)
{
	fprintf(out, "usage: dpoints %s %s\n\noptions:\n", cmd, synopsis);
	for (size_t k = 0; k < nopts; k++) {
		const cli_opt *o = &opts[k];
		const char *arg = o->kind == CLI_FLAG     ? ""
				  : o->kind == CLI_VEC3   ? " X,Y,Z"
				  : o->kind == CLI_CHOICE ? " CHOICE"
				  : o->kind == CLI_STRING ? " VALUE"
							  : " N";
		char left[64];
		snprintf(left, sizeof left, "%s%s%s", strcmp(o->name, "--output") == 0 ? "-o, " : "", o->name, arg);
		fprintf(out, "  %-26s %s", left, o->help);
		if (o->kind == CLI_CHOICE)
			fprintf(out, " (%s)", o->choices);
		print_default(out, o);
		fputc('\n', out);
	}
	fprintf(out, "  %-26s %s\n", "-h, --help", "print this help");
}
