/* Internal declarations shared by the point-file readers and the PLY writer:
 * a chunked input stream with a line reader, token scanning, binary scalar
 * decoding, a growing point/face builder, and the atomic output file. */
#ifndef DP_IO_IO_H
#define DP_IO_IO_H

#include "dpoints.h"

#include <stdint.h>
#include <stdio.h>

/* ------------------------------------------------------------ input stream */

/* A file (or a caller's bytes in memory) read in large chunks through one
 * buffer, so text parsers can run strtof over memory instead of calling stdio
 * per token. Memory goes through the same buffer and refills as a file: the
 * parsers write into the buffer (NUL-terminating lines), and the fuzzers
 * reach every refill path through dp_cloud_read_memory. */
typedef struct dp_io_stream {
	int fd;              /* -1 when reading memory */
	const unsigned char *mem; /* the bytes read when fd is -1; not owned */
	const char *path;    /* for error messages; not owned */
	char *buf;           /* cap + 1 bytes: room to NUL-terminate a last line */
	size_t cap, pos, end; /* unread bytes are buf[pos, end) */
	int eof;             /* the file has no more bytes to give */
	uint64_t offset;     /* file offset of buf[0] */
	uint64_t size;       /* file size; UINT64_MAX when not a regular file */
	size_t line;         /* number of the last line returned, from 1 */
	uint64_t raw_pos;    /* bytes taken from the file or memory (compressed ones when gz) */
	uint64_t raw_size;   /* of the memory read (size becomes unknown when it is gzip) */
	void *gz;            /* decompression state when the input is gzip, else NULL */
	const char *columns; /* XYZ columns named by the caller ("x,y,z,r,g,b"), NULL: detected */
} dp_io_stream;

/* Opens `path` ("-": standard input); DP_ERR_IO (with strerror) when missing
 * or unreadable. Content starting with the gzip magic is decompressed on the
 * fly (files and memory alike), its size then unknown. */
dp_status dp_io_open(dp_io_stream *s, const char *path, dp_error *err);
/* Reads `size` bytes at `data` (kept, not copied, until dp_io_close) as if they
 * were a file named `name`. Fails only with DP_ERR_NOMEM. */
dp_status dp_io_open_memory(dp_io_stream *s, const void *data, size_t size, const char *name, dp_error *err);
void dp_io_close(dp_io_stream *s);

/* Next line without its "\n" or "\r\n", NUL-terminated and writable until the
 * next call; *line is NULL at end of file. */
dp_status dp_io_line(dp_io_stream *s, char **line, dp_error *err);

/* Points *bytes at the next n bytes and consumes them; *bytes is NULL when
 * fewer than n remain (the caller names what was truncated). */
dp_status dp_io_bytes(dp_io_stream *s, size_t n, const unsigned char **bytes, dp_error *err);

/* Consumes n bytes; *skipped is 0 when fewer than n remained. */
dp_status dp_io_skip(dp_io_stream *s, uint64_t n, int *skipped, dp_error *err);

/* Bytes not yet consumed; UINT64_MAX when the size is unknown (a pipe). */
uint64_t dp_io_remaining(const dp_io_stream *s);

/* Rejects a header count that the rest of the file cannot hold: `count` items
 * of at least `min_bytes` each (DP_ERR_FORMAT). Called before allocating. */
dp_status dp_io_check_count(const dp_io_stream *s, uint64_t count, uint64_t min_bytes,
			    const char *what, dp_error *err);

/* The fewest bytes `tokens` whitespace-separated numbers can take in a text
 * file: one character and one separator each. */
#define DP_IO_MIN_TEXT_BYTES(tokens) (2 * (uint64_t)(tokens))

/* Fails unless only blank lines (and, when `comment` is not 0, comment lines)
 * remain: data beyond the declared counts means the header lies. */
dp_status dp_io_expect_end(dp_io_stream *s, char comment, const char *what, dp_error *err);

/* ---------------------------------------------------------------- tokens */

/* Scanning one whitespace-separated token at *cur, advancing *cur past it.
 * Return 1 when scanned, 0 when the line has no token left, -1 when the token
 * is not a number of the asked kind. */
int dp_io_scan_float(char **cur, float *value);
int dp_io_scan_int(char **cur, long long *value);
int dp_io_scan_skip(char **cur);
/* A whole token that is a decimal count (no sign): 1 when parsed, else 0. */
int dp_io_parse_count(const char *text, uint64_t *count);
/* Ends the line at its first `comment` character. */
void dp_io_strip_comment(char *line, char comment);
/* Splits a line in place into at most `max` tokens; returns how many were
 * found, or max + 1 when there were more. */
int dp_io_split(char *line, char **tokens, int max);

/* Tokens across lines, for formats whose records need not end lines. */
typedef struct dp_io_tokens {
	dp_io_stream *s;
	char *cur;
} dp_io_tokens;

/* Moves t->cur to the next token, reading lines as needed; *more = 0 at end
 * of file. */
dp_status dp_io_tokens_next(dp_io_tokens *t, int *more, dp_error *err);

/* ------------------------------------------------------- binary scalars */

typedef enum dp_io_kind {
	DP_IO_INT,
	DP_IO_UINT,
	DP_IO_FLOAT
} dp_io_kind;

/* Decodes one scalar of `size` bytes (1, 2, 4 or 8; floats 4 or 8). */
double dp_io_decode(const unsigned char *p, dp_io_kind kind, size_t size, int big_endian);

/* --------------------------------------------------------------- builder */

/* Points and triangles collected by a reader, grown geometrically when the
 * count is not known up front. */
typedef struct dp_io_builder {
	dp_cloud c;          /* c.n points used, c.nfaces triangles used */
	size_t cap;          /* points allocated */
	size_t face_cap;     /* triangles allocated */
	int normals;         /* points carry normals */
	int colours;         /* points carry colours (c.rgb, 3 bytes each) */
	int intensities;     /* points carry an intensity (c.intensity) */
	const char *path;    /* the file being read, for messages; not owned */
} dp_io_builder;

/* A polygon being fanned into triangles (v0, v[i-1], v[i]). */
typedef struct dp_io_fan {
	uint32_t first, prev;
	size_t count;
} dp_io_fan;

/* An empty builder for the file `path` (borrowed: it names the file in
 * out-of-memory messages). */
void dp_io_builder_init(dp_io_builder *b, const char *path);
/* Gives the builder normal arrays; call before adding points. */
dp_status dp_io_builder_want_normals(dp_io_builder *b, dp_error *err);
/* Gives the builder colour arrays; call before adding points. Each added
 * point's colour is then set with dp_io_builder_set_rgb (black otherwise). */
dp_status dp_io_builder_want_colours(dp_io_builder *b, dp_error *err);
void dp_io_builder_set_rgb(dp_io_builder *b, size_t index, const unsigned char rgb[3]);
/* The same for intensities (0 until set). */
dp_status dp_io_builder_want_intensity(dp_io_builder *b, dp_error *err);
void dp_io_builder_set_intensity(dp_io_builder *b, size_t index, float value);
/* Allocates room for n points (a count already checked against the file). */
dp_status dp_io_builder_reserve(dp_io_builder *b, size_t n, dp_error *err);
/* Appends a point; `normal` is ignored unless the builder has normals. */
dp_status dp_io_builder_add(dp_io_builder *b, float x, float y, float z, const float *normal,
			    dp_error *err);
dp_status dp_io_builder_add_triangle(dp_io_builder *b, uint32_t a, uint32_t v1, uint32_t v2,
				     dp_error *err);
/* Adds polygon corner `index`; from the third corner on, each adds a triangle. */
dp_status dp_io_fan_add(dp_io_builder *b, dp_io_fan *fan, uint32_t index, dp_error *err);
/* Validates (points present, coordinates finite, face indices in range),
 * trims the arrays and moves them into `cloud`; the builder is emptied. */
dp_status dp_io_builder_finish(dp_io_builder *b, const char *path, dp_cloud *cloud, dp_error *err);
void dp_io_builder_free(dp_io_builder *b);

/* Fails naming point `index` (from 0) when a coordinate or normal component
 * is NaN or infinite. */
dp_status dp_io_check_finite(const char *path, size_t index, float x, float y, float z,
			     const float *normal, dp_error *err);

/* --------------------------------------------------------------- readers */

/* Each reader fills the builder from an open stream; dp_cloud_read opens,
 * finishes and cleans up. `flags` holds DP_READ_MESH. */
typedef dp_status (*dp_io_reader)(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err);

dp_status dp_io_read_ply(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err);
/* Reads a PLY file's vertices into `b` and its `edge` element (vertex1,
 * vertex2) into a malloc'ed array of 2 * *nedges indices (NULL when none). */
dp_status dp_io_read_ply_edges(dp_io_stream *s, dp_io_builder *b, uint32_t **edges, size_t *nedges,
			       dp_error *err);
dp_status dp_io_read_xyz(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err);
dp_status dp_io_read_pcd(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err);
dp_status dp_io_read_off(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err);
dp_status dp_io_read_obj(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err);

/* dp_cloud_read with the format given (an extension: "ply", "xyz", ...; NULL
 * takes it from the path, ignoring a trailing ".gz") and, for XYZ-like text,
 * the columns (NULL: detected from the data). `path` "-" reads standard
 * input, which then needs `format`. Same errors as dp_cloud_read. */
dp_status dp_io_read_cloud(const char *path, const char *format, const char *columns, dp_cloud *cloud, int flags,
			   dp_error *err);
/* The format dp_io_read_cloud would take from `path` ("" when none). */
const char *dp_io_format_of(const char *path);

/* dp_ply_write with per-vertex colours: rgb, when not NULL, holds 3 bytes a
 * vertex, written after the float properties as uchar red, green, blue. */
dp_status dp_io_ply_write_rgb(const char *path, size_t n, const dp_ply_property *props, size_t nprops,
			      const unsigned char *rgb, const uint32_t *edges, size_t nedges, const uint32_t *faces,
			      size_t nfaces, int ascii, dp_error *err);

/* ---------------------------------------------------------- atomic output */

/* A file written under "<path>.tmp.<pid>" and renamed onto `path` only when
 * complete, so readers never see a partial file. */
typedef struct dp_atomic_file {
	FILE *f;
	const char *path;    /* not owned */
	char *tmp_path;
} dp_atomic_file;

dp_status dp_atomic_open(dp_atomic_file *af, const char *path, dp_error *err);
/* Flushes, syncs, closes and renames; on any failure removes the temporary
 * file and reports DP_ERR_IO. */
dp_status dp_atomic_commit(dp_atomic_file *af, dp_error *err);
/* Closes and removes the temporary file (after a failed write). */
void dp_atomic_abort(dp_atomic_file *af);

#endif
