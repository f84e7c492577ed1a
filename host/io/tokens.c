#include "io/io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* Newlines never reach here: lines come without them. */
static int is_space(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

static char *skip_space(char *p)
{
	while (is_space(*p))
		p++;
	return p;
}

/* A number ends at whitespace or the end of the line; "1.5abc" is no number. */
static int ends_token(const char *end)
{
	return *end == '\0' || is_space(*end);
}

int dp_io_scan_float(char **cur, float *value)
{
	char *p = skip_space(*cur), *end;
	*cur = p;
	if (!*p)
		return 0;
	float v = strtof(p, &end);
	if (end == p || !ends_token(end))
		return -1;
	*value = v;
	*cur = end;
	return 1;
}

int dp_io_scan_int(char **cur, long long *value)
{
	char *p = skip_space(*cur), *end;
	*cur = p;
	if (!*p)
		return 0;
	errno = 0;
	long long v = strtoll(p, &end, 10);
	if (end == p || !ends_token(end) || errno == ERANGE)
		return -1;
	*value = v;
	*cur = end;
	return 1;
}

int dp_io_scan_skip(char **cur)
{
	char *p = skip_space(*cur);
	if (!*p) {
		*cur = p;
		return 0;
	}
	while (*p && !is_space(*p))
		p++;
	*cur = p;
	return 1;
}

int dp_io_parse_count(const char *text, uint64_t *count)
{
	char *end;
	if (*text < '0' || *text > '9')
		return 0;
	errno = 0;
	unsigned long long v = strtoull(text, &end, 10);
	if (*end || errno == ERANGE)
		return 0;
	*count = v;
	return 1;
}

void dp_io_strip_comment(char *line, char comment)
{
	char *c = strchr(line, comment);
	if (c)
		*c = '\0';
}

int dp_io_split(char *line, char **tokens, int max)
{
	int n = 0;
	char *p = line;
	for (;;) {
		p = skip_space(p);
		if (!*p)
			return n;
		if (n == max)
			return max + 1;
		tokens[n++] = p;
		while (*p && !is_space(*p))
			p++;
		if (*p)
			*p++ = '\0';
	}
}

dp_status dp_io_tokens_next(dp_io_tokens *t, int *more, dp_error *err)
{
	for (;;) {
		if (t->cur) {
			t->cur = skip_space(t->cur);
			if (*t->cur) {
				*more = 1;
				return DP_OK;
			}
		}
		dp_status st = dp_io_line(t->s, &t->cur, err);
		if (st != DP_OK)
			return st;
		if (!t->cur) {
			*more = 0;
			return DP_OK;
		}
	}
}
