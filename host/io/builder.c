#include "io/io.h"

#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* First allocation when the count is unknown; doubling from here keeps the
 * number of reallocations logarithmic. */
#define BUILDER_MIN_CAP 4096

void dp_io_builder_init(dp_io_builder *b, const char *path)
{
	memset(b, 0, sizeof *b);
	b->path = path;
}

void dp_io_builder_free(dp_io_builder *b)
{
	const char *path = b->path;
	dp_cloud_free(&b->c);
	memset(b, 0, sizeof *b);
	b->path = path;
}

/* Turns on one per-point array (*flag) before any point is added, and
 * allocates it at the current capacity. */
static dp_status want(dp_io_builder *b, int *flag, const char *what, dp_error *err)
{
	if (b->c.n > 0)
		return dp_fail(err, DP_ERR_INTERNAL, "io builder: %s requested after points were added", what);
	*flag = 1;
	size_t cap = b->cap;
	b->cap = 0;
	return dp_io_builder_reserve(b, cap, err);
}

dp_status dp_io_builder_want_normals(dp_io_builder *b, dp_error *err)
{
	return want(b, &b->normals, "normals", err);
}

dp_status dp_io_builder_want_colours(dp_io_builder *b, dp_error *err)
{
	return want(b, &b->colours, "colours", err);
}

void dp_io_builder_set_rgb(dp_io_builder *b, size_t index, const unsigned char rgb[3])
{
	if (b->colours && index < b->c.n)
		memcpy(b->c.rgb + 3 * index, rgb, 3);
}

dp_status dp_io_builder_want_intensity(dp_io_builder *b, dp_error *err)
{
	return want(b, &b->intensities, "intensities", err);
}

void dp_io_builder_set_intensity(dp_io_builder *b, size_t index, float value)
{
	if (b->intensities && index < b->c.n)
		b->c.intensity[index] = value;
}

/* realloc that leaves *p untouched on failure, so every array stays owned. */
static int grow_array(float **p, size_t n)
{
	float *q = realloc(*p, (n ? n : 1) * sizeof **p);
	if (!q)
		return 0;
	*p = q;
	return 1;
}

dp_status dp_io_builder_reserve(dp_io_builder *b, size_t n, dp_error *err)
{
	if (n <= b->cap)
		return DP_OK;
	if (n > SIZE_MAX / 2 / sizeof(float))
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu points", b->path, n);
	float **arrays[6] = {&b->c.x, &b->c.y, &b->c.z, &b->c.nx, &b->c.ny, &b->c.nz};
	int count = b->normals ? 6 : 3;
	for (int i = 0; i < count; i++)
		if (!grow_array(arrays[i], n))
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu points", b->path, n);
	if (b->colours) {
		unsigned char *rgb = realloc(b->c.rgb, 3 * (n ? n : 1));
		if (!rgb)
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu colours", b->path, n);
		b->c.rgb = rgb;
	}
	if (b->intensities && !grow_array(&b->c.intensity, n))
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu intensities", b->path, n);
	b->cap = n;
	return DP_OK;
}

dp_status dp_io_builder_add(dp_io_builder *b, float x, float y, float z, const float *normal,
			    dp_error *err)
{
	if (b->c.n == b->cap) {
		size_t cap = b->cap < BUILDER_MIN_CAP ? BUILDER_MIN_CAP : 2 * b->cap;
		dp_status st = dp_io_builder_reserve(b, cap, err);
		if (st != DP_OK)
			return st;
	}
	size_t i = b->c.n++;
	b->c.x[i] = x;
	b->c.y[i] = y;
	b->c.z[i] = z;
	if (b->normals) {
		b->c.nx[i] = normal[0];
		b->c.ny[i] = normal[1];
		b->c.nz[i] = normal[2];
	}
	if (b->colours)
		memset(b->c.rgb + 3 * i, 0, 3);
	if (b->intensities)
		b->c.intensity[i] = 0.0f;
	return DP_OK;
}

dp_status dp_io_builder_add_triangle(dp_io_builder *b, uint32_t a, uint32_t v1, uint32_t v2,
				     dp_error *err)
{
	if (b->c.nfaces == b->face_cap) {
		size_t cap = b->face_cap < BUILDER_MIN_CAP ? BUILDER_MIN_CAP : 2 * b->face_cap;
		if (cap > SIZE_MAX / 3 / sizeof(uint32_t))
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu triangles", b->path, cap);
		uint32_t *faces = realloc(b->c.faces, 3 * cap * sizeof *faces);
		if (!faces)
			return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory for %zu triangles", b->path, cap);
		b->c.faces = faces;
		b->face_cap = cap;
	}
	uint32_t *t = b->c.faces + 3 * b->c.nfaces++;
	t[0] = a;
	t[1] = v1;
	t[2] = v2;
	return DP_OK;
}

dp_status dp_io_fan_add(dp_io_builder *b, dp_io_fan *fan, uint32_t index, dp_error *err)
{
	dp_status st = DP_OK;
	if (fan->count == 0)
		fan->first = index;
	else if (fan->count >= 2)
		st = dp_io_builder_add_triangle(b, fan->first, fan->prev, index, err);
	fan->prev = index;
	fan->count++;
	return st;
}

/* Gives back the slack left by geometric growth; keeps the block if the
 * smaller realloc fails. */
static void *trimmed(void *p, size_t bytes)
{
	if (!p)
		return NULL;
	void *q = realloc(p, bytes ? bytes : 1);
	return q ? q : p;
}

dp_status dp_io_builder_finish(dp_io_builder *b, const char *path, dp_cloud *cloud, dp_error *err)
{
	dp_cloud *c = &b->c;
	memset(cloud, 0, sizeof *cloud);
	if (c->n == 0)
		return dp_fail(err, DP_ERR_EMPTY, "%s: no points", path);
	for (size_t i = 0; i < c->n; i++) {
		float normal[3];
		if (b->normals) {
			normal[0] = c->nx[i];
			normal[1] = c->ny[i];
			normal[2] = c->nz[i];
		}
		dp_status st = dp_io_check_finite(path, i, c->x[i], c->y[i], c->z[i],
						  b->normals ? normal : NULL, err);
		if (st != DP_OK)
			return st;
		if (b->intensities && !isfinite(c->intensity[i]))
			return dp_fail(err, DP_ERR_FORMAT, "%s: point %zu (counting from 0) has a non-finite intensity",
				       path, i);
	}
	for (size_t i = 0; i < 3 * c->nfaces; i++)
		if (c->faces[i] >= c->n)
			return dp_fail(err, DP_ERR_FORMAT,
				       "%s: triangle %zu refers to vertex %u (counting from 0) but there are %zu vertices",
				       path, i / 3, c->faces[i], c->n);
	size_t bytes = c->n * sizeof(float);
	c->x = trimmed(c->x, bytes);
	c->y = trimmed(c->y, bytes);
	c->z = trimmed(c->z, bytes);
	c->nx = trimmed(c->nx, bytes);
	c->ny = trimmed(c->ny, bytes);
	c->nz = trimmed(c->nz, bytes);
	c->rgb = trimmed(c->rgb, 3 * c->n);
	c->intensity = trimmed(c->intensity, bytes);
	if (c->nfaces == 0) {
		free(c->faces);
		c->faces = NULL;
	} else {
		c->faces = trimmed(c->faces, 3 * c->nfaces * sizeof(uint32_t));
	}
	*cloud = *c;
	memset(b, 0, sizeof *b);
	return DP_OK;
}
