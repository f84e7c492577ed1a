/* Built-in analytic shapes: definitions, exact volumes and the distance
 * functions that tests use to measure surfaces and skeletons. */
#include "tools/shapes.h"

#include "core/common.h"

#include <math.h>
#include <string.h>

/* The trefoil's core stays at least 1.21 s from its far strands and bends
 * with radius at least 1.29 s, so a tube of radius up to 0.5 s is embedded. */
#define KNOT_TUBE_MAX 0.5
/* Coarse polyline used to bracket the nearest core point before refining. */
#define KNOT_COARSE_SEGMENTS 512
/* Golden-section steps: the bracket shrinks by 0.618 per step, 60 steps
 * take it from 3 coarse segments to far below float precision. */
#define KNOT_REFINE_STEPS 60
/* Trapezoid nodes for the knot's length (the speed is a smooth periodic
 * function, so the rule converges geometrically). */
#define KNOT_LENGTH_NODES 4096

static const struct {
	const char *name;
	dp_shape shape;
} defaults[] = {
	{"sphere", {DP_SHAPE_SPHERE, 1.0, 0, 0, 0, 0, 0, 48}},
	{"cylinder", {DP_SHAPE_CYLINDER, 0.25, 2.0, 0, 0, 0, 0, 48}},
	{"slab", {DP_SHAPE_SLAB, 0, 0, 2.0, 0.2, 0, 0, 48}},
	{"torus", {DP_SHAPE_TORUS, 1.0, 0, 0, 0, 0.3, 0, 48}},
	{"knot", {DP_SHAPE_KNOT, 0.35, 0, 0, 0, 0.12, 0, 32}},
	{"chair", {DP_SHAPE_CHAIR, 0.05, 0.9, 1.0, 0.08, 0, 1.0, 32}},
	/* rods of radius 2-3 r at the default 4000 deep points: parts thinner
	 * than the σp = 5 r neighbourhoods */
	{"rods", {DP_SHAPE_RODS, 0.02, 1.0, 0.4, 0, 0, 0, 32}},
};
#define NSHAPES (sizeof defaults / sizeof defaults[0])

dp_status dp_shape_default(const char *name, dp_shape *shape, dp_error *err)
{
	for (size_t i = 0; name && i < NSHAPES; i++)
		if (strcmp(name, defaults[i].name) == 0) {
			*shape = defaults[i].shape;
			return DP_OK;
		}
	return dp_fail(err, DP_ERR_ARG,
		       "shape: unknown shape '%s' (valid: sphere, cylinder, slab, torus, knot, chair, rods)",
		       name ? name : "(null)");
}

const char *dp_shape_name(dp_shape_kind kind)
{
	for (size_t i = 0; i < NSHAPES; i++)
		if (defaults[i].shape.kind == kind)
			return defaults[i].name;
	return "unknown";
}

static int positive(double v)
{
	return isfinite(v) && v > 0;
}

dp_status dp_shape_check(const dp_shape *s, dp_error *err)
{
	int ok;
	switch (s->kind) {
	case DP_SHAPE_SPHERE: ok = positive(s->radius); break;
	case DP_SHAPE_CYLINDER: ok = positive(s->radius) && positive(s->length); break;
	case DP_SHAPE_SLAB: ok = positive(s->width) && positive(s->thickness); break;
	case DP_SHAPE_TORUS: ok = positive(s->radius) && positive(s->tube) && s->tube < s->radius; break;
	case DP_SHAPE_KNOT: ok = positive(s->radius) && positive(s->tube) && s->tube <= KNOT_TUBE_MAX * s->radius; break;
	case DP_SHAPE_CHAIR:
		ok = positive(s->radius) && positive(s->length) && positive(s->width) && positive(s->thickness) &&
		     positive(s->height) && s->width > 4 * DP_CHAIR_LEG_INSET * s->radius &&
		     s->thickness < s->width;
		break;
	case DP_SHAPE_RODS: ok = positive(s->radius) && positive(s->length) && s->width > 2 * s->radius; break;
	default: return dp_fail(err, DP_ERR_ARG, "shape: unknown kind %d", (int)s->kind);
	}
	if (!ok)
		return dp_fail(err, DP_ERR_ARG, "shape %s: dimensions out of range (radius %g, length %g, width %g, "
			       "thickness %g, tube %g, height %g)", dp_shape_name(s->kind), s->radius, s->length,
			       s->width, s->thickness, s->tube, s->height);
	if (s->resolution < DP_SHAPE_RESOLUTION_MIN || s->resolution > DP_SHAPE_RESOLUTION_MAX)
		return dp_fail(err, DP_ERR_ARG, "shape %s: resolution %d outside [%d, %d]", dp_shape_name(s->kind),
			       s->resolution, DP_SHAPE_RESOLUTION_MIN, DP_SHAPE_RESOLUTION_MAX);
	return DP_OK;
}

void dp_trefoil(double s, double t, double p[3])
{
	p[0] = s * (sin(t) + 2.0 * sin(2.0 * t));
	p[1] = s * (cos(t) - 2.0 * cos(2.0 * t));
	p[2] = -s * sin(3.0 * t);
}

void dp_trefoil_tangent(double t, double d[3])
{
	d[0] = cos(t) + 4.0 * cos(2.0 * t);
	d[1] = -sin(t) + 4.0 * sin(2.0 * t);
	d[2] = -3.0 * cos(3.0 * t);
	double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	for (int k = 0; k < 3; k++)
		d[k] /= len;
}

double dp_trefoil_length(double s)
{
	double total = 0;
	for (int i = 0; i < KNOT_LENGTH_NODES; i++) {
		double t = 2.0 * M_PI * i / KNOT_LENGTH_NODES;
		double a = cos(t) + 4.0 * cos(2.0 * t), b = -sin(t) + 4.0 * sin(2.0 * t), c = -3.0 * cos(3.0 * t);
		total += sqrt(a * a + b * b + c * c);
	}
	return s * total * 2.0 * M_PI / KNOT_LENGTH_NODES;
}

void dp_chair_layout(const dp_shape *s, dp_chair_parts *c)
{
	double w = 0.5 * s->width, top = s->length + s->thickness;
	double seat_lo[3] = {-w, -w, s->length}, seat_hi[3] = {w, w, top};
	double back_lo[3] = {-w, w - s->thickness, top}, back_hi[3] = {w, w, top + s->height};
	memcpy(c->seat_lo, seat_lo, sizeof seat_lo);
	memcpy(c->seat_hi, seat_hi, sizeof seat_hi);
	memcpy(c->back_lo, back_lo, sizeof back_lo);
	memcpy(c->back_hi, back_hi, sizeof back_hi);
	double off = w - DP_CHAIR_LEG_INSET * s->radius;
	for (int i = 0; i < 4; i++) {
		c->leg[i][0] = (i & 1) ? off : -off;
		c->leg[i][1] = (i & 2) ? off : -off;
		c->leg[i][2] = 0.5 * s->length;
	}
}

/* The face of the box [lo, hi] across `axis` on `side`. */
static dp_chair_rect box_face(const double lo[3], const double hi[3], int axis, int side)
{
	dp_chair_rect f = {.axis = axis, .side = side};
	memcpy(f.lo, lo, sizeof f.lo);
	memcpy(f.hi, hi, sizeof f.hi);
	if (side)
		f.lo[axis] = f.hi[axis];
	else
		f.hi[axis] = f.lo[axis];
	return f;
}

void dp_chair_rects(const dp_chair_parts *c, dp_chair_rect out[DP_CHAIR_RECTS])
{
	int k = 0;
	for (int axis = 0; axis < 2; axis++)
		for (int side = 0; side < 2; side++)
			out[k++] = box_face(c->seat_lo, c->seat_hi, axis, side);
	out[k] = box_face(c->seat_lo, c->seat_hi, 2, 1);
	out[k++].hi[1] = c->back_lo[1];
	for (int axis = 0; axis < 3; axis++)
		for (int side = 0; side < 2; side++)
			if (axis < 2 || side)
				out[k++] = box_face(c->back_lo, c->back_hi, axis, side);
}

void dp_rods_layout(const dp_shape *s, double axes[4][3])
{
	for (int i = 0; i < 4; i++) {
		axes[i][0] = (i & 1 ? 0.5 : -0.5) * s->width;
		axes[i][1] = (i & 2 ? 0.5 : -0.5) * s->width;
		axes[i][2] = 0.0;
	}
}

/* ----------------------------------------------------- analytic geometry */

static double len3(double x, double y, double z)
{
	return sqrt(x * x + y * y + z * z);
}

/* Signed distance to the box [lo, hi] (exact, negative inside). */
static double box_sdf(const double p[3], const double lo[3], const double hi[3])
{
	double q[3], out = 0, in = -INFINITY;
	for (int d = 0; d < 3; d++) {
		double c = 0.5 * (lo[d] + hi[d]), h = 0.5 * (hi[d] - lo[d]);
		q[d] = fabs(p[d] - c) - h;
		out += q[d] > 0 ? q[d] * q[d] : 0;
		in = fmax(in, q[d]);
	}
	return sqrt(out) + fmin(in, 0.0);
}

/* Signed distance to a capped cylinder with axis z through c (exact). */
static double cylinder_sdf(const double p[3], const double c[3], double radius, double length)
{
	double dr = hypot(p[0] - c[0], p[1] - c[1]) - radius, dz = fabs(p[2] - c[2]) - 0.5 * length;
	return hypot(fmax(dr, 0.0), fmax(dz, 0.0)) + fmin(fmax(dr, dz), 0.0);
}

/* Distance to the rectangle {lo <= x <= hi} with lo[d] == hi[d] on one axis. */
static double rect_distance(const double p[3], const double lo[3], const double hi[3])
{
	double e2 = 0;
	for (int d = 0; d < 3; d++) {
		double e = fmax(fmax(lo[d] - p[d], 0.0), p[d] - hi[d]);
		e2 += e * e;
	}
	return sqrt(e2);
}

/* Distance to the vertical segment through c of the given length. */
static double axis_distance(const double p[3], const double c[3], double length)
{
	double dz = fmax(fabs(p[2] - c[2]) - 0.5 * length, 0.0);
	return len3(p[0] - c[0], p[1] - c[1], dz);
}

static double knot_point_dist2(double s, double t, const double p[3])
{
	double c[3];
	dp_trefoil(s, t, c);
	return (c[0] - p[0]) * (c[0] - p[0]) + (c[1] - p[1]) * (c[1] - p[1]) + (c[2] - p[2]) * (c[2] - p[2]);
}

/* Golden-section minimum of the squared distance over t in [a, b]. */
static double knot_refine(double s, const double p[3], double a, double b)
{
	double golden = 0.5 * (sqrt(5.0) - 1.0);
	double x1 = b - golden * (b - a), x2 = a + golden * (b - a);
	double f1 = knot_point_dist2(s, x1, p), f2 = knot_point_dist2(s, x2, p);
	for (int k = 0; k < KNOT_REFINE_STEPS; k++) {
		if (f1 < f2) {
			b = x2;
			x2 = x1;
			f2 = f1;
			x1 = b - golden * (b - a);
			f1 = knot_point_dist2(s, x1, p);
		} else {
			a = x1;
			x1 = x2;
			f1 = f2;
			x2 = a + golden * (b - a);
			f2 = knot_point_dist2(s, x2, p);
		}
	}
	return fmin(f1, f2);
}

/* Nearest core point: every local minimum of the distance over the vertices
 * of a coarse polyline brackets a basin (the neighbouring vertices), which
 * golden-section search refines; the least of them is the global minimum. */
static double knot_core_distance(double s, const double p[3])
{
	double d2[KNOT_COARSE_SEGMENTS], step = 2.0 * M_PI / KNOT_COARSE_SEGMENTS, best = INFINITY;
	for (int i = 0; i < KNOT_COARSE_SEGMENTS; i++)
		d2[i] = knot_point_dist2(s, step * i, p);
	for (int i = 0; i < KNOT_COARSE_SEGMENTS; i++) {
		double prev = d2[(i + KNOT_COARSE_SEGMENTS - 1) % KNOT_COARSE_SEGMENTS];
		double next = d2[(i + 1) % KNOT_COARSE_SEGMENTS];
		if (d2[i] <= prev && d2[i] <= next)
			best = fmin(best, fmin(d2[i], knot_refine(s, p, step * (i - 1), step * (i + 1))));
	}
	return sqrt(best);
}

/* Distance to the boundary of the chair's solid, the faces shape_mesh.c
 * builds: every face of the parts but those inside it (the back's underside
 * and the seat's top beneath it, the legs' tops and the discs of the seat's
 * underside on them). */
static double chair_surface_distance(const dp_shape *s, const double p[3])
{
	dp_chair_parts c;
	dp_chair_layout(s, &c);
	dp_chair_rect rect[DP_CHAIR_RECTS];
	dp_chair_rects(&c, rect);
	double d = INFINITY;
	for (int k = 0; k < DP_CHAIR_RECTS; k++)
		d = fmin(d, rect_distance(p, rect[k].lo, rect[k].hi));
	/* the seat's underside: within a leg's disc the nearest point of the
	 * face is on the disc's rim (the discs lie well inside the face) */
	dp_chair_rect base = box_face(c.seat_lo, c.seat_hi, 2, 0);
	double under = rect_distance(p, base.lo, base.hi), dz = p[2] - c.seat_lo[2];
	for (int i = 0; i < 4; i++) {
		double rho = hypot(p[0] - c.leg[i][0], p[1] - c.leg[i][1]);
		double bottom = c.leg[i][2] - 0.5 * s->length;
		if (rho < s->radius)
			under = hypot(s->radius - rho, dz);
		d = fmin(d, hypot(rho - s->radius, fmax(fabs(p[2] - c.leg[i][2]) - 0.5 * s->length, 0.0)));
		d = fmin(d, hypot(fmax(rho - s->radius, 0.0), p[2] - bottom));
	}
	return fmin(d, under);
}

double dp_shape_volume(const dp_shape *s)
{
	if (dp_shape_check(s, NULL) != DP_OK)
		return NAN;
	switch (s->kind) {
	case DP_SHAPE_SPHERE: return 4.0 / 3.0 * M_PI * s->radius * s->radius * s->radius;
	case DP_SHAPE_CYLINDER: return M_PI * s->radius * s->radius * s->length;
	case DP_SHAPE_SLAB: return s->width * s->width * s->thickness;
	case DP_SHAPE_TORUS: return 2.0 * M_PI * M_PI * s->radius * s->tube * s->tube;
	case DP_SHAPE_KNOT: return M_PI * s->tube * s->tube * dp_trefoil_length(s->radius);
	case DP_SHAPE_CHAIR:
		return s->width * s->width * s->thickness + s->width * s->thickness * s->height +
		       4.0 * M_PI * s->radius * s->radius * s->length;
	case DP_SHAPE_RODS: return 4.0 * M_PI * s->radius * s->radius * s->length;
	}
	return NAN;
}

double dp_shape_surface_distance(const dp_shape *s, const double p[3])
{
	if (dp_shape_check(s, NULL) != DP_OK)
		return NAN;
	double origin[3] = {0, 0, 0};
	switch (s->kind) {
	case DP_SHAPE_SPHERE: return fabs(len3(p[0], p[1], p[2]) - s->radius);
	case DP_SHAPE_CYLINDER: return fabs(cylinder_sdf(p, origin, s->radius, s->length));
	case DP_SHAPE_SLAB: {
		double h = 0.5 * s->width, t = 0.5 * s->thickness;
		double lo[3] = {-h, -h, -t}, hi[3] = {h, h, t};
		return fabs(box_sdf(p, lo, hi));
	}
	case DP_SHAPE_TORUS: return fabs(hypot(hypot(p[0], p[1]) - s->radius, p[2]) - s->tube);
	case DP_SHAPE_KNOT: return fabs(knot_core_distance(s->radius, p) - s->tube);
	case DP_SHAPE_CHAIR: return chair_surface_distance(s, p);
	case DP_SHAPE_RODS: {
		double axes[4][3], d = INFINITY;
		dp_rods_layout(s, axes);
		for (int i = 0; i < 4; i++)
			d = fmin(d, fabs(cylinder_sdf(p, axes[i], s->radius, s->length)));
		return d;
	}
	}
	return NAN;
}

double dp_shape_skeleton_distance(const dp_shape *s, const double p[3])
{
	if (dp_shape_check(s, NULL) != DP_OK)
		return NAN;
	double origin[3] = {0, 0, 0};
	switch (s->kind) {
	case DP_SHAPE_SPHERE: return len3(p[0], p[1], p[2]);
	case DP_SHAPE_CYLINDER: return axis_distance(p, origin, s->length);
	case DP_SHAPE_SLAB: {
		double h = 0.5 * s->width, lo[3] = {-h, -h, 0}, hi[3] = {h, h, 0};
		return rect_distance(p, lo, hi);
	}
	case DP_SHAPE_TORUS: return hypot(hypot(p[0], p[1]) - s->radius, p[2]);
	case DP_SHAPE_KNOT: return knot_core_distance(s->radius, p);
	case DP_SHAPE_CHAIR: {
		dp_chair_parts c;
		dp_chair_layout(s, &c);
		double seat_z = 0.5 * (c.seat_lo[2] + c.seat_hi[2]), back_y = 0.5 * (c.back_lo[1] + c.back_hi[1]);
		double slo[3] = {c.seat_lo[0], c.seat_lo[1], seat_z}, shi[3] = {c.seat_hi[0], c.seat_hi[1], seat_z};
		double blo[3] = {c.back_lo[0], back_y, c.back_lo[2]}, bhi[3] = {c.back_hi[0], back_y, c.back_hi[2]};
		double d = fmin(rect_distance(p, slo, shi), rect_distance(p, blo, bhi));
		for (int i = 0; i < 4; i++)
			d = fmin(d, axis_distance(p, c.leg[i], s->length));
		return d;
	}
	case DP_SHAPE_RODS: {
		double axes[4][3], d = INFINITY;
		dp_rods_layout(s, axes);
		for (int i = 0; i < 4; i++)
			d = fmin(d, axis_distance(p, axes[i], s->length));
		return d;
	}
	}
	return NAN;
}

dp_status dp_shape_core_curve(const dp_shape *shape, size_t n, dp_cloud *out, dp_error *err)
{
	memset(out, 0, sizeof *out);
	dp_status st = dp_shape_check(shape, err);
	if (st != DP_OK)
		return st;
	if (n < 2)
		return dp_fail(err, DP_ERR_ARG, "shape %s: core curve needs at least 2 samples, got %zu",
			       dp_shape_name(shape->kind), n);
	dp_shape_kind k = shape->kind;
	if (k != DP_SHAPE_CYLINDER && k != DP_SHAPE_TORUS && k != DP_SHAPE_KNOT)
		return dp_fail(err, DP_ERR_ARG, "shape %s: has no single core curve (cylinder, torus, knot have)",
			       dp_shape_name(k));
	st = dp_cloud_alloc(out, n, 0, err);
	if (st != DP_OK)
		return st;
	for (size_t i = 0; i < n; i++) {
		double p[3], t = 2.0 * M_PI * (double)i / (double)n;
		if (k == DP_SHAPE_CYLINDER) {
			p[0] = p[1] = 0;
			p[2] = shape->length * ((double)i / (double)(n - 1) - 0.5);
		} else if (k == DP_SHAPE_TORUS) {
			p[0] = shape->radius * cos(t);
			p[1] = shape->radius * sin(t);
			p[2] = 0;
		} else {
			dp_trefoil(shape->radius, t, p);
		}
		out->x[i] = (float)p[0];
		out->y[i] = (float)p[1];
		out->z[i] = (float)p[2];
	}
	return DP_OK;
}
