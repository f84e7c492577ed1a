#include "io/io.h"

#include "core/common.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* One face corner "v", "v/vt", "v//vn" or "v/vt/vn": the vertex index is
 * 1-based, or negative to count back from the last vertex read so far.
 * Returns 1 with the 0-based index, 0 at the end of the line, -1 when bad. */
static int scan_corner(char **cur, size_t nvertices, long long *index)
{
	char *p = *cur, *end;
	while (*p == ' ' || *p == '\t' || *p == '\r')
		p++;
	if (!*p)
		return 0;
	errno = 0;
	long long v = strtoll(p, &end, 10);
	if (end == p || errno == ERANGE || (*end && *end != '/' && *end != ' ' && *end != '\t' && *end != '\r'))
		return -1;
	while (*end && *end != ' ' && *end != '\t')
		end++;
	*cur = end;
	if (v > 0)
		*index = v - 1;
	else if (v < 0 && v >= -(long long)nvertices)
		*index = (long long)nvertices + v;
	else
		return -1;
	return 1;
}

static dp_status read_face(dp_io_stream *s, dp_io_builder *b, char *cur, dp_error *err)
{
	dp_io_fan fan = {0, 0, 0};
	long long index;
	int r;
	while ((r = scan_corner(&cur, b->c.n, &index)) == 1) {
		/* Forward references are checked against the final count when the
		 * builder finishes. */
		if (index > (long long)UINT32_MAX)
			break;
		dp_status st = dp_io_fan_add(b, &fan, (uint32_t)index, err);
		if (st != DP_OK)
			return st;
	}
	if (r != 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: bad or out-of-range vertex index in face", s->path,
			       s->line);
	return DP_OK;
}

/* Wavefront OBJ: `v x y z [w] [r g b]` and `f` lines; every other statement
 * (vn, vt, g, o, s, usemtl, ...) is ignored. */
dp_status dp_io_read_obj(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err)
{
	for (;;) {
		char *line, *cur;
		dp_status st = dp_io_line(s, &line, err);
		if (st != DP_OK || !line)
			return st;
		dp_io_strip_comment(line, '#');
		cur = line;
		while (*cur == ' ' || *cur == '\t')
			cur++;
		if (cur[0] == 'v' && (cur[1] == ' ' || cur[1] == '\t')) {
			float v[3];
			cur++;
			for (int k = 0; k < 3; k++)
				if (dp_io_scan_float(&cur, &v[k]) != 1)
					return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: a vertex needs x, y and z", s->path,
						       s->line);
			if ((st = dp_io_builder_add(b, v[0], v[1], v[2], NULL, err)) != DP_OK)
				return st;
		} else if (cur[0] == 'f' && (cur[1] == ' ' || cur[1] == '\t') && (flags & DP_READ_MESH)) {
			if ((st = read_face(s, b, cur + 1, err)) != DP_OK)
				return st;
		}
	}
}
