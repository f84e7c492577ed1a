#include "io/ply.h"

#include "core/common.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* "property list uchar int vertex_indices" has the most tokens of any line. */
#define PLY_MAX_TOKENS 6

static const struct {
	const char *name;
	dp_io_kind kind;
	size_t size;
} ply_types[] = {
	{"char", DP_IO_INT, 1},    {"int8", DP_IO_INT, 1},     {"uchar", DP_IO_UINT, 1},
	{"uint8", DP_IO_UINT, 1},  {"short", DP_IO_INT, 2},    {"int16", DP_IO_INT, 2},
	{"ushort", DP_IO_UINT, 2}, {"uint16", DP_IO_UINT, 2},  {"int", DP_IO_INT, 4},
	{"int32", DP_IO_INT, 4},   {"uint", DP_IO_UINT, 4},    {"uint32", DP_IO_UINT, 4},
	{"float", DP_IO_FLOAT, 4}, {"float32", DP_IO_FLOAT, 4}, {"double", DP_IO_FLOAT, 8},
	{"float64", DP_IO_FLOAT, 8},
};

static const char *const vertex_roles[] = {"x", "y", "z", "nx", "ny", "nz"};

static int parse_type(const char *name, ply_type *t)
{
	for (size_t i = 0; i < sizeof ply_types / sizeof ply_types[0]; i++)
		if (strcmp(name, ply_types[i].name) == 0) {
			t->kind = ply_types[i].kind;
			t->size = ply_types[i].size;
			return 1;
		}
	return 0;
}

static dp_status header_fail(dp_io_stream *s, const char *problem, const char *word, dp_error *err)
{
	return dp_fail(err, DP_ERR_FORMAT, "%s: header line %zu: %s%s%s%s", s->path, s->line, problem,
		       word ? " '" : "", word ? word : "", word ? "'" : "");
}

/* `items` (n of `size` bytes, room for *cap, never more than `most`) with
 * room for one more: the same or a moved array, or NULL when out of memory
 * (items is then left as it was). */
static void *grow(void *items, int *cap, int n, int most, size_t size)
{
	if (n < *cap)
		return items;
	int want = *cap ? 2 * *cap : 4;
	if (want > most)
		want = most;
	void *g = realloc(items, (size_t)want * size);
	if (g)
		*cap = want;
	return g;
}

static dp_status add_property(dp_io_stream *s, ply_header *h, char **tok, int ntok, dp_error *err)
{
	if (h->nelements == 0)
		return header_fail(s, "property before any element", NULL, err);
	ply_element *el = &h->elements[h->nelements - 1];
	if (el->nprops == PLY_MAX_PROPERTIES)
		return header_fail(s, "too many properties on element", el->name, err);
	ply_property *props = grow(el->props, &el->props_cap, el->nprops, PLY_MAX_PROPERTIES, sizeof *props);
	if (!props)
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for the PLY header", s->path);
	el->props = props;
	ply_property *p = &el->props[el->nprops];
	const char *name;
	memset(p, 0, sizeof *p);
	p->role = ROLE_NONE;
	if (ntok == 5 && strcmp(tok[1], "list") == 0) {
		p->is_list = 1;
		if (!parse_type(tok[2], &p->count_type))
			return header_fail(s, "unknown type", tok[2], err);
		if (p->count_type.kind == DP_IO_FLOAT)
			return header_fail(s, "list length type must be an integer type, not", tok[2], err);
		if (!parse_type(tok[3], &p->type))
			return header_fail(s, "unknown type", tok[3], err);
		name = tok[4];
	} else if (ntok == 3) {
		if (!parse_type(tok[1], &p->type))
			return header_fail(s, "unknown type", tok[1], err);
		name = tok[2];
	} else {
		return header_fail(s, "expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'", NULL, err);
	}
	if (strcmp(el->name, "vertex") == 0 && !p->is_list) {
		for (int r = ROLE_X; r <= ROLE_NZ; r++)
			if (strcmp(name, vertex_roles[r]) == 0)
				p->role = r;
		/* MeshLab and CloudCompare write red/green/blue; some tools diffuse_red... */
		const char *colour = strncmp(name, "diffuse_", 8) == 0 ? name + 8 : name;
		if (strcmp(colour, "red") == 0)
			p->role = ROLE_RED;
		else if (strcmp(colour, "green") == 0)
			p->role = ROLE_GREEN;
		else if (strcmp(colour, "blue") == 0)
			p->role = ROLE_BLUE;
		else if (strcasecmp(name, "intensity") == 0 || strcasecmp(name, "scalar_intensity") == 0)
			p->role = ROLE_INTENSITY;
	}
	if (strcmp(el->name, "face") == 0 && p->is_list &&
	    (strcmp(name, "vertex_indices") == 0 || strcmp(name, "vertex_index") == 0))
		p->role = ROLE_FACE;
	if (strcmp(el->name, "edge") == 0 && !p->is_list) {
		if (strcmp(name, "vertex1") == 0)
			p->role = ROLE_EDGE1;
		else if (strcmp(name, "vertex2") == 0)
			p->role = ROLE_EDGE2;
	}
	el->nprops++;
	return DP_OK;
}

static dp_status add_element(dp_io_stream *s, ply_header *h, char **tok, int ntok, dp_error *err)
{
	if (ntok != 3)
		return header_fail(s, "expected 'element NAME COUNT'", NULL, err);
	if (h->nelements == PLY_MAX_ELEMENTS)
		return header_fail(s, "too many elements", NULL, err);
	ply_element *elements = grow(h->elements, &h->elements_cap, h->nelements, PLY_MAX_ELEMENTS, sizeof *elements);
	if (!elements)
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for the PLY header", s->path);
	h->elements = elements;
	/* counted at once, so that dp_io_ply_header_free sees it whatever fails */
	ply_element *el = &h->elements[h->nelements++];
	memset(el, 0, sizeof *el);
	if (!dp_io_parse_count(tok[2], &el->count))
		return header_fail(s, "bad element count", tok[2], err);
	snprintf(el->name, sizeof el->name, "%s", tok[1]);
	if (strcmp(el->name, "vertex") == 0) {
		if (h->vertex >= 0)
			return header_fail(s, "second vertex element", NULL, err);
		h->vertex = h->nelements - 1;
	}
	return DP_OK;
}

void dp_io_ply_header_free(ply_header *h)
{
	for (int e = 0; e < h->nelements; e++)
		free(h->elements[e].props);
	free(h->elements);
	memset(h, 0, sizeof *h);
}

static dp_status set_format(dp_io_stream *s, ply_header *h, char **tok, int ntok, dp_error *err)
{
	if (ntok != 3)
		return header_fail(s, "expected 'format FORMAT VERSION'", NULL, err);
	if (strcmp(tok[1], "ascii") == 0)
		h->format = PLY_ASCII;
	else if (strcmp(tok[1], "binary_little_endian") == 0)
		h->format = PLY_BINARY_LE;
	else if (strcmp(tok[1], "binary_big_endian") == 0)
		h->format = PLY_BINARY_BE;
	else
		return header_fail(s, "unknown format", tok[1], err);
	return DP_OK;
}

/* A row without properties takes no bytes, so no file size bounds its count
 * and reading 2^64 of them never ends. */
static dp_status check_empty_rows(dp_io_stream *s, const ply_header *h, dp_error *err)
{
	for (int e = 0; e < h->nelements; e++) {
		const ply_element *el = &h->elements[e];
		if (el->nprops == 0 && el->count > 0)
			return dp_fail(err, DP_ERR_FORMAT, "%s: element '%s' declares %llu rows but has no properties",
				       s->path, el->name, (unsigned long long)el->count);
	}
	return DP_OK;
}

/* Checks that the vertex element has usable x, y, z and notes the normals. */
static dp_status check_vertex(dp_io_stream *s, ply_header *h, dp_error *err)
{
	if (h->vertex < 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: no vertex element in the header", s->path);
	const ply_element *el = &h->elements[h->vertex];
	int seen[ROLE_NZ + 1] = {0};
	for (int i = 0; i < el->nprops; i++)
		if (el->props[i].role >= ROLE_X && el->props[i].role <= ROLE_NZ)
			seen[el->props[i].role] = 1;
	if (!seen[ROLE_X] || !seen[ROLE_Y] || !seen[ROLE_Z])
		return dp_fail(err, DP_ERR_FORMAT, "%s: the vertex element lacks an x, y or z property", s->path);
	h->normals = seen[ROLE_NX] && seen[ROLE_NY] && seen[ROLE_NZ];
	int colours[3] = {0, 0, 0};
	for (int i = 0; i < el->nprops; i++)
		if (el->props[i].role >= ROLE_RED && el->props[i].role <= ROLE_BLUE)
			colours[el->props[i].role - ROLE_RED] = 1;
	h->colours = colours[0] && colours[1] && colours[2];
	h->intensity = 0;
	for (int i = 0; i < el->nprops; i++)
		h->intensity |= el->props[i].role == ROLE_INTENSITY;
	return DP_OK;
}

dp_status dp_io_ply_read_header(dp_io_stream *s, ply_header *h, dp_error *err)
{
	char *line, *tok[PLY_MAX_TOKENS];
	int have_format = 0;
	dp_status st = dp_io_line(s, &line, err);
	if (st != DP_OK)
		return st;
	if (!line || dp_io_split(line, tok, 1) != 1 || strcmp(tok[0], "ply") != 0)
		return dp_fail(err, DP_ERR_FORMAT, "%s: not a PLY file (the first line is not 'ply')", s->path);
	h->vertex = -1;
	for (;;) {
		if ((st = dp_io_line(s, &line, err)) != DP_OK)
			return st;
		if (!line)
			return dp_fail(err, DP_ERR_FORMAT, "%s: the header has no end_header line", s->path);
		if (strncmp(line, "comment", 7) == 0 || strncmp(line, "obj_info", 8) == 0)
			continue;
		int ntok = dp_io_split(line, tok, PLY_MAX_TOKENS);
		if (ntok == 0)
			continue;
		if (ntok > PLY_MAX_TOKENS)
			return header_fail(s, "too many words", NULL, err);
		if (strcmp(tok[0], "end_header") == 0)
			break;
		if (strcmp(tok[0], "format") == 0) {
			st = set_format(s, h, tok, ntok, err);
			have_format = 1;
		} else if (strcmp(tok[0], "element") == 0) {
			st = add_element(s, h, tok, ntok, err);
		} else if (strcmp(tok[0], "property") == 0) {
			st = add_property(s, h, tok, ntok, err);
		} else {
			st = header_fail(s, "unknown keyword", tok[0], err);
		}
		if (st != DP_OK)
			return st;
	}
	if (!have_format)
		return dp_fail(err, DP_ERR_FORMAT, "%s: the header has no format line", s->path);
	if ((st = check_empty_rows(s, h, err)) != DP_OK)
		return st;
	return check_vertex(s, h, err);
}
