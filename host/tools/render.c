/* Pictures of point sets: z-buffered splats and segments seen by orthographic
 * cameras orbiting the scene, so a person can see what a stage did. */
#include "core/common.h"
#include "tools/png_write.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_WIDTH 512
#define DEFAULT_VIEWS 3
#define DEFAULT_UP_AXIS 1           /* y: the Stanford scans and most PLY files stand on y */
#define DEFAULT_ELEVATION_DEG 20.0  /* a little from above shows tops as well as sides */
/* Views live on the stack; more than this would be too narrow to look at. */
#define MAX_VIEWS 64
/* 7 bytes per pixel (colour + depth): caps the buffers at about 235 MB. */
#define MAX_PIXELS ((size_t)1 << 25)
/* Fraction of the view left empty on each side so splats on the bounding box
 * stay inside the picture. */
#define FIT_MARGIN 0.05
/* Lambert shading: surfaces edge-on to the viewer keep this much of their
 * colour, so silhouettes stay recognisable rather than black. */
#define AMBIENT 0.25f
/* Depth shading: the farthest points keep this much of their colour. */
#define DEPTH_SHADE_MIN 0.35f
/* Auto splat radius = AUTO_SPLAT_FACTOR * the mean spacing of the points on
 * their surface, in pixels: a radius of spacing/sqrt(3) just covers a
 * hexagonal sampling, and irregular scans need some more. */
#define AUTO_SPLAT_FACTOR 0.75
/* The surface area behind that spacing is counted in cubic cells of an
 * occupancy grid. Cells must be coarser than the spacing, or empty cells
 * make the area (and the splats) too small: the grid is sized so a surface
 * as large as one face of its box gets this many points per cell (a sphere,
 * pi faces large, still gets about five). */
#define AREA_POINTS_PER_CELL 16.0
/* 256^3 bits = 2 MB, enough to measure a million points. */
#define AREA_MAX_CELLS_PER_AXIS 256
/* Sparse sets must not become blobs: at most this fraction of the span. */
#define AUTO_SPLAT_MAX_FRACTION (1.0 / 64.0)
/* Half a pixel diagonal: the pixel a point falls into is always covered. */
#define MIN_SPLAT_RADIUS 0.7072f

/* One orthographic view: screen axes right/up and the direction towards the
 * camera; depth grows towards the camera. */
typedef struct view {
	double right[3], up[3], toward[3];
	double depth_min, depth_max;  /* over the bounding box, for depth shading */
	int x0;                       /* first image column of this view */
} view;

typedef struct scene {
	double centre[3];
	double scale;                 /* pixels per unit length, shared by every view */
	int width, height;            /* of the whole image */
	int view_width;
	unsigned char *rgb;
	float *depth;
} scene;

typedef struct projected {
	float x, y, depth;
} projected;

void dp_render_params_default(dp_render_params *p)
{
	memset(p, 0, sizeof *p);
	p->width = DEFAULT_WIDTH;
	p->views = DEFAULT_VIEWS;
	p->up_axis = DEFAULT_UP_AXIS;
	p->elevation_deg = DEFAULT_ELEVATION_DEG;
	p->azimuth_deg = 0.0;
	p->background[0] = p->background[1] = p->background[2] = 255;
}

static int point_finite(const dp_cloud *c, size_t i)
{
	return isfinite(c->x[i]) && isfinite(c->y[i]) && isfinite(c->z[i]);
}

static dp_status check_params(const dp_render_params *p, dp_error *err)
{
	if (p->width < 1)
		return dp_fail(err, DP_ERR_ARG, "render: view size %d is not positive", p->width);
	if (p->views < 1 || p->views > MAX_VIEWS)
		return dp_fail(err, DP_ERR_ARG, "render: %d views outside 1..%d", p->views, MAX_VIEWS);
	if ((size_t)p->width > MAX_PIXELS / (size_t)p->views / (size_t)p->width)
		return dp_fail(err, DP_ERR_ARG, "render: %d views of %d pixels exceed %zu pixels", p->views,
			       p->width, MAX_PIXELS);
	if (p->up_axis < 0 || p->up_axis > 2)
		return dp_fail(err, DP_ERR_ARG, "render: up axis %d is not 0 (x), 1 (y) or 2 (z)", p->up_axis);
	if (!(fabs(p->elevation_deg) <= 90.0))
		return dp_fail(err, DP_ERR_ARG, "render: elevation %g outside -90..90 degrees", p->elevation_deg);
	if (!isfinite(p->azimuth_deg))
		return dp_fail(err, DP_ERR_ARG, "render: azimuth is not finite");
	return DP_OK;
}

static dp_status check_layers(const dp_render_layer *layers, size_t nlayers, dp_error *err)
{
	if (nlayers > 0 && !layers)
		return dp_fail(err, DP_ERR_ARG, "render: no layer array");
	for (size_t l = 0; l < nlayers; l++) {
		const dp_render_layer *layer = &layers[l];
		const dp_cloud *c = layer->cloud;
		if (!c || (c->n > 0 && (!c->x || !c->y || !c->z)))
			return dp_fail(err, DP_ERR_ARG, "render: layer %zu has no points array", l);
		if (!(layer->point_size_px >= 0.0f) || !isfinite(layer->point_size_px))
			return dp_fail(err, DP_ERR_ARG, "render: layer %zu point size %g is not >= 0", l,
				       (double)layer->point_size_px);
		if (layer->nedges > 0 && !layer->edges)
			return dp_fail(err, DP_ERR_ARG, "render: layer %zu has %zu edges but no array", l,
				       layer->nedges);
		for (size_t e = 0; e < 2 * layer->nedges; e++)
			if (layer->edges[e] >= c->n)
				return dp_fail(err, DP_ERR_ARG,
					       "render: layer %zu edge %zu uses point %u of %zu", l, e / 2,
					       (unsigned)layer->edges[e], c->n);
	}
	return DP_OK;
}

/* Union bounding box of every finite point; returns how many there are. */
static size_t bounding_box(const dp_render_layer *layers, size_t nlayers, double lo[3], double hi[3])
{
	size_t count = 0;
	for (int a = 0; a < 3; a++) {
		lo[a] = INFINITY;
		hi[a] = -INFINITY;
	}
	for (size_t l = 0; l < nlayers; l++) {
		const dp_cloud *c = layers[l].cloud;
		for (size_t i = 0; i < c->n; i++) {
			if (!point_finite(c, i))
				continue;
			const double p[3] = { c->x[i], c->y[i], c->z[i] };
			for (int a = 0; a < 3; a++) {
				lo[a] = fmin(lo[a], p[a]);
				hi[a] = fmax(hi[a], p[a]);
			}
			count++;
		}
	}
	return count;
}

static double dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Cameras orbit the up axis: (up, h1, h2) is a right-handed frame of
 * coordinate axes, azimuth 0 puts the camera on +h1 with +h2 to the right. */
static void place_view(view *v, const dp_render_params *p, int k)
{
	const double deg = M_PI / 180.0;
	double az = (p->azimuth_deg + 360.0 * k / p->views) * deg;
	double el = p->elevation_deg * deg;
	double up[3] = { 0 }, h1[3] = { 0 }, h2[3] = { 0 };
	up[p->up_axis] = 1.0;
	h1[(p->up_axis + 1) % 3] = 1.0;
	h2[(p->up_axis + 2) % 3] = 1.0;
	for (int a = 0; a < 3; a++) {
		double horizontal = cos(az) * h1[a] + sin(az) * h2[a];
		v->toward[a] = cos(el) * horizontal + sin(el) * up[a];
		v->right[a] = cos(az) * h2[a] - sin(az) * h1[a];
		v->up[a] = cos(el) * up[a] - sin(el) * horizontal;
	}
	v->x0 = k * p->width;
}

/* Centres the box in every view and picks the one scale at which its corners
 * fit inside every view, so sizes compare across views. */
static void fit_camera(scene *s, view *views, const dp_render_params *p, const double lo[3],
		       const double hi[3])
{
	double extent = 0.0;
	for (int a = 0; a < 3; a++)
		s->centre[a] = 0.5 * (lo[a] + hi[a]);
	for (int k = 0; k < p->views; k++) {
		view *v = &views[k];
		place_view(v, p, k);
		v->depth_min = INFINITY;
		v->depth_max = -INFINITY;
		for (int corner = 0; corner < 8; corner++) {
			double d[3];
			for (int a = 0; a < 3; a++)
				d[a] = ((corner >> a) & 1 ? hi[a] : lo[a]) - s->centre[a];
			extent = fmax(extent, fmax(fabs(dot3(d, v->right)), fabs(dot3(d, v->up))));
			v->depth_min = fmin(v->depth_min, dot3(d, v->toward));
			v->depth_max = fmax(v->depth_max, dot3(d, v->toward));
		}
	}
	double half = 0.5 * p->width * (1.0 - 2.0 * FIT_MARGIN);
	/* A single point (or all points equal) has no extent: any scale shows it. */
	s->scale = extent > 0.0 ? half / extent : 1.0;
}

static projected project(const scene *s, const view *v, const dp_cloud *c, size_t i)
{
	const double d[3] = { c->x[i] - s->centre[0], c->y[i] - s->centre[1], c->z[i] - s->centre[2] };
	projected q;
	q.x = (float)(v->x0 + 0.5 * s->view_width + s->scale * dot3(d, v->right));
	q.y = (float)(0.5 * s->view_width - s->scale * dot3(d, v->up));
	q.depth = (float)dot3(d, v->toward);
	return q;
}

static float depth_shade(const view *v, float depth)
{
	double range = v->depth_max - v->depth_min;
	double t = range > 0.0 ? (depth - v->depth_min) / range : 1.0;
	t = fmin(1.0, fmax(0.0, t));
	return DEPTH_SHADE_MIN + (1.0f - DEPTH_SHADE_MIN) * (float)t;
}

/* Lambert towards the viewer with |n.v|, so flipped normals are lit too;
 * points without a usable normal fall back to depth shading. */
static float point_shade(const view *v, const dp_cloud *c, size_t i, float depth)
{
	if (!c->nx)
		return depth_shade(v, depth);
	const double n[3] = { c->nx[i], c->ny[i], c->nz[i] };
	double len2 = dot3(n, n);
	if (!(len2 > 0.0) || !isfinite(len2))
		return depth_shade(v, depth);
	double lambert = fmin(1.0, fabs(dot3(n, v->toward)) / sqrt(len2));
	return AMBIENT + (1.0f - AMBIENT) * (float)lambert;
}

static void put_pixel(scene *s, int x, int y, float depth, const unsigned char rgb[3], float shade)
{
	size_t at = (size_t)y * (size_t)s->width + (size_t)x;
	if (!(depth > s->depth[at]))
		return;
	s->depth[at] = depth;
	for (int c = 0; c < 3; c++)
		s->rgb[3 * at + c] = (unsigned char)lrintf(rgb[c] * shade);
}

static void splat(scene *s, const view *v, projected q, float radius, const unsigned char rgb[3], float shade)
{
	int xlo = (int)floorf(q.x - radius), xhi = (int)floorf(q.x + radius);
	int ylo = (int)floorf(q.y - radius), yhi = (int)floorf(q.y + radius);
	if (xlo < v->x0)
		xlo = v->x0;
	if (xhi > v->x0 + s->view_width - 1)
		xhi = v->x0 + s->view_width - 1;
	if (ylo < 0)
		ylo = 0;
	if (yhi > s->height - 1)
		yhi = s->height - 1;
	for (int y = ylo; y <= yhi; y++) {
		float dy = (float)y + 0.5f - q.y;
		for (int x = xlo; x <= xhi; x++) {
			float dx = (float)x + 0.5f - q.x;
			if (dx * dx + dy * dy <= radius * radius)
				put_pixel(s, x, y, q.depth, rgb, shade);
		}
	}
}

/* DDA: one pixel per step along the longer screen axis, depth interpolated. */
static void segment(scene *s, const view *v, projected a, projected b, const unsigned char rgb[3])
{
	float dx = b.x - a.x, dy = b.y - a.y, dz = b.depth - a.depth;
	int steps = (int)ceilf(fmaxf(fabsf(dx), fabsf(dy)));
	if (steps < 1)
		steps = 1;
	for (int k = 0; k <= steps; k++) {
		float t = (float)k / (float)steps;
		int x = (int)floorf(a.x + t * dx), y = (int)floorf(a.y + t * dy);
		float depth = a.depth + t * dz;
		if (x >= v->x0 && x < v->x0 + s->view_width && y >= 0 && y < s->height)
			put_pixel(s, x, y, depth, rgb, depth_shade(v, depth));
	}
}

/* Mean spacing of the finite points of `c` on the surface they sample:
 * sqrt(area / n), the area counted as occupied grid cells times a cell's
 * face. 0 when the points do not span a volume cell (one point, all equal). */
static dp_status surface_spacing(const dp_cloud *c, double *spacing, dp_error *err)
{
	double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
	size_t n = 0;
	for (size_t i = 0; i < c->n; i++) {
		if (!point_finite(c, i))
			continue;
		const double p[3] = { c->x[i], c->y[i], c->z[i] };
		for (int a = 0; a < 3; a++) {
			lo[a] = fmin(lo[a], p[a]);
			hi[a] = fmax(hi[a], p[a]);
		}
		n++;
	}
	*spacing = 0.0;
	double extent = n ? fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2])) : 0.0;
	if (!(extent > 0.0))
		return DP_OK;
	double cells = ceil(sqrt((double)n / AREA_POINTS_PER_CELL));
	size_t g = (size_t)fmin(fmax(cells, 1.0), AREA_MAX_CELLS_PER_AXIS);
	double cell = extent / (double)g;
	size_t nbits = g * g * g;
	unsigned char *occupied = calloc((nbits + 7) / 8, 1);
	if (!occupied)
		return dp_fail(err, DP_ERR_NOMEM, "render: out of memory for the splat size grid");
	size_t count = 0;
	for (size_t i = 0; i < c->n; i++) {
		if (!point_finite(c, i))
			continue;
		const double p[3] = { c->x[i], c->y[i], c->z[i] };
		size_t at = 0;
		for (int a = 0; a < 3; a++) {
			size_t k = (size_t)((p[a] - lo[a]) / cell);
			at = at * g + (k < g ? k : g - 1);
		}
		if (!(occupied[at / 8] & (1u << (at % 8)))) {
			occupied[at / 8] |= (unsigned char)(1u << (at % 8));
			count++;
		}
	}
	free(occupied);
	*spacing = sqrt((double)count * cell * cell / (double)n);
	return DP_OK;
}

static dp_status splat_radius(const scene *s, const dp_render_layer *layer, float *radius, dp_error *err)
{
	/* Larger than the view would only cost time (and overflow pixel indices). */
	if (layer->point_size_px > 0.0f) {
		*radius = fminf(fmaxf(0.5f * layer->point_size_px, MIN_SPLAT_RADIUS), (float)s->view_width);
		return DP_OK;
	}
	double spacing;
	dp_status st = surface_spacing(layer->cloud, &spacing, err);
	if (st != DP_OK)
		return st;
	double largest = AUTO_SPLAT_MAX_FRACTION * s->view_width * (1.0 - 2.0 * FIT_MARGIN);
	double r = spacing > 0.0 ? fmin(AUTO_SPLAT_FACTOR * spacing * s->scale, largest) : largest;
	*radius = fmaxf((float)r, MIN_SPLAT_RADIUS);
	return DP_OK;
}

static void draw_layer(scene *s, const view *v, const dp_render_layer *layer, float radius)
{
	const dp_cloud *c = layer->cloud;
	if (!layer->segments_only) {
		for (size_t i = 0; i < c->n; i++) {
			if (!point_finite(c, i))
				continue;
			projected q = project(s, v, c, i);
			splat(s, v, q, radius, layer->rgb, point_shade(v, c, i, q.depth));
		}
	}
	for (size_t e = 0; e < layer->nedges; e++) {
		uint32_t i = layer->edges[2 * e], j = layer->edges[2 * e + 1];
		if (!point_finite(c, i) || !point_finite(c, j))
			continue;
		segment(s, v, project(s, v, c, i), project(s, v, c, j), layer->rgb);
	}
}

dp_status dp_render_rgb(const dp_render_layer *layers, size_t nlayers, const dp_render_params *params,
			unsigned char **rgb, int *w, int *h, dp_error *err)
{
	dp_render_params defaults;
	if (!params) {
		dp_render_params_default(&defaults);
		params = &defaults;
	}
	if (!rgb || !w || !h)
		return dp_fail(err, DP_ERR_ARG, "render: no output image");
	*rgb = NULL;
	*w = *h = 0;
	dp_status st = check_params(params, err);
	if (st == DP_OK)
		st = check_layers(layers, nlayers, err);
	if (st != DP_OK)
		return st;
	double lo[3], hi[3];
	if (bounding_box(layers, nlayers, lo, hi) == 0)
		return dp_fail(err, DP_ERR_EMPTY, "render: no finite point in %zu layer(s)", nlayers);

	view views[MAX_VIEWS];
	scene s = { .view_width = params->width, .width = params->views * params->width,
		    .height = params->width };
	fit_camera(&s, views, params, lo, hi);
	size_t npixels = (size_t)s.width * (size_t)s.height;
	s.rgb = dp_alloc_array(npixels, 3);
	s.depth = dp_alloc_array(npixels, sizeof(float));
	if (!s.rgb || !s.depth) {
		free(s.rgb);
		free(s.depth);
		return dp_fail(err, DP_ERR_NOMEM, "render: out of memory for a %dx%d image", s.width, s.height);
	}
	for (size_t at = 0; at < npixels; at++) {
		memcpy(s.rgb + 3 * at, params->background, 3);
		s.depth[at] = -INFINITY;
	}
	for (size_t l = 0; l < nlayers && st == DP_OK; l++) {
		float radius;
		st = splat_radius(&s, &layers[l], &radius, err);
		for (int k = 0; k < params->views && st == DP_OK; k++)
			draw_layer(&s, &views[k], &layers[l], radius);
	}
	free(s.depth);
	if (st != DP_OK) {
		free(s.rgb);
		return st;
	}
	*rgb = s.rgb;
	*w = s.width;
	*h = s.height;
	return DP_OK;
}

dp_status dp_render_png(const char *path, const dp_render_layer *layers, size_t nlayers,
			const dp_render_params *params, dp_error *err)
{
	if (!path)
		return dp_fail(err, DP_ERR_ARG, "render: no output path");
	unsigned char *rgb;
	int w, h;
	dp_status st = dp_render_rgb(layers, nlayers, params, &rgb, &w, &h, err);
	if (st != DP_OK) {
		/* Name the picture that was not made: the caller may render several. */
		if (err) {
			char reason[DP_ERROR_MESSAGE_MAX];
			memcpy(reason, err->message, sizeof reason);
			dp_fail(err, st, "%s: %s", path, reason);
		}
		return st;
	}
	st = dp_png_write_rgb(path, rgb, w, h, err);
	free(rgb);
	return st;
}
