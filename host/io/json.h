/* A tiny JSON writer for reports: keys in order, numbers with full precision.
 * Internal to the library and the tool. */
#ifndef DP_IO_JSON_H
#define DP_IO_JSON_H

#include "dpoints.h"

#include <stdio.h>

typedef struct dp_json_writer {
	FILE *f;
	int depth;
	int first[16];
} dp_json_writer;

void dp_json_begin(dp_json_writer *w, FILE *f);
void dp_json_object(dp_json_writer *w, const char *key); /* key NULL inside arrays / at top */
void dp_json_end_object(dp_json_writer *w);
void dp_json_array(dp_json_writer *w, const char *key);
void dp_json_end_array(dp_json_writer *w);
void dp_json_num(dp_json_writer *w, const char *key, double v);
void dp_json_int(dp_json_writer *w, const char *key, long long v);
void dp_json_str(dp_json_writer *w, const char *key, const char *v);
void dp_json_bool(dp_json_writer *w, const char *key, int v);
void dp_json_finish(dp_json_writer *w);

/* Parameter blocks of reports, shared by report.json and the tool's wlop report. */
void dp_json_wlop_params(dp_json_writer *w, const dp_wlop_params *p);
void dp_json_normal_params(dp_json_writer *w, const dp_normal_params *p);

#endif
