#ifndef DP_CLI_JSON_READ_H
#define DP_CLI_JSON_READ_H

#include <stddef.h>
#include <stdio.h>

typedef enum dp_json_type {
	DP_JSON_NULL,
	DP_JSON_BOOL,
	DP_JSON_NUMBER,
	DP_JSON_STRING,
	DP_JSON_OBJECT,
	DP_JSON_ARRAY
} dp_json_type;

/* A parsed value; members of objects and items of arrays are `child` then
 * `next` in document order, members with their `key`. */
typedef struct dp_json {
	dp_json_type type;
	char *key;
	char *string;
	double number; /* numbers, and bools as 0 / 1 */
	struct dp_json *child, *next;
} dp_json;

/* NULL when the text is not one JSON value (or memory ran out). */
dp_json *dp_json_parse(const char *text, size_t len);
dp_json *dp_json_read_file(const char *path);
void dp_json_free(dp_json *v);
/* The member at a dotted path ("results.wlop.seconds"), or NULL. */
const dp_json *dp_json_get(const dp_json *v, const char *path);
double dp_json_number(const dp_json *v, const char *path, double fallback);
const char *dp_json_string(const dp_json *v, const char *path);
/* One line, no spaces: for JSON lines and a one-object stdout. */
void dp_json_write_compact(FILE *f, const dp_json *v);
/* A quoted, escaped string, or null for NULL. */
void dp_json_write_string(FILE *f, const char *s);

#endif
