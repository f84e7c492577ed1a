#include "io/io.h"

#include "core/common.h"

/* x y z, optionally followed by nx ny nz. */
#define XYZ_POSITION_COLUMNS 3
#define XYZ_NORMAL_COLUMNS 6

/* Whitespace-separated columns, one point a line; `#` starts a comment. Every
 * line must have the column count of the first. */
dp_status dp_io_read_xyz(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err)
{
	int columns = 0;
	(void)flags;
	for (;;) {
		char *line, *cur;
		float v[XYZ_NORMAL_COLUMNS];
		int k = 0, r = 0;
		dp_status st = dp_io_line(s, &line, err);
		if (st != DP_OK)
			return st;
		if (!line)
			return DP_OK;
		dp_io_strip_comment(line, '#');
		cur = line;
		while (k < XYZ_NORMAL_COLUMNS && (r = dp_io_scan_float(&cur, &v[k])) == 1)
			k++;
		if (r < 0)
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: column %d is not a number", s->path,
				       s->line, k + 1);
		if (k == 0)
			continue;
		int extra = dp_io_scan_skip(&cur);
		if (columns == 0) {
			if (extra || (k != XYZ_POSITION_COLUMNS && k != XYZ_NORMAL_COLUMNS))
				return dp_fail(err, DP_ERR_FORMAT,
					       "%s: line %zu: expected 3 or 6 columns (x y z [nx ny nz]), found %s%d",
					       s->path, s->line, extra ? "more than " : "", k);
			columns = k;
			if (columns == XYZ_NORMAL_COLUMNS && (st = dp_io_builder_want_normals(b, err)) != DP_OK)
				return st;
		} else if (extra || k != columns) {
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: %s%d columns where the first point has %d",
				       s->path, s->line, extra ? "more than " : "", k, columns);
		}
		if ((st = dp_io_builder_add(b, v[0], v[1], v[2], v + 3, err)) != DP_OK)
			return st;
	}
}
