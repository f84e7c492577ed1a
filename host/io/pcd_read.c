#include "io/io.h"

#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* PCL's own point types have at most a few dozen fields. */
#define PCD_MAX_FIELDS 64
/* The largest PCL point type (a VFH signature, 308 floats) is about 1.2 KB; a
 * bound far above it keeps a lying SIZE/COUNT from sizing the read buffer. */
#define PCD_MAX_POINT_BYTES 65536

/* PCD_RGB holds PCL's packed colour, 0x00RRGGBB ("rgb", a float's bits) or
 * 0xAARRGGBB ("rgba", an unsigned int): its bits travel in the float slot. */
enum pcd_role { PCD_X, PCD_Y, PCD_Z, PCD_NX, PCD_NY, PCD_NZ, PCD_RGB, PCD_I, PCD_ROLES };

static const char *const pcd_role_names[PCD_ROLES] = {"x",	  "y",	 "z",	 "normal_x",
						      "normal_y", "normal_z", "rgb", "intensity"};

enum pcd_data { PCD_NO_DATA, PCD_ASCII, PCD_BINARY };

typedef struct pcd_header {
	int nfields, nsize, ntype, ncount;
	size_t size[PCD_MAX_FIELDS];
	dp_io_kind kind[PCD_MAX_FIELDS];
	uint64_t count[PCD_MAX_FIELDS];
	int role_field[PCD_ROLES];     /* field index of each role, or -1 */
	uint64_t width, height, points;
	int have_width, have_height, have_points;
	int data;
	int normals;
} pcd_header;

static dp_status header_fail(dp_io_stream *s, const char *problem, dp_error *err)
{
	return dp_fail(err, DP_ERR_FORMAT, "%s: header line %zu: %s", s->path, s->line, problem);
}

static void parse_fields(pcd_header *h, char **tok, int ntok)
{
	h->nfields = ntok - 1;
	for (int r = 0; r < PCD_ROLES; r++)
		h->role_field[r] = -1;
	for (int i = 0; i < h->nfields; i++) {
		for (int r = 0; r < PCD_ROLES; r++)
			if (strcmp(tok[i + 1], pcd_role_names[r]) == 0)
				h->role_field[r] = i;
		if (strcmp(tok[i + 1], "rgba") == 0)
			h->role_field[PCD_RGB] = i;
	}
}

static dp_status parse_numbers(dp_io_stream *s, char **tok, int ntok, uint64_t *out, int *n,
			       const char *what, dp_error *err)
{
	char problem[64];
	*n = ntok - 1;
	for (int i = 0; i < *n; i++)
		if (!dp_io_parse_count(tok[i + 1], &out[i])) {
			snprintf(problem, sizeof problem, "bad %s value", what);
			return header_fail(s, problem, err);
		}
	return DP_OK;
}

static dp_status parse_types(dp_io_stream *s, pcd_header *h, char **tok, int ntok, dp_error *err)
{
	h->ntype = ntok - 1;
	for (int i = 0; i < h->ntype; i++) {
		if (strcmp(tok[i + 1], "F") == 0)
			h->kind[i] = DP_IO_FLOAT;
		else if (strcmp(tok[i + 1], "I") == 0)
			h->kind[i] = DP_IO_INT;
		else if (strcmp(tok[i + 1], "U") == 0)
			h->kind[i] = DP_IO_UINT;
		else
			return header_fail(s, "TYPE must be F, I or U", err);
	}
	return DP_OK;
}

static dp_status parse_data(dp_io_stream *s, pcd_header *h, char **tok, int ntok, dp_error *err)
{
	if (ntok != 2)
		return header_fail(s, "expected 'DATA ascii' or 'DATA binary'", err);
	if (strcmp(tok[1], "ascii") == 0)
		h->data = PCD_ASCII;
	else if (strcmp(tok[1], "binary") == 0)
		h->data = PCD_BINARY;
	else if (strcmp(tok[1], "binary_compressed") == 0)
		return dp_fail(err, DP_ERR_FORMAT,
			       "%s: DATA binary_compressed is unsupported; convert the file to ascii or binary "
			       "(pcl_convert_pcd_ascii_binary)", s->path);
	else
		return header_fail(s, "unknown DATA kind", err);
	return DP_OK;
}

static dp_status parse_line(dp_io_stream *s, pcd_header *h, char **tok, int ntok, dp_error *err)
{
	uint64_t v[PCD_MAX_FIELDS];
	dp_status st = DP_OK;
	const char *key = tok[0];
	if (strcasecmp(key, "VERSION") == 0 || strcasecmp(key, "VIEWPOINT") == 0)
		return DP_OK;
	if (strcasecmp(key, "FIELDS") == 0 || strcasecmp(key, "COLUMNS") == 0) {
		parse_fields(h, tok, ntok);
		return DP_OK;
	}
	if (strcasecmp(key, "SIZE") == 0) {
		if ((st = parse_numbers(s, tok, ntok, v, &h->nsize, "SIZE", err)) != DP_OK)
			return st;
		for (int i = 0; i < h->nsize; i++)
			h->size[i] = v[i];
		return DP_OK;
	}
	if (strcasecmp(key, "TYPE") == 0)
		return parse_types(s, h, tok, ntok, err);
	if (strcasecmp(key, "COUNT") == 0)
		return parse_numbers(s, tok, ntok, h->count, &h->ncount, "COUNT", err);
	if (strcasecmp(key, "DATA") == 0)
		return parse_data(s, h, tok, ntok, err);
	uint64_t *dst = NULL;
	if (strcasecmp(key, "WIDTH") == 0)
		dst = &h->width, h->have_width = 1;
	else if (strcasecmp(key, "HEIGHT") == 0)
		dst = &h->height, h->have_height = 1;
	else if (strcasecmp(key, "POINTS") == 0)
		dst = &h->points, h->have_points = 1;
	else
		return header_fail(s, "unknown keyword", err);
	if (ntok != 2 || !dp_io_parse_count(tok[1], dst))
		return header_fail(s, "expected one count", err);
	return DP_OK;
}

/* Checks the header for consistency once DATA has been seen. */
static dp_status check_header(dp_io_stream *s, pcd_header *h, dp_error *err)
{
	if (h->nfields == 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: the header has no FIELDS line", s->path);
	if (h->nsize != h->nfields || h->ntype != h->nfields)
		return dp_fail(err, DP_ERR_FORMAT, "%s: FIELDS, SIZE and TYPE list %d, %d and %d entries", s->path,
			       h->nfields, h->nsize, h->ntype);
	if (h->ncount == 0) {
		for (int i = 0; i < h->nfields; i++)
			h->count[i] = 1;
	} else if (h->ncount != h->nfields) {
		return dp_fail(err, DP_ERR_FORMAT, "%s: FIELDS lists %d entries but COUNT %d", s->path, h->nfields,
			       h->ncount);
	}
	for (int i = 0; i < h->nfields; i++) {
		size_t z = h->size[i];
		int ok = h->kind[i] == DP_IO_FLOAT ? (z == 4 || z == 8) : (z == 1 || z == 2 || z == 4 || z == 8);
		if (!ok || h->count[i] == 0 || h->count[i] > UINT32_MAX)
			return dp_fail(err, DP_ERR_FORMAT, "%s: field %d has an invalid SIZE or COUNT", s->path, i + 1);
	}
	for (int r = PCD_X; r <= PCD_Z; r++)
		if (h->role_field[r] < 0)
			return dp_fail(err, DP_ERR_FORMAT, "%s: FIELDS has no %s", s->path, pcd_role_names[r]);
	h->normals = 1;
	for (int r = PCD_NX; r <= PCD_NZ; r++)
		if (h->role_field[r] < 0)
			h->normals = 0;
	for (int r = 0; r < PCD_ROLES; r++)
		if (h->role_field[r] >= 0 && h->count[h->role_field[r]] != 1)
			return dp_fail(err, DP_ERR_FORMAT, "%s: field %s must have COUNT 1", s->path, pcd_role_names[r]);
	if (h->role_field[PCD_RGB] >= 0 && h->size[h->role_field[PCD_RGB]] != 4)
		return dp_fail(err, DP_ERR_FORMAT, "%s: field rgb/rgba must have SIZE 4 (packed colour)", s->path);
	if (h->have_width && h->have_height && h->height && h->width > UINT64_MAX / h->height)
		return dp_fail(err, DP_ERR_FORMAT, "%s: WIDTH x HEIGHT overflows", s->path);
	if (!h->have_points) {
		if (!h->have_width)
			return dp_fail(err, DP_ERR_FORMAT, "%s: the header has neither POINTS nor WIDTH", s->path);
		h->points = h->width * (h->have_height ? h->height : 1);
	} else if (h->have_width && h->have_height && h->width * h->height != h->points) {
		return dp_fail(err, DP_ERR_FORMAT, "%s: POINTS %llu differs from WIDTH x HEIGHT = %llu x %llu", s->path,
			       (unsigned long long)h->points, (unsigned long long)h->width,
			       (unsigned long long)h->height);
	}
	return DP_OK;
}

static dp_status read_header(dp_io_stream *s, pcd_header *h, dp_error *err)
{
	char *tok[PCD_MAX_FIELDS + 1];
	memset(h, 0, sizeof *h);
	while (h->data == PCD_NO_DATA) {
		char *line;
		dp_status st = dp_io_line(s, &line, err);
		if (st != DP_OK)
			return st;
		if (!line)
			return dp_fail(err, DP_ERR_FORMAT, "%s: not a PCD file (no DATA line)", s->path);
		dp_io_strip_comment(line, '#');
		int ntok = dp_io_split(line, tok, PCD_MAX_FIELDS + 1);
		if (ntok == 0)
			continue;
		if (ntok > PCD_MAX_FIELDS + 1)
			return header_fail(s, "too many fields", err);
		if ((st = parse_line(s, h, tok, ntok, err)) != DP_OK)
			return st;
	}
	return check_header(s, h, err);
}

/* A NaN position is PCL's "no return" marker for organised clouds: the point
 * is dropped. A NaN normal on a real point means "not estimated" and becomes
 * the zero vector, the same "unknown" other files use. */
static dp_status add_point(dp_io_stream *s, dp_io_builder *b, uint64_t index, const float v[PCD_ROLES],
			   dp_error *err)
{
	float normal[3] = {v[PCD_NX], v[PCD_NY], v[PCD_NZ]};
	if (isnan(v[PCD_X]) || isnan(v[PCD_Y]) || isnan(v[PCD_Z]))
		return DP_OK;
	if (isnan(normal[0]) || isnan(normal[1]) || isnan(normal[2]))
		normal[0] = normal[1] = normal[2] = 0;
	dp_status st = dp_io_check_finite(s->path, (size_t)index, v[PCD_X], v[PCD_Y], v[PCD_Z],
					  b->normals ? normal : NULL, err);
	if (st == DP_OK)
		st = dp_io_builder_add(b, v[PCD_X], v[PCD_Y], v[PCD_Z], normal, err);
	if (st == DP_OK && b->colours) {
		uint32_t packed;
		memcpy(&packed, &v[PCD_RGB], sizeof packed);
		unsigned char rgb[3] = {(unsigned char)(packed >> 16), (unsigned char)(packed >> 8), (unsigned char)packed};
		dp_io_builder_set_rgb(b, b->c.n - 1, rgb);
	}
	if (st == DP_OK && b->intensities)
		dp_io_builder_set_intensity(b, b->c.n - 1, v[PCD_I]);
	return st;
}

/* The packed colour's bits from an ascii token: a float for "rgb" of TYPE F,
 * an integer for TYPE U or I. */
static int scan_packed(char **cur, dp_io_kind kind, float *slot)
{
	uint32_t packed;
	if (kind == DP_IO_FLOAT) {
		float f;
		int r = dp_io_scan_float(cur, &f);
		if (r == 1) {
			memcpy(&packed, &f, sizeof packed);
			memcpy(slot, &packed, sizeof packed);
		}
		return r;
	}
	long long v;
	int r = dp_io_scan_int(cur, &v);
	if (r == 1) {
		packed = (uint32_t)v;
		memcpy(slot, &packed, sizeof packed);
	}
	return r;
}

static dp_status read_ascii(dp_io_stream *s, const pcd_header *h, dp_io_builder *b, dp_error *err)
{
	uint64_t done = 0;
	int field_role[PCD_MAX_FIELDS];
	for (int i = 0; i < h->nfields; i++)
		field_role[i] = -1;
	for (int r = 0; r < PCD_ROLES; r++)
		if (h->role_field[r] >= 0)
			field_role[h->role_field[r]] = r;
	while (done < h->points) {
		char *line, *cur;
		float v[PCD_ROLES] = {0};
		dp_status st = dp_io_line(s, &line, err);
		if (st != DP_OK)
			return st;
		if (!line)
			return dp_fail(err, DP_ERR_FORMAT, "%s: truncated: the file ends after %llu of %llu points",
				       s->path, (unsigned long long)done, (unsigned long long)h->points);
		cur = line;
		if (!dp_io_scan_skip(&cur))
			continue;
		cur = line;
		for (int i = 0; i < h->nfields; i++) {
			for (uint64_t c = 0; c < h->count[i]; c++) {
				int r = field_role[i] == PCD_RGB ? scan_packed(&cur, h->kind[i], &v[PCD_RGB])
					: field_role[i] >= 0	 ? dp_io_scan_float(&cur, &v[field_role[i]])
								 : dp_io_scan_skip(&cur);
				if (r == 0)
					return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: fewer values than FIELDS and COUNT describe",
						       s->path, s->line);
				if (r < 0)
					return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: %s is not a number", s->path,
						       s->line, pcd_role_names[field_role[i]]);
			}
		}
		if (dp_io_scan_skip(&cur))
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: more values than FIELDS and COUNT describe",
				       s->path, s->line);
		if ((st = add_point(s, b, done, v, err)) != DP_OK)
			return st;
		done++;
	}
	return dp_io_expect_end(s, 0, "declared POINTS", err);
}

static dp_status read_binary(dp_io_stream *s, const pcd_header *h, dp_io_builder *b, uint64_t point_size,
			     dp_error *err)
{
	size_t offset[PCD_ROLES] = {0};
	for (int r = 0; r < PCD_ROLES; r++) {
		if (h->role_field[r] < 0)
			continue;
		for (int i = 0; i < h->role_field[r]; i++)
			offset[r] += h->size[i] * h->count[i];
	}
	for (uint64_t done = 0; done < h->points; done++) {
		const unsigned char *p;
		float v[PCD_ROLES] = {0};
		dp_status st = dp_io_bytes(s, (size_t)point_size, &p, err);
		if (st != DP_OK)
			return st;
		if (!p)
			return dp_fail(err, DP_ERR_FORMAT, "%s: truncated: the file ends after %llu of %llu points",
				       s->path, (unsigned long long)done, (unsigned long long)h->points);
		for (int r = 0; r < PCD_ROLES; r++) {
			int f = h->role_field[r];
			if (f >= 0 && r == PCD_RGB) {
				uint32_t packed = (uint32_t)dp_io_decode(p + offset[r], DP_IO_UINT, 4, 0);
				memcpy(&v[r], &packed, sizeof packed);
			} else if (f >= 0) {
				v[r] = (float)dp_io_decode(p + offset[r], h->kind[f], h->size[f], 0);
			}
		}
		if ((st = add_point(s, b, done, v, err)) != DP_OK)
			return st;
	}
	const unsigned char *extra;
	dp_status st = dp_io_bytes(s, 1, &extra, err);
	if (st == DP_OK && extra)
		st = dp_fail(err, DP_ERR_FORMAT, "%s: data continues after the declared POINTS", s->path);
	return st;
}

dp_status dp_io_read_pcd(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err)
{
	pcd_header h;
	uint64_t tokens = 0, point_size = 0;
	(void)flags;
	dp_status st = read_header(s, &h, err);
	if (st != DP_OK)
		return st;
	for (int i = 0; i < h.nfields; i++) {
		tokens += h.count[i];
		point_size += h.size[i] * h.count[i];
	}
	if (point_size > PCD_MAX_POINT_BYTES)
		return dp_fail(err, DP_ERR_FORMAT, "%s: points of %llu bytes each are implausible", s->path,
			       (unsigned long long)point_size);
	uint64_t min_bytes = h.data == PCD_ASCII ? DP_IO_MIN_TEXT_BYTES(tokens) : point_size;
	if ((st = dp_io_check_count(s, h.points, min_bytes, "points", err)) != DP_OK)
		return st;
	if (h.normals && (st = dp_io_builder_want_normals(b, err)) != DP_OK)
		return st;
	if (h.role_field[PCD_RGB] >= 0 && (st = dp_io_builder_want_colours(b, err)) != DP_OK)
		return st;
	if (h.role_field[PCD_I] >= 0 && (st = dp_io_builder_want_intensity(b, err)) != DP_OK)
		return st;
	if (h.points > SIZE_MAX)
		return dp_fail(err, DP_ERR_FORMAT, "%s: too many points", s->path);
	if (dp_io_remaining(s) != UINT64_MAX && (st = dp_io_builder_reserve(b, (size_t)h.points, err)) != DP_OK)
		return st;
	if (h.data == PCD_ASCII)
		return read_ascii(s, &h, b, err);
	return read_binary(s, &h, b, point_size, err);
}
