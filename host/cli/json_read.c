/* A small JSON reader for the reports the tool itself wrote: `summary` merges
 * them and `--skip-done` checks them, so a folder is judged by what its run
 * recorded rather than by guessing from file names. */
#include "cli/json_read.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

typedef struct parser {
	const char *s, *end;
	int depth;
} parser;

static void skip_ws(parser *p)
{
	while (p->s < p->end && isspace((unsigned char)*p->s))
		p->s++;
}

static dp_json *node(dp_json_type type)
{
	dp_json *v = calloc(1, sizeof *v);
	if (v)
		v->type = type;
	return v;
}

/* Escapes other than \" \\ \/ \n \t become '?': reports hold paths and
 * messages, and a wrong byte there is better than refusing the report. */
static char *parse_string(parser *p)
{
	if (p->s >= p->end || *p->s != '"')
		return NULL;
	p->s++;
	size_t cap = 16, len = 0;
	char *out = malloc(cap);
	while (out && p->s < p->end && *p->s != '"') {
		char c = *p->s++;
		if (c == '\\' && p->s < p->end) {
			char e = *p->s++;
			c = e == 'n' ? '\n' : e == 't' ? '\t' : (e == '"' || e == '\\' || e == '/') ? e : '?';
			if (e == 'u')
				p->s += p->end - p->s >= 4 ? 4 : p->end - p->s;
		}
		if (len + 2 > cap) {
			char *grown = realloc(out, cap *= 2);
			if (!grown) {
				free(out);
				return NULL;
			}
			out = grown;
		}
		out[len++] = c;
	}
	if (!out || p->s >= p->end) {
		free(out);
		return NULL;
	}
	p->s++;
	out[len] = '\0';
	return out;
}

static dp_json *parse_value(parser *p);

/* Members (objects) or items (arrays), appended in order. */
static dp_json *parse_list(parser *p, dp_json_type type, char close)
{
	dp_json *v = node(type), **tail = v ? &v->child : NULL;
	if (!v)
		return NULL;
	p->s++;
	skip_ws(p);
	if (p->s < p->end && *p->s == close) {
		p->s++;
		return v;
	}
	for (;;) {
		char *key = NULL;
		skip_ws(p);
		if (type == DP_JSON_OBJECT) {
			if (!(key = parse_string(p)))
				break;
			skip_ws(p);
			if (p->s >= p->end || *p->s != ':') {
				free(key);
				break;
			}
			p->s++;
		}
		dp_json *item = parse_value(p);
		if (!item) {
			free(key);
			break;
		}
		item->key = key;
		*tail = item;
		tail = &item->next;
		skip_ws(p);
		if (p->s < p->end && *p->s == ',') {
			p->s++;
			continue;
		}
		if (p->s < p->end && *p->s == close) {
			p->s++;
			return v;
		}
		break;
	}
	dp_json_free(v);
	return NULL;
}

static dp_json *parse_value(parser *p)
{
	skip_ws(p);
	if (p->s >= p->end || p->depth > 64)
		return NULL;
	char c = *p->s;
	dp_json *v = NULL;
	if (c == '{' || c == '[') {
		p->depth++;
		v = parse_list(p, c == '{' ? DP_JSON_OBJECT : DP_JSON_ARRAY, c == '{' ? '}' : ']');
		p->depth--;
	} else if (c == '"') {
		char *s = parse_string(p);
		if (s && !(v = node(DP_JSON_STRING)))
			free(s);
		else if (v)
			v->string = s;
	} else if (p->end - p->s >= 4 && strncmp(p->s, "true", 4) == 0) {
		p->s += 4;
		if ((v = node(DP_JSON_BOOL)))
			v->number = 1;
	} else if (p->end - p->s >= 5 && strncmp(p->s, "false", 5) == 0) {
		p->s += 5;
		v = node(DP_JSON_BOOL);
	} else if (p->end - p->s >= 4 && strncmp(p->s, "null", 4) == 0) {
		p->s += 4;
		v = node(DP_JSON_NULL);
	} else if (c == '-' || isdigit((unsigned char)c)) {
		char buf[64];
		size_t n = 0;
		while (p->s + n < p->end && n < sizeof buf - 1 && strchr("+-.0123456789eE", p->s[n]))
			n++;
		memcpy(buf, p->s, n);
		buf[n] = '\0';
		char *end;
		double d = strtod(buf, &end);
		if (end == buf + n && (v = node(DP_JSON_NUMBER))) {
			v->number = d;
			p->s += n;
		}
	}
	return v;
}

dp_json *dp_json_parse(const char *text, size_t len)
{
	parser p = {text, text + len, 0};
	dp_json *v = parse_value(&p);
	skip_ws(&p);
	if (v && p.s != p.end) {
		dp_json_free(v);
		return NULL;
	}
	return v;
}

dp_json *dp_json_read_file(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	size_t cap = 1 << 16, len = 0, got;
	char *buf = malloc(cap);
	int bad = !buf;
	while (!bad && (got = fread(buf + len, 1, cap - len, f)) > 0) {
		len += got;
		if (len < cap)
			continue;
		/* reports are a few kilobytes: anything past 64 MiB is not one */
		char *grown = cap < (64u << 20) ? realloc(buf, cap * 2) : NULL;
		if (!grown)
			bad = 1;
		else
			buf = grown, cap *= 2;
	}
	bad |= ferror(f);
	fclose(f);
	dp_json *v = bad ? NULL : dp_json_parse(buf, len);
	free(buf);
	return v;
}

void dp_json_free(dp_json *v)
{
	while (v) {
		dp_json *next = v->next;
		dp_json_free(v->child);
		free(v->key);
		free(v->string);
		free(v);
		v = next;
	}
}

const dp_json *dp_json_get(const dp_json *v, const char *path)
{
	while (v && *path) {
		const char *dot = strchr(path, '.');
		size_t len = dot ? (size_t)(dot - path) : strlen(path);
		if (v->type != DP_JSON_OBJECT)
			return NULL;
		const dp_json *m = v->child;
		while (m && !(strlen(m->key) == len && strncmp(m->key, path, len) == 0))
			m = m->next;
		v = m;
		path += len + (dot != NULL);
	}
	return v;
}

double dp_json_number(const dp_json *v, const char *path, double fallback)
{
	v = dp_json_get(v, path);
	return v && (v->type == DP_JSON_NUMBER || v->type == DP_JSON_BOOL) ? v->number : fallback;
}

const char *dp_json_string(const dp_json *v, const char *path)
{
	v = dp_json_get(v, path);
	return v && v->type == DP_JSON_STRING ? v->string : NULL;
}

static void write_string(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"' || *s == '\\')
			fprintf(f, "\\%c", *s);
		else if ((unsigned char)*s < 0x20)
			fprintf(f, "\\u%04x", *s);
		else
			fputc(*s, f);
	}
	fputc('"', f);
}

void dp_json_write_compact(FILE *f, const dp_json *v)
{
	switch (v->type) {
	case DP_JSON_NULL:
		fputs("null", f);
		break;
	case DP_JSON_BOOL:
		fputs(v->number ? "true" : "false", f);
		break;
	case DP_JSON_NUMBER:
		fprintf(f, "%.10g", v->number);
		break;
	case DP_JSON_STRING:
		write_string(f, v->string);
		break;
	case DP_JSON_OBJECT:
	case DP_JSON_ARRAY:
		fputc(v->type == DP_JSON_OBJECT ? '{' : '[', f);
		for (const dp_json *m = v->child; m; m = m->next) {
			if (m != v->child)
				fputc(',', f);
			if (v->type == DP_JSON_OBJECT) {
				write_string(f, m->key);
				fputc(':', f);
			}
			dp_json_write_compact(f, m);
		}
		fputc(v->type == DP_JSON_OBJECT ? '}' : ']', f);
		break;
	}
}

void dp_json_write_string(FILE *f, const char *s)
{
	if (s)
		write_string(f, s);
	else
		fputs("null", f);
}
