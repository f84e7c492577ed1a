#include "io/io.h"

#include "core/common.h"

#include <string.h>
#include <strings.h>

static const struct {
	const char *extension;
	dp_io_reader read;
} readers[] = {
	{"ply", dp_io_read_ply}, {"xyz", dp_io_read_xyz}, {"xyzn", dp_io_read_xyz}, {"pwn", dp_io_read_xyz},
	{"txt", dp_io_read_xyz}, {"pts", dp_io_read_xyz}, {"pcd", dp_io_read_pcd}, {"off", dp_io_read_off},
	{"obj", dp_io_read_obj},
};

/* The extension of the file name (not of a folder in the path), or "";
 * "scan.ply.gz" gives "ply" (the stream decompresses whatever the format),
 * an unknown one before ".gz" gives "gz". */
static const char *extension(const char *path)
{
	const char *slash = strrchr(path, '/');
	const char *name = slash ? slash + 1 : path;
	const char *dot = strrchr(name, '.');
	if (!dot || dot == name)
		return "";
	if (strcasecmp(dot, ".gz") != 0)
		return dot + 1;
	const char *inner = dot;
	while (inner > name && inner[-1] != '.')
		inner--;
	if (inner - 1 > name)
		for (size_t i = 0; i < sizeof readers / sizeof readers[0]; i++)
			if (strlen(readers[i].extension) == (size_t)(dot - inner) &&
			    strncasecmp(inner, readers[i].extension, (size_t)(dot - inner)) == 0)
				return readers[i].extension;
	return dot + 1;
}

const char *dp_io_format_of(const char *path)
{
	return extension(path);
}

/* The reader for format (an extension), or NULL. */
static dp_io_reader reader_of(const char *ext)
{
	for (size_t i = 0; i < sizeof readers / sizeof readers[0]; i++)
		if (strcasecmp(ext, readers[i].extension) == 0)
			return readers[i].read;
	return NULL;
}

static dp_io_reader reader_for(const char *path)
{
	return reader_of(extension(path));
}

static dp_status unknown_format(const char *path, dp_error *err)
{
	return dp_fail(err, DP_ERR_FORMAT,
		       "%s: unknown point file format '%s' (expected .ply, .xyz, .xyzn, .pwn, .txt, .pts, .pcd, .off or .obj, "
		       "optionally gzip-compressed as .ply.gz and so on; --format names it)",
		       path, extension(path));
}

/* Parses an open stream into `cloud` and closes the stream. */
static dp_status read_stream(dp_io_stream *s, dp_io_reader read, dp_cloud *cloud, int flags, dp_error *err)
{
	dp_status st;
	if (s->size == 0) {
		st = dp_fail(err, DP_ERR_EMPTY, "%s: empty file", s->path);
	} else {
		dp_io_builder b;
		dp_io_builder_init(&b, s->path);
		st = read(s, &b, flags, err);
		if (st == DP_OK)
			st = dp_io_builder_finish(&b, s->path, cloud, err);
		dp_io_builder_free(&b);
	}
	dp_io_close(s);
	return st;
}

dp_status dp_cloud_read(const char *path, dp_cloud *cloud, int flags, dp_error *err)
{
	return dp_io_read_cloud(path, NULL, NULL, cloud, flags, err);
}

dp_status dp_io_read_cloud(const char *path, const char *format, const char *columns, dp_cloud *cloud, int flags,
			   dp_error *err)
{
	if (!cloud)
		return dp_fail(err, DP_ERR_ARG, "dp_cloud_read: cloud is NULL");
	memset(cloud, 0, sizeof *cloud);
	if (!path)
		return dp_fail(err, DP_ERR_ARG, "dp_cloud_read: path is NULL");
	if (flags & ~DP_READ_MESH)
		return dp_fail(err, DP_ERR_ARG, "%s: unknown read flags 0x%x", path, (unsigned)flags);
	int is_stdin = strcmp(path, "-") == 0;
	if (is_stdin && !format)
		return dp_fail(err, DP_ERR_ARG, "standard input: its format is unknown; name it with --format "
						"(ply, xyz, pts, pcd, off, obj, ...)");
	dp_io_reader read = format ? reader_of(format) : reader_for(path);
	if (!read && format)
		return dp_fail(err, DP_ERR_ARG,
			       "%s: unknown format '%s' (expected ply, xyz, xyzn, pwn, txt, pts, pcd, off or obj)",
			       is_stdin ? "standard input" : path, format);
	if (!read)
		return unknown_format(path, err);
	if (columns && read != dp_io_read_xyz)
		return dp_fail(err, DP_ERR_ARG, "%s: columns can be named for XYZ-like text only (.xyz, .txt, .pts, ...)",
			       is_stdin ? "standard input" : path);
	dp_io_stream s;
	dp_status st = dp_io_open(&s, path, err);
	if (st != DP_OK)
		return st;
	s.columns = columns;
	return read_stream(&s, read, cloud, flags, err);
}

dp_status dp_cloud_read_memory(const void *data, size_t size, const char *name, dp_cloud *cloud, int flags,
			       dp_error *err)
{
	if (!cloud)
		return dp_fail(err, DP_ERR_ARG, "dp_cloud_read_memory: cloud is NULL");
	memset(cloud, 0, sizeof *cloud);
	if (!name)
		return dp_fail(err, DP_ERR_ARG, "dp_cloud_read_memory: name is NULL");
	if (!data && size > 0)
		return dp_fail(err, DP_ERR_ARG, "%s: data is NULL but size is %zu", name, size);
	if (flags & ~DP_READ_MESH)
		return dp_fail(err, DP_ERR_ARG, "%s: unknown read flags 0x%x", name, (unsigned)flags);
	dp_io_reader read = reader_for(name);
	if (!read)
		return unknown_format(name, err);
	dp_io_stream s;
	dp_status st = dp_io_open_memory(&s, data, size, name, err);
	if (st != DP_OK)
		return st;
	return read_stream(&s, read, cloud, flags, err);
}

dp_status dp_ply_read_edges(const char *path, uint32_t **edges, size_t *nedges, dp_error *err)
{
	if (!edges || !nedges)
		return dp_fail(err, DP_ERR_ARG, "dp_ply_read_edges: edges or nedges is NULL");
	*edges = NULL;
	*nedges = 0;
	if (!path)
		return dp_fail(err, DP_ERR_ARG, "dp_ply_read_edges: path is NULL");
	if (strcasecmp(extension(path), "ply") != 0)
		return DP_OK;
	dp_io_stream s;
	dp_status st = dp_io_open(&s, path, err);
	if (st != DP_OK)
		return st;
	if (s.size == 0) {
		st = dp_fail(err, DP_ERR_EMPTY, "%s: empty file", path);
	} else {
		dp_io_builder b;
		dp_io_builder_init(&b, path);
		st = dp_io_read_ply_edges(&s, &b, edges, nedges, err);
		dp_io_builder_free(&b);
	}
	dp_io_close(&s);
	return st;
}
