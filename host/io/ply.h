/* The PLY header, parsed by ply_header.c and used by ply_read.c to read the
 * data that follows it. */
#ifndef DP_IO_PLY_H
#define DP_IO_PLY_H

#include "io/io.h"

/* Real files have a handful of elements; 3D Gaussian-splat files have ~62
 * vertex properties. Fixed bounds keep the header one allocation. */
#define PLY_MAX_ELEMENTS 32
#define PLY_MAX_PROPERTIES 256
#define PLY_MAX_NAME 64

enum ply_format { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE };

/* What a property feeds: a vertex coordinate or normal, face corners, or an
 * edge end. */
enum ply_role {
	ROLE_NONE = -1, ROLE_X, ROLE_Y, ROLE_Z, ROLE_NX, ROLE_NY, ROLE_NZ, ROLE_FACE, ROLE_EDGE1, ROLE_EDGE2,
	ROLE_RED, ROLE_GREEN, ROLE_BLUE, ROLE_INTENSITY, ROLE_COUNT
};

typedef struct ply_type {
	dp_io_kind kind;
	size_t size;
} ply_type;

typedef struct ply_property {
	ply_type type;       /* of the value, or of the list items */
	ply_type count_type; /* of the list length, when is_list */
	int is_list;
	int role;
} ply_property;

typedef struct ply_element {
	char name[PLY_MAX_NAME];
	uint64_t count;
	int nprops, props_cap;
	ply_property *props; /* grown as the header declares them */
} ply_element;

/* Zero-initialise; free with dp_io_ply_header_free. The arrays grow as the
 * header declares elements and properties: at their limits they would take
 * 330 KB, whose zeroing for every file was most of the time a fuzzer spent
 * on a small PLY (7 000 files a second against 60 000-90 000 for the other
 * readers). */
typedef struct ply_header {
	int format;
	int nelements, elements_cap;
	ply_element *elements;
	int vertex;          /* index of the vertex element */
	int normals;         /* the vertex element has nx, ny and nz */
	int colours;         /* the vertex element has red, green and blue */
	int intensity;       /* the vertex element has intensity (or CloudCompare's scalar_intensity) */
} ply_header;

/* Parses the header up to end_header: elements, properties and their roles
 * (x y z nx ny nz of `vertex`, vertex_indices of `face`, vertex1 vertex2 of
 * `edge`). Fails unless the vertex element has x, y and z. */
dp_status dp_io_ply_read_header(dp_io_stream *s, ply_header *h, dp_error *err);
void dp_io_ply_header_free(ply_header *h);

#endif
