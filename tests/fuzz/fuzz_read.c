/* libFuzzer target for one point-file reader, picked at compile time by
 * DP_FUZZ_EXT ("ply", "pcd", "off", "obj" or "xyz"): the input is read through
 * dp_cloud_read_memory as a file with that extension, as points and as a
 * mesh, and (PLY) its edges through the reader dp_ply_read_edges uses. Every
 * guarantee dpoints.h documents for reading is checked, and a broken one
 * aborts, so the fuzzer reports it like a crash. */
#include "dpoints.h"
#include "io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef DP_FUZZ_EXT
#error "DP_FUZZ_EXT must name the format, e.g. -DDP_FUZZ_EXT=\"ply\""
#endif

#define NAME "fuzz." DP_FUZZ_EXT

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

static void broken(const char *what, const dp_error *err)
{
	fprintf(stderr, "fuzz_read(" DP_FUZZ_EXT "): guarantee broken: %s (message: '%s')\n", what,
		err ? err->message : "");
	abort();
}

static int all_zero(const void *p, size_t n)
{
	const unsigned char *b = p;
	for (size_t i = 0; i < n; i++)
		if (b[i])
			return 0;
	return 1;
}

/* Every failure: a known status, the same in err, one non-empty line that
 * names the input. */
static void check_error(dp_status st, const dp_error *err)
{
	if (st <= DP_OK || st > DP_ERR_INTERNAL)
		broken("status out of range", err);
	if (st == DP_ERR_INTERNAL)
		broken("DP_ERR_INTERNAL: an invariant broke", err);
	if (err->status != st)
		broken("err.status differs from the returned status", err);
	size_t len = strnlen(err->message, sizeof err->message);
	if (len == 0)
		broken("empty error message", err);
	if (len == sizeof err->message)
		broken("error message not NUL-terminated", err);
	if (strchr(err->message, '\n'))
		broken("error message spans lines", err);
	/* the builder's out-of-memory messages are made where no name is known */
	if (st != DP_ERR_NOMEM && !strstr(err->message, NAME))
		broken("error message does not name the input", err);
}

static void check_floats(const float *v, size_t n, const char *what, const dp_error *err)
{
	for (size_t i = 0; i < n; i++)
		if (!isfinite(v[i]))
			broken(what, err);
}

static void read_cloud(const unsigned char *data, size_t size, int flags)
{
	dp_cloud c;
	dp_error err = {0};
	/* garbage in, so a reader that leaves a field unwritten is caught */
	memset(&c, 0xa5, sizeof c);
	dp_status st = dp_cloud_read_memory(data, size, NAME, &c, flags, &err);
	if (st != DP_OK) {
		check_error(st, &err);
		if (!all_zero(&c, sizeof c))
			broken("cloud not zeroed on error", &err);
		return;
	}
	if (c.n == 0 || !c.x || !c.y || !c.z)
		broken("success without points", &err);
	if (!c.nx != !c.ny || !c.nx != !c.nz)
		broken("normals neither all present nor all absent", &err);
	check_floats(c.x, c.n, "non-finite x", &err);
	check_floats(c.y, c.n, "non-finite y", &err);
	check_floats(c.z, c.n, "non-finite z", &err);
	if (c.nx) {
		check_floats(c.nx, c.n, "non-finite nx", &err);
		check_floats(c.ny, c.n, "non-finite ny", &err);
		check_floats(c.nz, c.n, "non-finite nz", &err);
	}
	if (!(flags & DP_READ_MESH) && (c.nfaces || c.faces))
		broken("faces read although no mesh was asked for", &err);
	if (!c.nfaces != !c.faces)
		broken("nfaces and faces disagree", &err);
	for (size_t i = 0; i < 3 * c.nfaces; i++)
		if (c.faces[i] >= c.n)
			broken("face index out of range", &err);
	dp_cloud_free(&c);
	if (!all_zero(&c, sizeof c))
		broken("dp_cloud_free left the struct non-zero", &err);
}

/* dp_ply_read_edges's reader: edges within the vertices read, none on error. */
static void read_edges(const unsigned char *data, size_t size)
{
	dp_io_stream s;
	dp_error err = {0};
	if (dp_io_open_memory(&s, data, size, NAME, &err) != DP_OK)
		return;
	dp_io_builder b;
	dp_io_builder_init(&b, NAME);
	uint32_t *edges = (uint32_t *)&b; /* not NULL, so an unset output shows */
	size_t nedges = 1;
	dp_status st = dp_io_read_ply_edges(&s, &b, &edges, &nedges, &err);
	if (st != DP_OK) {
		check_error(st, &err);
		if (edges || nedges)
			broken("edges returned with an error", &err);
	} else {
		if (!edges != !nedges)
			broken("edges and nedges disagree", &err);
		for (size_t i = 0; i < 2 * nedges; i++)
			if (edges[i] >= b.c.n)
				broken("edge index out of range", &err);
	}
	free(edges);
	dp_io_builder_free(&b);
	dp_io_close(&s);
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
	read_cloud(data, size, DP_READ_POINTS);
	read_cloud(data, size, DP_READ_MESH);
	if (strcmp(DP_FUZZ_EXT, "ply") == 0)
		read_edges(data, size);
	return 0;
}
