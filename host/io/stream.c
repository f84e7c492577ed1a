#include "io/io.h"

#include "core/common.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

/* Large enough that read(2) and refills cost nothing next to parsing. A
 * build may make it tiny (CMake DP_STREAM_CHUNK) so that tests and fuzzers
 * with small inputs cross chunk boundaries and regrow the buffer. */
#ifdef DP_STREAM_CHUNK
#define STREAM_CHUNK ((size_t)(DP_STREAM_CHUNK))
#else
#define STREAM_CHUNK ((size_t)1 << 20)
#endif
/* Slack over a small file's size, so reaching its end needs no regrowth. */
#define STREAM_MIN_CAP ((size_t)64)
/* Longest accepted line. Real point files have lines of tens of bytes; the
 * bound stops a binary file without newlines from being slurped into memory
 * by the header parser. */
#define STREAM_MAX_LINE ((size_t)16 << 20)

/* Compressed input: raw bytes go through `in` into zlib, which writes the
 * stream's buffer, so every reader reads .gz files without knowing it. */
typedef struct gz_source {
	z_stream z;
	int ended; /* the last member ended (more raw bytes may start another) */
	unsigned char in[1 << 16];
} gz_source;

dp_status dp_io_open(dp_io_stream *s, const char *path, dp_error *err)
{
	memset(s, 0, sizeof *s);
	s->fd = -1;
	s->path = path;
	/* "-": standard input, whose format the caller names */
	int fd = strcmp(path, "-") == 0 ? fcntl(STDIN_FILENO, F_DUPFD_CLOEXEC, 0) : open(path, O_RDONLY | O_CLOEXEC);
	if (strcmp(path, "-") == 0)
		s->path = "standard input";
	if (fd < 0)
		return dp_fail(err, DP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
	struct stat st;
	if (fstat(fd, &st) != 0) {
		int e = errno;
		close(fd);
		return dp_fail(err, DP_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
	}
	if (S_ISDIR(st.st_mode)) {
		close(fd);
		return dp_fail(err, DP_ERR_IO, "%s: cannot read: %s", path, strerror(EISDIR));
	}
	s->size = S_ISREG(st.st_mode) ? (uint64_t)st.st_size : UINT64_MAX;
	/* A small file gets a buffer of its own size. */
	s->cap = s->size < STREAM_CHUNK ? (size_t)s->size + STREAM_MIN_CAP : STREAM_CHUNK;
	s->buf = malloc(s->cap + 1);
	if (!s->buf) {
		close(fd);
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for the read buffer", path);
	}
	s->fd = fd;
	return DP_OK;
}

dp_status dp_io_open_memory(dp_io_stream *s, const void *data, size_t size, const char *name, dp_error *err)
{
	memset(s, 0, sizeof *s);
	s->fd = -1;
	s->path = name;
	s->mem = data;
	s->size = s->raw_size = size;
	s->cap = size < STREAM_CHUNK ? size + STREAM_MIN_CAP : STREAM_CHUNK;
	s->buf = malloc(s->cap + 1);
	if (!s->buf)
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for the read buffer", name);
	return DP_OK;
}

/* read(2) for both kinds of stream: raw bytes from the file or from memory. */
static ssize_t raw_read(dp_io_stream *s, void *dst, size_t n)
{
	if (s->fd >= 0) {
		ssize_t got;
		do
			got = read(s->fd, dst, n);
		while (got < 0 && errno == EINTR);
		if (got > 0)
			s->raw_pos += (uint64_t)got;
		return got;
	}
	size_t left = (size_t)(s->raw_size - s->raw_pos);
	if (n > left)
		n = left;
	if (n > 0)
		memcpy(dst, s->mem + s->raw_pos, n);
	s->raw_pos += n;
	return (ssize_t)n;
}

/* Switches to decompression when the first raw bytes are a gzip header;
 * `head` holds them, and they become zlib's first input. */
static dp_status gz_begin(dp_io_stream *s, const unsigned char *head, size_t n, dp_error *err)
{
	gz_source *g = malloc(sizeof *g);
	if (!g)
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for decompression", s->path);
	memset(&g->z, 0, sizeof g->z);
	g->ended = 0;
	/* 16 + 15: a gzip wrapper and the largest window */
	if (inflateInit2(&g->z, 16 + 15) != Z_OK) {
		free(g);
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for decompression", s->path);
	}
	memcpy(g->in, head, n);
	g->z.next_in = g->in;
	g->z.avail_in = (uInt)n;
	s->gz = g;
	/* the decompressed size is known only at the end */
	s->size = UINT64_MAX;
	return DP_OK;
}

static dp_status gz_read(dp_io_stream *s, char *dst, size_t n, size_t *got, dp_error *err)
{
	gz_source *g = s->gz;
	*got = 0;
	g->z.next_out = (unsigned char *)dst;
	g->z.avail_out = (uInt)(n > UINT_MAX ? UINT_MAX : n);
	while (g->z.avail_out > 0) {
		if (g->z.avail_in == 0) {
			ssize_t r = raw_read(s, g->in, sizeof g->in);
			if (r < 0)
				return dp_fail(err, DP_ERR_IO, "%s: read failed: %s", s->path, strerror(errno));
			if (r == 0) {
				if (!g->ended)
					return dp_fail(err, DP_ERR_FORMAT, "%s: the gzip data is truncated", s->path);
				break;
			}
			g->z.next_in = g->in;
			g->z.avail_in = (uInt)r;
		}
		if (g->ended) {
			/* gzip allows members one after another (cat a.gz b.gz) */
			if (inflateReset(&g->z) != Z_OK)
				return dp_fail(err, DP_ERR_FORMAT, "%s: gzip data is corrupt", s->path);
			g->ended = 0;
		}
		int zr = inflate(&g->z, Z_NO_FLUSH);
		if (zr == Z_STREAM_END)
			g->ended = 1;
		else if (zr == Z_MEM_ERROR)
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory decompressing", s->path);
		else if (zr != Z_OK && zr != Z_BUF_ERROR)
			return dp_fail(err, DP_ERR_FORMAT, "%s: gzip data is corrupt: %s", s->path,
				       g->z.msg ? g->z.msg : "inflate failed");
	}
	*got = (size_t)((char *)g->z.next_out - dst);
	return DP_OK;
}

/* Up to n bytes of content into dst (*got 0 at the end), decompressed when
 * the input is gzip. */
static dp_status source_read(dp_io_stream *s, char *dst, size_t n, size_t *got, dp_error *err)
{
	*got = 0;
	if (s->gz)
		return gz_read(s, dst, n, got, err);
	int first = s->raw_pos == 0;
	ssize_t r = raw_read(s, dst, n);
	if (r < 0)
		return dp_fail(err, DP_ERR_IO, "%s: read failed: %s", s->path, strerror(errno));
	if (first && r >= 2 && (unsigned char)dst[0] == 0x1f && (unsigned char)dst[1] == 0x8b) {
		dp_status st = gz_begin(s, (const unsigned char *)dst, (size_t)r, err);
		return st != DP_OK ? st : gz_read(s, dst, n, got, err);
	}
	*got = (size_t)r;
	return DP_OK;
}

void dp_io_close(dp_io_stream *s)
{
	if (s->gz) {
		inflateEnd(&((gz_source *)s->gz)->z);
		free(s->gz);
		s->gz = NULL;
	}
	if (s->fd >= 0)
		close(s->fd);
	free(s->buf);
	s->fd = -1;
	s->buf = NULL;
}

/* Makes at least `need` unread bytes available unless the file ends first. */
static dp_status fill(dp_io_stream *s, size_t need, dp_error *err)
{
	if (s->end - s->pos >= need || s->eof)
		return DP_OK;
	if (s->pos > 0) {
		memmove(s->buf, s->buf + s->pos, s->end - s->pos);
		s->offset += s->pos;
		s->end -= s->pos;
		s->pos = 0;
	}
	if (need > s->cap) {
		size_t cap = s->cap * 2 > need ? s->cap * 2 : need;
		char *buf = realloc(s->buf, cap + 1);
		if (!buf)
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory growing the read buffer to %zu bytes",
				       s->path, cap);
		s->buf = buf;
		s->cap = cap;
	}
	while (s->end < need && !s->eof) {
		size_t got;
		dp_status st = source_read(s, s->buf + s->end, s->cap - s->end, &got, err);
		if (st != DP_OK)
			return st;
		if (got == 0)
			s->eof = 1;
		s->end += got;
	}
	return DP_OK;
}

static char *end_line(dp_io_stream *s, char *start, char *stop)
{
	*stop = '\0';
	if (stop > start && stop[-1] == '\r')
		stop[-1] = '\0';
	s->line++;
	return start;
}

dp_status dp_io_line(dp_io_stream *s, char **line, dp_error *err)
{
	size_t scanned = 0;
	*line = NULL;
	for (;;) {
		char *start = s->buf + s->pos;
		size_t have = s->end - s->pos;
		char *nl = memchr(start + scanned, '\n', have - scanned);
		if (nl) {
			s->pos += (size_t)(nl - start) + 1;
			*line = end_line(s, start, nl);
			return DP_OK;
		}
		if (s->eof) {
			if (have > 0) {
				s->pos = s->end;
				*line = end_line(s, start, start + have);
			}
			return DP_OK;
		}
		if (have >= STREAM_MAX_LINE)
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu is longer than %zu bytes", s->path,
				       s->line + 1, STREAM_MAX_LINE);
		scanned = have;
		dp_status st = fill(s, have + 1, err);
		if (st != DP_OK)
			return st;
	}
}

dp_status dp_io_bytes(dp_io_stream *s, size_t n, const unsigned char **bytes, dp_error *err)
{
	*bytes = NULL;
	dp_status st = fill(s, n, err);
	if (st != DP_OK || s->end - s->pos < n)
		return st;
	*bytes = (const unsigned char *)s->buf + s->pos;
	s->pos += n;
	return DP_OK;
}

dp_status dp_io_skip(dp_io_stream *s, uint64_t n, int *skipped, dp_error *err)
{
	*skipped = 0;
	while (n > 0) {
		size_t step = n < s->cap ? (size_t)n : s->cap;
		dp_status st = fill(s, step, err);
		if (st != DP_OK)
			return st;
		if (s->end - s->pos < step)
			return DP_OK;
		s->pos += step;
		n -= step;
	}
	*skipped = 1;
	return DP_OK;
}

uint64_t dp_io_remaining(const dp_io_stream *s)
{
	if (s->size == UINT64_MAX)
		return UINT64_MAX;
	uint64_t done = s->offset + s->pos;
	return s->size > done ? s->size - done : 0;
}

dp_status dp_io_check_count(const dp_io_stream *s, uint64_t count, uint64_t min_bytes,
			    const char *what, dp_error *err)
{
	uint64_t left = dp_io_remaining(s);
	if (left == UINT64_MAX || count == 0 || min_bytes == 0)
		return DP_OK;
	/* +1: the last text record may end without its separator. */
	if (count <= (left + 1) / min_bytes)
		return DP_OK;
	if (count > UINT64_MAX / min_bytes)
		return dp_fail(err, DP_ERR_FORMAT, "%s: header declares %llu %s, more than any file can hold",
			       s->path, (unsigned long long)count, what);
	return dp_fail(err, DP_ERR_FORMAT,
		       "%s: header declares %llu %s (at least %llu bytes) but only %llu bytes follow",
		       s->path, (unsigned long long)count, what, (unsigned long long)(count * min_bytes),
		       (unsigned long long)left);
}

dp_status dp_io_expect_end(dp_io_stream *s, char comment, const char *what, dp_error *err)
{
	for (;;) {
		char *line, *cur;
		dp_status st = dp_io_line(s, &line, err);
		if (st != DP_OK || !line)
			return st;
		if (comment)
			dp_io_strip_comment(line, comment);
		cur = line;
		if (dp_io_scan_skip(&cur))
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: data continues after the %s", s->path,
				       s->line, what);
	}
}
