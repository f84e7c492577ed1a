#include "io/ply.h"

#include "core/common.h"

#include <stdlib.h>
#include <string.h>

/* First allocation for edges; doubling from here. */
#define PLY_MIN_EDGES 1024

/* The fewest bytes one row of `el` takes: every list empty. */
static uint64_t min_row_bytes(const ply_element *el, int format)
{
	uint64_t bytes = 0;
	for (int i = 0; i < el->nprops; i++) {
		const ply_property *p = &el->props[i];
		if (format == PLY_ASCII)
			bytes += DP_IO_MIN_TEXT_BYTES(1);
		else
			bytes += p->is_list ? p->count_type.size : p->type.size;
	}
	return bytes;
}

/* Edges gathered from an `edge` element, grown geometrically. */
typedef struct ply_edges {
	uint32_t *v;         /* 2*n vertex indices */
	size_t n, cap;
} ply_edges;

/* Where one value comes from (the binary bytes or an ascii token) and where
 * rows go. */
typedef struct ply_source {
	dp_io_stream *s;
	dp_io_tokens tokens;
	int format;
	const ply_element *el;
	uint64_t row;
	uint64_t nvertices;
	dp_io_builder *b;
	ply_edges *edges;    /* NULL when edges are not wanted */
} ply_source;

static dp_status truncated(ply_source *src, dp_error *err)
{
	return dp_fail(err, DP_ERR_FORMAT, "%s: truncated: the file ends after %llu of %llu %s rows",
		       src->s->path, (unsigned long long)src->row, (unsigned long long)src->el->count,
		       src->el->name);
}

static dp_status bad_value(ply_source *src, const char *what, dp_error *err)
{
	if (src->format != PLY_ASCII)
		return dp_fail(err, DP_ERR_FORMAT, "%s: %s in %s %llu", src->s->path, what, src->el->name,
			       (unsigned long long)src->row);
	return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: %s in %s %llu", src->s->path, src->s->line, what,
		       src->el->name, (unsigned long long)src->row);
}

/* Reads one scalar as a double; integers when `integer` (list lengths and
 * indices), where an ascii "1.5" is an error. */
static dp_status read_value(ply_source *src, ply_type type, int integer, double *value, dp_error *err)
{
	if (src->format != PLY_ASCII) {
		const unsigned char *p;
		dp_status st = dp_io_bytes(src->s, type.size, &p, err);
		if (st != DP_OK)
			return st;
		if (!p)
			return truncated(src, err);
		*value = dp_io_decode(p, type.kind, type.size, src->format == PLY_BINARY_BE);
		return DP_OK;
	}
	int more;
	dp_status st = dp_io_tokens_next(&src->tokens, &more, err);
	if (st != DP_OK)
		return st;
	if (!more)
		return truncated(src, err);
	if (integer) {
		long long v;
		if (dp_io_scan_int(&src->tokens.cur, &v) != 1)
			return bad_value(src, "expected an integer", err);
		*value = (double)v;
	} else {
		float v;
		if (dp_io_scan_float(&src->tokens.cur, &v) != 1)
			return bad_value(src, "expected a number", err);
		*value = v;
	}
	return DP_OK;
}

static dp_status skip_values(ply_source *src, ply_type type, uint64_t count, dp_error *err)
{
	if (src->format != PLY_ASCII) {
		int skipped;
		if (count > UINT64_MAX / type.size)
			return truncated(src, err);
		dp_status st = dp_io_skip(src->s, count * type.size, &skipped, err);
		if (st == DP_OK && !skipped)
			st = truncated(src, err);
		return st;
	}
	for (uint64_t i = 0; i < count; i++) {
		int more;
		dp_status st = dp_io_tokens_next(&src->tokens, &more, err);
		if (st != DP_OK)
			return st;
		if (!more)
			return truncated(src, err);
		dp_io_scan_skip(&src->tokens.cur);
	}
	return DP_OK;
}

/* An index value read from the file, checked against the vertex count. */
static dp_status check_index(ply_source *src, double index, uint32_t *out, dp_error *err)
{
	if (index < 0 || index >= (double)src->nvertices || index > (double)UINT32_MAX)
		return dp_fail(err, DP_ERR_FORMAT, "%s: %s %llu: vertex index %.0f is out of range (%llu vertices)",
			       src->s->path, src->el->name, (unsigned long long)src->row, index,
			       (unsigned long long)src->nvertices);
	*out = (uint32_t)index;
	return DP_OK;
}

static dp_status read_face(ply_source *src, const ply_property *p, uint64_t length, dp_error *err)
{
	dp_io_fan fan = {0, 0, 0};
	if (p->type.kind == DP_IO_FLOAT)
		return bad_value(src, "vertex indices of a floating-point type", err);
	for (uint64_t k = 0; k < length; k++) {
		double value = 0;
		uint32_t index = 0;
		dp_status st = read_value(src, p->type, 1, &value, err);
		if (st == DP_OK)
			st = check_index(src, value, &index, err);
		if (st == DP_OK)
			st = dp_io_fan_add(src->b, &fan, index, err);
		if (st != DP_OK)
			return st;
	}
	return DP_OK;
}

static dp_status add_edge(ply_source *src, const double value[2], dp_error *err)
{
	ply_edges *e = src->edges;
	uint32_t a = 0, b = 0;
	dp_status st = check_index(src, value[0], &a, err);
	if (st == DP_OK)
		st = check_index(src, value[1], &b, err);
	if (st != DP_OK)
		return st;
	if (e->n == e->cap) {
		size_t cap = e->cap ? 2 * e->cap : PLY_MIN_EDGES;
		uint32_t *v = cap <= SIZE_MAX / 2 / sizeof *v ? realloc(e->v, 2 * cap * sizeof *v) : NULL;
		if (!v)
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu edges", src->s->path, cap);
		e->v = v;
		e->cap = cap;
	}
	e->v[2 * e->n] = a;
	e->v[2 * e->n + 1] = b;
	e->n++;
	return DP_OK;
}

/* Colour properties as bytes: uchar as is, floats in [0, 1] scaled, 16-bit
 * integers scaled down; out of range values clamped. */
static void set_colour(ply_source *src, const double *value)
{
	unsigned char rgb[3];
	for (int c = 0; c < 3; c++) {
		const ply_property *p = NULL;
		for (int i = 0; i < src->el->nprops && !p; i++)
			if (src->el->props[i].role == ROLE_RED + c)
				p = &src->el->props[i];
		double x = value[c];
		if (p && p->type.kind == DP_IO_FLOAT)
			x *= 255.0;
		else if (p && p->type.size >= 2)
			x /= 257.0;
		rgb[c] = (unsigned char)(x >= 255.0 ? 255.0 : x > 0.0 ? x + 0.5 : 0.0);
	}
	dp_io_builder_set_rgb(src->b, src->b->c.n - 1, rgb);
}

static dp_status read_row(ply_source *src, int is_vertex, dp_error *err)
{
	double v[ROLE_COUNT] = {0};
	const ply_element *el = src->el;
	for (int i = 0; i < el->nprops; i++) {
		const ply_property *p = &el->props[i];
		double value = 0;
		dp_status st;
		if (!p->is_list) {
			if (p->role == ROLE_NONE) {
				st = skip_values(src, p->type, 1, err);
			} else {
				int index = p->role == ROLE_EDGE1 || p->role == ROLE_EDGE2;
				if (index && p->type.kind == DP_IO_FLOAT)
					return bad_value(src, "vertex indices of a floating-point type", err);
				st = read_value(src, p->type, index, &v[p->role], err);
			}
			if (st != DP_OK)
				return st;
			continue;
		}
		if ((st = read_value(src, p->count_type, 1, &value, err)) != DP_OK)
			return st;
		if (value < 0)
			return bad_value(src, "negative list length", err);
		if (p->role == ROLE_FACE)
			st = read_face(src, p, (uint64_t)value, err);
		else
			st = skip_values(src, p->type, (uint64_t)value, err);
		if (st != DP_OK)
			return st;
	}
	if (is_vertex) {
		float normal[3] = {(float)v[ROLE_NX], (float)v[ROLE_NY], (float)v[ROLE_NZ]};
		dp_status st = dp_io_builder_add(src->b, (float)v[ROLE_X], (float)v[ROLE_Y], (float)v[ROLE_Z], normal, err);
		if (st == DP_OK && src->b->colours)
			set_colour(src, v + ROLE_RED);
		if (st == DP_OK && src->b->intensities)
			dp_io_builder_set_intensity(src->b, src->b->c.n - 1, (float)v[ROLE_INTENSITY]);
		return st;
	}
	if (src->edges && strcmp(el->name, "edge") == 0)
		return add_edge(src, v + ROLE_EDGE1, err);
	return DP_OK;
}

static dp_status read_data(ply_source *src, const ply_header *h, dp_error *err)
{
	dp_io_stream *s = src->s;
	dp_status st;
	if (h->normals && (st = dp_io_builder_want_normals(src->b, err)) != DP_OK)
		return st;
	if (h->colours && (st = dp_io_builder_want_colours(src->b, err)) != DP_OK)
		return st;
	if (h->intensity && (st = dp_io_builder_want_intensity(src->b, err)) != DP_OK)
		return st;
	for (int e = 0; e < h->nelements; e++) {
		const ply_element *el = &h->elements[e];
		char what[PLY_MAX_NAME + 16];
		snprintf(what, sizeof what, "%s rows", el->name);
		if ((st = dp_io_check_count(s, el->count, min_row_bytes(el, h->format), what, err)) != DP_OK)
			return st;
		if (e == h->vertex) {
			if (el->count > SIZE_MAX)
				return dp_fail(err, DP_ERR_FORMAT, "%s: too many vertices", s->path);
			if (dp_io_remaining(s) != UINT64_MAX &&
			    (st = dp_io_builder_reserve(src->b, (size_t)el->count, err)) != DP_OK)
				return st;
		}
		src->el = el;
		for (src->row = 0; src->row < el->count; src->row++)
			if ((st = read_row(src, e == h->vertex, err)) != DP_OK)
				return st;
	}
	if (h->format == PLY_ASCII) {
		int more;
		if ((st = dp_io_tokens_next(&src->tokens, &more, err)) != DP_OK)
			return st;
		if (more)
			return dp_fail(err, DP_ERR_FORMAT, "%s: line %zu: data continues after the last element",
				       s->path, s->line);
		return DP_OK;
	}
	const unsigned char *extra;
	if ((st = dp_io_bytes(s, 1, &extra, err)) != DP_OK)
		return st;
	if (extra)
		return dp_fail(err, DP_ERR_FORMAT,
			       "%s: data continues after the last element (the header's counts are too small)",
			       s->path);
	return DP_OK;
}

/* Drops the roles of data the caller did not ask for, so it is skipped; an
 * edge element asked for must name both ends, each once (one named twice
 * and the other not at all read the missing end as vertex 0). */
static dp_status select_roles(dp_io_stream *s, ply_header *h, int faces, int edges, dp_error *err)
{
	for (int e = 0; e < h->nelements; e++) {
		ply_element *el = &h->elements[e];
		int first = 0, second = 0;
		for (int i = 0; i < el->nprops; i++) {
			int *role = &el->props[i].role;
			if (*role == ROLE_FACE && !faces)
				*role = ROLE_NONE;
			if ((*role == ROLE_EDGE1 || *role == ROLE_EDGE2) && !edges)
				*role = ROLE_NONE;
			first += *role == ROLE_EDGE1;
			second += *role == ROLE_EDGE2;
		}
		if (edges && strcmp(el->name, "edge") == 0 && (first != 1 || second != 1))
			return dp_fail(err, DP_ERR_FORMAT, "%s: the edge element needs int properties vertex1 and vertex2",
				       s->path);
	}
	return DP_OK;
}

/* Reads vertices (and faces with DP_READ_MESH) into `b`, and the edge
 * element into `edges` when it is not NULL. */
static dp_status read_ply(dp_io_stream *s, dp_io_builder *b, int flags, ply_edges *edges, dp_error *err)
{
	ply_header h = {0};
	dp_status st = dp_io_ply_read_header(s, &h, err);
	if (st == DP_OK)
		st = select_roles(s, &h, flags & DP_READ_MESH, edges != NULL, err);
	if (st == DP_OK) {
		ply_source src = {s, {s, NULL}, h.format, NULL, 0, h.elements[h.vertex].count, b, edges};
		st = read_data(&src, &h, err);
	}
	dp_io_ply_header_free(&h);
	return st;
}

dp_status dp_io_read_ply(dp_io_stream *s, dp_io_builder *b, int flags, dp_error *err)
{
	return read_ply(s, b, flags, NULL, err);
}

dp_status dp_io_read_ply_edges(dp_io_stream *s, dp_io_builder *b, uint32_t **edges, size_t *nedges, dp_error *err)
{
	ply_edges e = {NULL, 0, 0};
	dp_status st = read_ply(s, b, DP_READ_POINTS, &e, err);
	if (st != DP_OK || e.n == 0) {
		free(e.v);
		e.v = NULL;
		e.n = 0;
	}
	*edges = e.v;
	*nedges = e.n;
	return st;
}
