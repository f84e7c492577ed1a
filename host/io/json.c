/* The JSON writer of reports (report.json, the tool's --report and eval
 * files): keys in order, numbers with full precision, non-finite as null. */
#include "io/json.h"

#include <math.h>

static void key(dp_json_writer *w, const char *k)
{
	if (!w->first[w->depth])
		fputc(',', w->f);
	w->first[w->depth] = 0;
	if (w->depth)
		fprintf(w->f, "\n%*s", 2 * w->depth, "");
	if (k)
		fprintf(w->f, "\"%s\": ", k);
}

void dp_json_begin(dp_json_writer *w, FILE *f)
{
	w->f = f;
	w->depth = 0;
	w->first[0] = 1;
}

static void open_(dp_json_writer *w, const char *k, char c)
{
	key(w, k);
	fputc(c, w->f);
	if (w->depth < 15)
		w->depth++;
	w->first[w->depth] = 1;
}

static void close_(dp_json_writer *w, char c)
{
	int empty = w->first[w->depth];
	w->depth--;
	if (!empty)
		fprintf(w->f, "\n%*s", 2 * w->depth, "");
	fputc(c, w->f);
}

void dp_json_object(dp_json_writer *w, const char *k) { open_(w, k, '{'); }
void dp_json_end_object(dp_json_writer *w) { close_(w, '}'); }
void dp_json_array(dp_json_writer *w, const char *k) { open_(w, k, '['); }
void dp_json_end_array(dp_json_writer *w) { close_(w, ']'); }

void dp_json_num(dp_json_writer *w, const char *k, double v)
{
	key(w, k);
	if (isfinite(v))
		fprintf(w->f, "%.10g", v);
	else
		fputs("null", w->f);
}

void dp_json_int(dp_json_writer *w, const char *k, long long v)
{
	key(w, k);
	fprintf(w->f, "%lld", v);
}

void dp_json_str(dp_json_writer *w, const char *k, const char *v)
{
	key(w, k);
	fputc('"', w->f);
	for (const char *p = v; *p; p++) {
		if (*p == '"' || *p == '\\')
			fprintf(w->f, "\\%c", *p);
		else if ((unsigned char)*p < 0x20)
			fprintf(w->f, "\\u%04x", *p);
		else
			fputc(*p, w->f);
	}
	fputc('"', w->f);
}

void dp_json_bool(dp_json_writer *w, const char *k, int v)
{
	key(w, k);
	fputs(v ? "true" : "false", w->f);
}

void dp_json_finish(dp_json_writer *w)
{
	fputc('\n', w->f);
}
