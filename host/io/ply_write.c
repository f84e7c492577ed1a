#include "io/io.h"

#include "core/common.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <string.h>

/* Binary rows are packed into a stack buffer of this size before each
 * fwrite: large enough to make the call overhead vanish, small enough for any
 * thread's stack. */
#define PLY_WRITE_CHUNK ((size_t)1 << 14)
/* Enough significant digits that every float reads back bit-exact. */
#define PLY_FLOAT_FORMAT "%.9g"

/* Little-endian bytes collected in chunks; `failed` latches a short write. */
typedef struct byte_sink {
	FILE *f;
	size_t used;
	int failed;
	unsigned char buf[PLY_WRITE_CHUNK];
} byte_sink;

static void sink_flush(byte_sink *k)
{
	if (k->used && fwrite(k->buf, 1, k->used, k->f) != k->used)
		k->failed = 1;
	k->used = 0;
}

static void sink_u8(byte_sink *k, uint8_t v)
{
	if (k->used == sizeof k->buf)
		sink_flush(k);
	k->buf[k->used++] = v;
}

static void sink_u32(byte_sink *k, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		sink_u8(k, (uint8_t)(v >> (8 * i)));
}

static void sink_float(byte_sink *k, float f)
{
	uint32_t bits;
	memcpy(&bits, &f, sizeof bits);
	sink_u32(k, bits);
}

static int write_binary(FILE *f, size_t n, const dp_ply_property *props, size_t nprops, const unsigned char *rgb,
			const uint32_t *edges, size_t nedges, const uint32_t *faces, size_t nfaces)
{
	byte_sink k;
	k.f = f;
	k.used = 0;
	k.failed = 0;
	for (size_t i = 0; i < n; i++) {
		for (size_t p = 0; p < nprops; p++)
			sink_float(&k, props[p].values[i]);
		for (int c = 0; rgb && c < 3; c++)
			sink_u8(&k, rgb[3 * i + c]);
	}
	for (size_t i = 0; i < 2 * nedges; i++)
		sink_u32(&k, edges[i]);
	for (size_t i = 0; i < nfaces; i++) {
		sink_u8(&k, 3);
		for (int c = 0; c < 3; c++)
			sink_u32(&k, faces[3 * i + c]);
	}
	sink_flush(&k);
	return !k.failed;
}

static int write_ascii(FILE *f, size_t n, const dp_ply_property *props, size_t nprops, const unsigned char *rgb,
		       const uint32_t *edges, size_t nedges, const uint32_t *faces, size_t nfaces)
{
	for (size_t i = 0; i < n; i++) {
		for (size_t p = 0; p < nprops; p++)
			if (fprintf(f, PLY_FLOAT_FORMAT "%c", (double)props[p].values[i],
				    p + 1 < nprops || rgb ? ' ' : '\n') < 0)
				return 0;
		if (rgb && fprintf(f, "%u %u %u\n", rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]) < 0)
			return 0;
	}
	for (size_t i = 0; i < nedges; i++)
		if (fprintf(f, "%u %u\n", edges[2 * i], edges[2 * i + 1]) < 0)
			return 0;
	for (size_t i = 0; i < nfaces; i++)
		if (fprintf(f, "3 %u %u %u\n", faces[3 * i], faces[3 * i + 1], faces[3 * i + 2]) < 0)
			return 0;
	return 1;
}

static int valid_name(const char *name)
{
	if (!name || !*name)
		return 0;
	for (const char *c = name; *c; c++)
		if (!isgraph((unsigned char)*c))
			return 0;
	return 1;
}

static dp_status check_indices(const char *path, const char *what, const uint32_t *idx, size_t count,
			       size_t per, size_t n, dp_error *err)
{
	if (count && !idx)
		return dp_fail(err, DP_ERR_ARG, "%s: %zu %ss but no index array", path, count, what);
	for (size_t i = 0; i < count * per; i++)
		if (idx[i] >= n)
			return dp_fail(err, DP_ERR_ARG, "%s: %s %zu refers to vertex %u but there are %zu vertices", path,
				       what, i / per, idx[i], n);
	return DP_OK;
}

static dp_status check_args(const char *path, size_t n, const dp_ply_property *props, size_t nprops,
			    const uint32_t *edges, size_t nedges, const uint32_t *faces, size_t nfaces, dp_error *err)
{
	if (!path)
		return dp_fail(err, DP_ERR_ARG, "dp_ply_write: path is NULL");
	if (nprops == 0 || !props)
		return dp_fail(err, DP_ERR_ARG, "%s: no vertex properties to write", path);
	for (size_t p = 0; p < nprops; p++) {
		if (!valid_name(props[p].name))
			return dp_fail(err, DP_ERR_ARG, "%s: property %zu has an empty name or one with spaces", path, p);
		if (n && !props[p].values)
			return dp_fail(err, DP_ERR_ARG, "%s: property %s has no values", path, props[p].name);
	}
	/* Indices are written as PLY int. */
	if ((nedges || nfaces) && n > INT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "%s: %zu vertices are too many for int indices", path, n);
	dp_status st = check_indices(path, "edge", edges, nedges, 2, n, err);
	if (st == DP_OK)
		st = check_indices(path, "face", faces, nfaces, 3, n, err);
	return st;
}

dp_status dp_ply_write(const char *path, size_t n, const dp_ply_property *props, size_t nprops,
		       const uint32_t *edges, size_t nedges, const uint32_t *faces, size_t nfaces,
		       int ascii, dp_error *err)
{
	return dp_io_ply_write_rgb(path, n, props, nprops, NULL, edges, nedges, faces, nfaces, ascii, err);
}

dp_status dp_io_ply_write_rgb(const char *path, size_t n, const dp_ply_property *props, size_t nprops,
			      const unsigned char *rgb, const uint32_t *edges, size_t nedges, const uint32_t *faces,
			      size_t nfaces, int ascii, dp_error *err)
{
	dp_status st = check_args(path, n, props, nprops, edges, nedges, faces, nfaces, err);
	if (st != DP_OK)
		return st;
	dp_atomic_file af;
	if ((st = dp_atomic_open(&af, path, err)) != DP_OK)
		return st;
	FILE *f = af.f;
	errno = 0;
	int ok = fprintf(f, "ply\nformat %s 1.0\ncomment written by dpoints\nelement vertex %zu\n",
			 ascii ? "ascii" : "binary_little_endian", n) > 0;
	for (size_t p = 0; p < nprops && ok; p++)
		ok = fprintf(f, "property float %s\n", props[p].name) > 0;
	if (ok && rgb)
		ok = fprintf(f, "property uchar red\nproperty uchar green\nproperty uchar blue\n") > 0;
	if (ok && nedges)
		ok = fprintf(f, "element edge %zu\nproperty int vertex1\nproperty int vertex2\n", nedges) > 0;
	if (ok && nfaces)
		ok = fprintf(f, "element face %zu\nproperty list uchar int vertex_indices\n", nfaces) > 0;
	ok = ok && fprintf(f, "end_header\n") > 0;
	if (ok)
		ok = ascii ? write_ascii(f, n, props, nprops, rgb, edges, nedges, faces, nfaces)
			   : write_binary(f, n, props, nprops, rgb, edges, nedges, faces, nfaces);
	if (!ok) {
		int e = errno;
		dp_atomic_abort(&af);
		return dp_fail(err, DP_ERR_IO, "%s: write failed: %s", path, strerror(e ? e : EIO));
	}
	return dp_atomic_commit(&af, err);
}

dp_status dp_cloud_write_ply(const char *path, const dp_cloud *cloud, int ascii, dp_error *err)
{
	if (!cloud)
		return dp_fail(err, DP_ERR_ARG, "%s: cloud is NULL", path ? path : "dp_cloud_write_ply");
	dp_ply_property props[7] = {
		{"x", cloud->x}, {"y", cloud->y}, {"z", cloud->z},
		{"nx", cloud->nx}, {"ny", cloud->ny}, {"nz", cloud->nz},
	};
	size_t nprops = cloud->nx ? 6 : 3;
	if (cloud->intensity)
		props[nprops++] = (dp_ply_property){"intensity", cloud->intensity};
	size_t nfaces = cloud->faces ? cloud->nfaces : 0;
	return dp_io_ply_write_rgb(path, cloud->n, props, nprops, cloud->rgb, NULL, 0, cloud->faces, nfaces, ascii, err);
}
