#include "io/io.h"

#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define XYZ_MAX_COLUMNS 16

typedef enum column {
	COL_SKIP,
	COL_X, COL_Y, COL_Z,
	COL_NX, COL_NY, COL_NZ,
	COL_R, COL_G, COL_B,
	COL_I
} column;

static const struct {
	const char *name;
	column col;
} column_names[] = {
	{"x", COL_X},	  {"y", COL_Y},	    {"z", COL_Z},    {"nx", COL_NX},	      {"ny", COL_NY},
	{"nz", COL_NZ},	  {"r", COL_R},	    {"g", COL_G},    {"b", COL_B},	      {"red", COL_R},
	{"green", COL_G}, {"blue", COL_B},  {"i", COL_I},    {"intensity", COL_I}, {"_", COL_SKIP},
	{"skip", COL_SKIP},
};

#define COLUMNS_HELP "x,y,z,nx,ny,nz,r,g,b,i and _ for a column to ignore"

/* "x,y,z,r,g,b" into map[]; x, y, z once each, normals and colours all
 * three or none. */
static dp_status parse_columns(const char *path, const char *spec, column *map, int *count, dp_error *err)
{
	int seen[COL_I + 1] = {0}, n = 0;
	const char *s = spec;
	for (;;) {
		const char *comma = strchr(s, ',');
		size_t len = comma ? (size_t)(comma - s) : strlen(s);
		size_t k = 0;
		while (k < sizeof column_names / sizeof column_names[0] &&
		       !(strlen(column_names[k].name) == len && strncmp(column_names[k].name, s, len) == 0))
			k++;
		if (k == sizeof column_names / sizeof column_names[0])
			return dp_fail(err, DP_ERR_ARG, "%s: --columns '%s': unknown column '%.*s' (names: " COLUMNS_HELP ")",
				       path, spec, (int)len, s);
		if (n == XYZ_MAX_COLUMNS)
			return dp_fail(err, DP_ERR_ARG, "%s: --columns '%s': more than %d columns", path, spec,
				       XYZ_MAX_COLUMNS);
		column c = column_names[k].col;
		if (c != COL_SKIP && seen[c]++)
			return dp_fail(err, DP_ERR_ARG, "%s: --columns '%s': '%.*s' named twice", path, spec, (int)len, s);
		map[n++] = c;
		if (!comma)
			break;
		s = comma + 1;
	}
	if (!seen[COL_X] || !seen[COL_Y] || !seen[COL_Z])
		return dp_fail(err, DP_ERR_ARG, "%s: --columns '%s' must name x, y and z", path, spec);
	int nn = seen[COL_NX] + seen[COL_NY] + seen[COL_NZ], nc = seen[COL_R] + seen[COL_G] + seen[COL_B];
	if (nn != 0 && nn != 3)
		return dp_fail(err, DP_ERR_ARG, "%s: --columns '%s' must name all of nx, ny, nz or none", path, spec);
	if (nc != 0 && nc != 3)
		return dp_fail(err, DP_ERR_ARG, "%s: --columns '%s' must name all of r, g, b or none", path, spec);
	*count = n;
	return DP_OK;
}

/* What three columns hold, judged over every row: normals have unit length;
 * colours are integers 0-255, or in [0, 1] without unit length. */
typedef enum triple_kind { TRIPLE_NORMAL, TRIPLE_COLOUR, TRIPLE_UNKNOWN } triple_kind;

static triple_kind classify(const float *rows, size_t n, int width, int first)
{
	size_t units = 0;
	int bytes = 1, unit_range = 1, finite = 1;
	for (size_t i = 0; i < n; i++) {
		const float *v = rows + i * (size_t)width + first;
		double len = sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
		units += fabs(len - 1.0) < 0.02;
		for (int k = 0; k < 3; k++) {
			finite &= isfinite(v[k]) != 0;
			bytes &= v[k] >= 0.0f && v[k] <= 255.0f && v[k] == floorf(v[k]);
			unit_range &= v[k] >= 0.0f && v[k] <= 1.0f;
		}
	}
	/* a non-finite value is reported as a bad normal by the finite check */
	if (units == n || !finite)
		return TRIPLE_NORMAL;
	if (bytes || unit_range)
		return TRIPLE_COLOUR;
	/* estimated normals of real scans have the odd zero vector */
	if (units >= n - n / 10)
		return TRIPLE_NORMAL;
	return TRIPLE_UNKNOWN;
}

/* The columns of a `width`-column file whose columns were not named. */
static dp_status detect(const char *path, const float *rows, size_t n, int width, column *map, dp_error *err)
{
	static const column xyz[3] = {COL_X, COL_Y, COL_Z}, normal[3] = {COL_NX, COL_NY, COL_NZ},
			    rgb[3] = {COL_R, COL_G, COL_B};
	memcpy(map, xyz, sizeof xyz);
	/* triples after x y z (and after an intensity column where there is one) */
	int first = width == 4 || width == 7 || width == 10 ? 4 : 3;
	if (first == 4)
		map[3] = COL_I;
	if (width < 3 || width > 10 || (width - first) % 3 != 0)
		return dp_fail(err, DP_ERR_FORMAT,
			       "%s: %d columns: expected x y z [intensity] [nx ny nz] [r g b] (3, 4, 6, 7, 9 or 10 columns); "
			       "name them with --columns (" COLUMNS_HELP ")",
			       path, width);
	int normals = 0, colours = 0;
	for (int t = first; t < width; t += 3) {
		triple_kind kind = classify(rows, n, width, t);
		if (kind == TRIPLE_UNKNOWN || (kind == TRIPLE_NORMAL ? normals : colours))
			return dp_fail(err, DP_ERR_FORMAT,
				       "%s: cannot tell what columns %d-%d hold (normals have unit length, colours are "
				       "integers 0-255 or in [0, 1]); name them with --columns, e.g. x,y,z,nx,ny,nz or x,y,z,r,g,b",
				       path, t + 1, t + 3);
		memcpy(map + t, kind == TRIPLE_NORMAL ? normal : rgb, sizeof normal);
		normals += kind == TRIPLE_NORMAL;
		colours += kind == TRIPLE_COLOUR;
	}
	return DP_OK;
}

/* Rows held back until the columns are decided: enough to judge them, few
 * enough that a file of a billion points is not held twice. */
#define XYZ_DETECT_ROWS 65536

typedef struct xyz_reader {
	dp_io_stream *s;
	dp_io_builder *b;
	column map[XYZ_MAX_COLUMNS];
	int named, width, decided;
	int at[COL_I + 1];  /* column of each role, or -1 */
	float scale;        /* 255 for colours given in [0, 1] */
	float *rows;        /* the first rows, until decided */
	size_t n, cap;
} xyz_reader;

static dp_status add_row(xyz_reader *x, const float *v, int streamed, dp_error *err)
{
	const int *at = x->at;
	float normal[3] = {0, 0, 0};
	if (at[COL_NX] >= 0) {
		normal[0] = v[at[COL_NX]];
		normal[1] = v[at[COL_NY]];
		normal[2] = v[at[COL_NZ]];
	}
	dp_status st = dp_io_builder_add(x->b, v[at[COL_X]], v[at[COL_Y]], v[at[COL_Z]], normal, err);
	if (st == DP_OK && at[COL_I] >= 0)
		dp_io_builder_set_intensity(x->b, x->b->c.n - 1, v[at[COL_I]]);
	if (st != DP_OK || at[COL_R] < 0)
		return st;
	unsigned char rgb[3];
	for (int c = 0; c < 3; c++) {
		float value = v[at[COL_R + c]];
		/* detected colours must stay colours: a later row that is not one
		 * means the first rows misled the guess */
		if (streamed && !x->named && !(value >= 0.0f && value * x->scale <= 255.0f))
			return dp_fail(err, DP_ERR_FORMAT,
				       "%s: line %zu: columns %d-%d held colours in the first %d rows but not here; name "
				       "them with --columns",
				       x->s->path, x->s->line, at[COL_R] + 1, at[COL_R] + 3, XYZ_DETECT_ROWS);
		value *= x->scale;
		rgb[c] = (unsigned char)(value > 255.0f ? 255.0f : value > 0.0f ? value + 0.5f : 0.0f);
	}
	dp_io_builder_set_rgb(x->b, x->b->c.n - 1, rgb);
	return DP_OK;
}

/* Decides the columns from the rows held back, then adds them. */
static dp_status decide(xyz_reader *x, dp_error *err)
{
	dp_status st;
	if (!x->named && (st = detect(x->s->path, x->rows, x->n, x->width, x->map, err)) != DP_OK)
		return st;
	for (int c = 0; c <= COL_I; c++)
		x->at[c] = -1;
	for (int c = 0; c < x->width; c++)
		x->at[x->map[c]] = c;
	x->scale = 1.0f;
	if (x->at[COL_R] >= 0) {
		/* colours in [0, 1] (every value of the columns) are scaled to bytes */
		x->scale = 255.0f;
		for (size_t i = 0; i < x->n && x->scale > 1.0f; i++)
			for (int c = COL_R; c <= COL_B; c++)
				if (x->rows[i * (size_t)x->width + x->at[c]] > 1.0f)
					x->scale = 1.0f;
		if ((st = dp_io_builder_want_colours(x->b, err)) != DP_OK)
			return st;
	}
	if (x->at[COL_NX] >= 0 && (st = dp_io_builder_want_normals(x->b, err)) != DP_OK)
		return st;
	if (x->at[COL_I] >= 0 && (st = dp_io_builder_want_intensity(x->b, err)) != DP_OK)
		return st;
	if ((st = dp_io_builder_reserve(x->b, x->n, err)) != DP_OK)
		return st;
	for (size_t i = 0; i < x->n; i++)
		if ((st = add_row(x, x->rows + i * (size_t)x->width, 0, err)) != DP_OK)
			return st;
	free(x->rows);
	x->rows = NULL;
	x->decided = 1;
	return DP_OK;
}

static dp_status hold_row(xyz_reader *x, const float *v, dp_error *err)
{
	if (x->n == x->cap) {
		size_t grown = x->cap ? 2 * x->cap : 1024;
		float *more = realloc(x->rows, grown * (size_t)x->width * sizeof *more);
		if (!more)
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory reading %zu points", x->s->path, grown);
		x->rows = more;
		x->cap = grown;
	}
	memcpy(x->rows + x->n * (size_t)x->width, v, (size_t)x->width * sizeof *v);
	x->n++;
	return x->n == XYZ_DETECT_ROWS ? decide(x, err) : DP_OK;
}

/* Whitespace-separated columns, one point a line; `#` starts a comment. Every
 * line must have the column count of the first. A line holding one whole
 * number is a point count (Leica PTS files start with one, and concatenated
 * scans have one each) and is skipped. */
dp_status dp_io_read_xyz(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err)
{
	xyz_reader x;
	memset(&x, 0, sizeof x);
	x.s = s;
	x.b = b;
	(void)flags;
	dp_status st = DP_OK;
	if (s->columns && (st = parse_columns(s->path, s->columns, x.map, &x.named, err)) != DP_OK)
		return st;
	for (;;) {
		char *line, *cur;
		float v[XYZ_MAX_COLUMNS];
		int k = 0, r = 0;
		if ((st = dp_io_line(s, &line, err)) != DP_OK)
			break;
		if (!line) {
			if (!x.decided && x.n > 0)
				st = decide(&x, err);
			break;
		}
		dp_io_strip_comment(line, '#');
		cur = line;
		while (k < XYZ_MAX_COLUMNS && (r = dp_io_scan_float(&cur, &v[k])) == 1)
			k++;
		if (r < 0) {
			st = dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: column %d is not a number", s->path, s->line, k + 1);
			break;
		}
		if (k == 0)
			continue;
		int extra = dp_io_scan_skip(&cur);
		if (k == 1 && !extra && v[0] >= 0.0f && v[0] == floorf(v[0]))
			continue;
		if (x.width == 0) {
			if (extra) {
				st = dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: more than %d columns", s->path, s->line,
					     XYZ_MAX_COLUMNS);
				break;
			}
			if (x.named && k != x.named) {
				st = dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: %d columns but --columns names %d", s->path,
					     s->line, k, x.named);
				break;
			}
			if (k < 3) {
				st = dp_fail(err, DP_ERR_FORMAT,
					     "%s: line %zu: expected at least 3 columns (x y z [nx ny nz] [r g b]), found %d",
					     s->path, s->line, k);
				break;
			}
			x.width = k;
		} else if (extra || k != x.width) {
			st = dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: %s%d columns where the first point has %d",
				     s->path, s->line, extra ? "more than " : "", k, x.width);
			break;
		}
		if ((st = x.decided ? add_row(&x, v, 1, err) : hold_row(&x, v, err)) != DP_OK)
			break;
	}
	free(x.rows);
	return st;
}
