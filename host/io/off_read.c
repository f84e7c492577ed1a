#include "io/io.h"

#include "core/common.h"

#include <string.h>

#define OFF_POSITION_VALUES 3
#define OFF_NORMAL_VALUES 6

/* The next line that holds data once `#` comments are removed; NULL at the
 * end of the file. */
static dp_status data_line(dp_io_stream *s, char **line, dp_error *err)
{
	for (;;) {
		dp_status st = dp_io_line(s, line, err);
		if (st != DP_OK || !*line)
			return st;
		dp_io_strip_comment(*line, '#');
		char *cur = *line;
		if (dp_io_scan_skip(&cur))
			return DP_OK;
	}
}

/* The keyword is [ST][C][N]OFF: texture coordinates and colours follow the
 * position on each vertex line and are ignored; N adds a normal. Some files
 * glue the counts to it ("OFF490 518 0"), so *rest points just after "OFF". */
static dp_status parse_keyword(dp_io_stream *s, char *line, int *normals, char **rest, dp_error *err)
{
	char *start = line, *end;
	while (*start == ' ' || *start == '\t')
		start++;
	end = start;
	dp_io_scan_skip(&end);
	char *off = strstr(start, "OFF");
	if (!off || off + 3 > end)
		return dp_fail(err, DP_ERR_FORMAT, "%s: not an OFF file (the first line has no OFF keyword)", s->path);
	for (char *q = start; q < off; q++) {
		if (*q == 'N')
			*normals = 1;
		else if (*q == '4' || *q == 'n')
			return dp_fail(err, DP_ERR_FORMAT, "%s: %.*sOFF files (not 3-D) are unsupported", s->path,
				       (int)(off - start), start);
		else if (*q != 'C' && *q != 'S' && *q != 'T')
			return dp_fail(err, DP_ERR_FORMAT, "%s: not an OFF file (unknown keyword)", s->path);
	}
	*rest = off + 3;
	char *next = *rest;
	while (*next == ' ' || *next == '\t')
		next++;
	if (strncmp(next, "BINARY", 6) == 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: binary OFF files are unsupported", s->path);
	return DP_OK;
}

static dp_status parse_counts(dp_io_stream *s, char *cur, long long counts[3], dp_error *err)
{
	int k = 0, r;
	long long v;
	counts[2] = 0;
	while ((r = dp_io_scan_int(&cur, &v)) == 1 && k < 3)
		counts[k++] = v;
	if (r < 0 || k < 2 || (r == 1 && k == 3) || counts[0] < 0 || counts[1] < 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: expected 'VERTICES FACES [EDGES]' counts", s->path,
			       s->line);
	return DP_OK;
}

static dp_status read_face(dp_io_stream *s, dp_io_builder *b, char *cur, long long face, long long nvertices,
			   dp_error *err)
{
	long long k, index;
	dp_io_fan fan = {0, 0, 0};
	if (dp_io_scan_int(&cur, &k) != 1 || k < 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: face %lld does not start with its vertex count",
			       s->path, s->line, face);
	for (long long i = 0; i < k; i++) {
		if (dp_io_scan_int(&cur, &index) != 1)
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: face %lld lists fewer than %lld vertex indices",
				       s->path, s->line, face, k);
		if (index < 0 || index >= nvertices)
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: face %lld: vertex index %lld is out of range "
				       "(%lld vertices)", s->path, s->line, face, index, nvertices);
		dp_status st = dp_io_fan_add(b, &fan, (uint32_t)index, err);
		if (st != DP_OK)
			return st;
	}
	return DP_OK;
}

/* OFF, NOFF, COFF, ...: one vertex per line (position, then an optional
 * normal; anything after is ignored), then one face per line. */
dp_status dp_io_read_off(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err)
{
	char *line, *rest;
	int normals = 0;
	long long counts[3];
	dp_status st = data_line(s, &line, err);
	if (st != DP_OK)
		return st;
	if (!line)
		return dp_fail(err, DP_ERR_EMPTY, "%s: no data", s->path);
	if ((st = parse_keyword(s, line, &normals, &rest, err)) != DP_OK)
		return st;
	char *cur = rest;
	if (!dp_io_scan_skip(&cur)) {
		if ((st = data_line(s, &rest, err)) != DP_OK)
			return st;
		if (!rest)
			return dp_fail(err, DP_ERR_FORMAT, "%s: truncated: no vertex and face counts", s->path);
	}
	if ((st = parse_counts(s, rest, counts, err)) != DP_OK)
		return st;
	int values = normals ? OFF_NORMAL_VALUES : OFF_POSITION_VALUES;
	if ((st = dp_io_check_count(s, (uint64_t)counts[0], DP_IO_MIN_TEXT_BYTES(values), "vertices", err)) != DP_OK)
		return st;
	if (normals && (st = dp_io_builder_want_normals(b, err)) != DP_OK)
		return st;
	if ((uint64_t)counts[0] > UINT32_MAX)
		return dp_fail(err, DP_ERR_FORMAT, "%s: too many vertices (%lld)", s->path, counts[0]);
	if (dp_io_remaining(s) != UINT64_MAX && (st = dp_io_builder_reserve(b, (size_t)counts[0], err)) != DP_OK)
		return st;
	for (long long i = 0; i < counts[0]; i++) {
		float v[OFF_NORMAL_VALUES];
		if ((st = data_line(s, &line, err)) != DP_OK)
			return st;
		if (!line)
			return dp_fail(err, DP_ERR_FORMAT, "%s: truncated: the file ends after %lld of %lld vertices",
				       s->path, i, counts[0]);
		cur = line;
		for (int k = 0; k < values; k++)
			if (dp_io_scan_float(&cur, &v[k]) != 1)
				return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: vertex %lld needs %d numbers", s->path,
					       s->line, i, values);
		if ((st = dp_io_builder_add(b, v[0], v[1], v[2], v + 3, err)) != DP_OK)
			return st;
	}
	for (long long f = 0; f < counts[1]; f++) {
		if ((st = data_line(s, &line, err)) != DP_OK)
			return st;
		if (!line)
			return dp_fail(err, DP_ERR_FORMAT, "%s: truncated: the file ends after %lld of %lld faces",
				       s->path, f, counts[1]);
		if ((flags & DP_READ_MESH) && (st = read_face(s, b, line, f, counts[0], err)) != DP_OK)
			return st;
	}
	return dp_io_expect_end(s, '#', "declared faces", err);
}
