/* Triangulation of the built-in shapes: closed, outward-wound meshes (the
 * chair's pieces meet along their edges without sharing vertices). */
#include "tools/shapes.h"

#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Writes vertices and faces into a preallocated mesh, or only counts them
 * when `m` is NULL, so every generator runs once to size and once to fill. */
typedef struct builder {
	dp_cloud *m;
	size_t nv, nf;
	int nomem;
} builder;

static uint32_t add_vertex(builder *b, double x, double y, double z)
{
	if (b->m) {
		b->m->x[b->nv] = (float)x;
		b->m->y[b->nv] = (float)y;
		b->m->z[b->nv] = (float)z;
	}
	return (uint32_t)b->nv++;
}

static void add_triangle(builder *b, uint32_t i, uint32_t j, uint32_t k)
{
	if (b->m) {
		b->m->faces[3 * b->nf] = i;
		b->m->faces[3 * b->nf + 1] = j;
		b->m->faces[3 * b->nf + 2] = k;
	}
	b->nf++;
}

/* a, b, c, d counter-clockwise seen from outside. */
static void add_quad(builder *b, uint32_t a, uint32_t bb, uint32_t c, uint32_t d)
{
	add_triangle(b, a, bb, c);
	add_triangle(b, a, c, d);
}

/* Quads between consecutive rows of `cols` vertices starting at `base`
 * (columns wrap; rows wrap when `wrap_rows`). Outward when the row direction
 * crossed with the column direction points outwards. */
static void connect_rows(builder *b, uint32_t base, int rows, int cols, int wrap_rows)
{
	int last = wrap_rows ? rows : rows - 1;
	for (int k = 0; k < last; k++) {
		uint32_t r0 = base + (uint32_t)(k * cols), r1 = base + (uint32_t)(((k + 1) % rows) * cols);
		for (int j = 0; j < cols; j++) {
			int j1 = (j + 1) % cols;
			add_quad(b, r0 + j, r1 + j, r1 + j1, r0 + j1);
		}
	}
}

/* A surface of revolution about the vertical line through `c`: row k of the
 * profile is a circle of radius r at height c[2] + z. A profile either wraps
 * (a torus), starts and ends on the axis (poles), or starts on a rim and ends
 * on the axis (a leg open at the top, where it meets the seat). It must run
 * so that (d profile) x (d azimuth) points outwards. */
typedef void (*profile_fn)(const void *ctx, int row, double *r, double *z);

enum revolve_ends { REVOLVE_WRAP, REVOLVE_POLES, REVOLVE_OPEN_TOP };

static void revolve(builder *b, const double c[3], profile_fn profile, const void *ctx, int rows, int cols,
		    enum revolve_ends ends)
{
	double r, z;
	int wrap = ends == REVOLVE_WRAP, north_pole = ends == REVOLVE_POLES;
	int first = north_pole ? 1 : 0, end = wrap ? rows : rows - 1;
	uint32_t north = 0, south = 0;
	if (north_pole) {
		profile(ctx, 0, &r, &z);
		north = add_vertex(b, c[0], c[1], c[2] + z);
	}
	uint32_t base = (uint32_t)b->nv;
	for (int k = first; k < end; k++) {
		profile(ctx, k, &r, &z);
		for (int j = 0; j < cols; j++) {
			double phi = 2.0 * M_PI * j / cols;
			add_vertex(b, c[0] + r * cos(phi), c[1] + r * sin(phi), c[2] + z);
		}
	}
	connect_rows(b, base, end - first, cols, wrap);
	if (wrap)
		return;
	profile(ctx, rows - 1, &r, &z);
	south = add_vertex(b, c[0], c[1], c[2] + z);
	uint32_t last = base + (uint32_t)((end - first - 1) * cols);
	for (int j = 0; j < cols; j++) {
		uint32_t j1 = (uint32_t)((j + 1) % cols);
		if (north_pole)
			add_triangle(b, north, base + j, base + j1);
		add_triangle(b, last + j, south, last + j1);
	}
}

typedef struct sphere_profile {
	double radius;
	int bands;
} sphere_profile;

static void sphere_row(const void *ctx, int row, double *r, double *z)
{
	const sphere_profile *s = ctx;
	double theta = M_PI * row / s->bands;
	/* Exact zeros at the poles keep them on the axis. */
	*r = (row == 0 || row == s->bands) ? 0.0 : s->radius * sin(theta);
	*z = s->radius * cos(theta);
}

static void make_sphere(builder *b, double radius, int res)
{
	sphere_profile p = {radius, res / 2 > 2 ? res / 2 : 2};
	double c[3] = {0, 0, 0};
	revolve(b, c, sphere_row, &p, p.bands + 1, res, REVOLVE_POLES);
}

/* Capped cylinder profile: north pole, top cap rings outwards, the side
 * downwards, bottom cap rings inwards, south pole; rows from `first` on. */
typedef struct cylinder_profile {
	double radius, length;
	int cap_rings, side_rows, first;
} cylinder_profile;

static void cylinder_row(const void *ctx, int row, double *r, double *z)
{
	const cylinder_profile *p = ctx;
	int nr = p->cap_rings, nz = p->side_rows;
	double h = 0.5 * p->length;
	row += p->first;
	if (row <= nr) {
		*r = p->radius * row / nr;
		*z = h;
	} else if (row <= nr + nz) {
		*r = p->radius;
		*z = h - p->length * (row - nr) / nz;
	} else {
		*r = p->radius * (2 * nr + nz - row) / nr;
		*z = -h;
	}
}

static int divisions(double length, double edge, int max)
{
	double n = round(length / edge);
	return n < 1 ? 1 : (n > max ? max : (int)n);
}

/* Without its top cap (`open_top`) the side's top rim is the profile's first
 * row: a chair leg, whose top lies inside the seat. */
static void make_cylinder(builder *b, const double centre[3], double radius, double length, int res, int open_top)
{
	double edge = 2.0 * M_PI * radius / res;
	cylinder_profile p = {radius, length, divisions(radius, edge, DP_SHAPE_RESOLUTION_MAX),
			      divisions(length, edge, 64 * DP_SHAPE_RESOLUTION_MAX), 0};
	int rows = 2 * p.cap_rings + p.side_rows + 1;
	if (open_top) {
		p.first = p.cap_rings;
		rows -= p.cap_rings;
	}
	revolve(b, centre, cylinder_row, &p, rows, res, open_top ? REVOLVE_OPEN_TOP : REVOLVE_POLES);
}

typedef struct torus_profile {
	double radius, tube;
	int rows;
} torus_profile;

static void torus_row(const void *ctx, int row, double *r, double *z)
{
	const torus_profile *p = ctx;
	/* Clockwise in the (r, z) half-plane, so that the normal points out. */
	double psi = -2.0 * M_PI * row / p->rows;
	*r = p->radius + p->tube * cos(psi);
	*z = p->tube * sin(psi);
}

static void make_torus(builder *b, double radius, double tube, int res)
{
	double c[3] = {0, 0, 0};
	int along = divisions(2.0 * M_PI * radius, 2.0 * M_PI * tube / res, 64 * DP_SHAPE_RESOLUTION_MAX);
	torus_profile p = {radius, tube, res};
	revolve(b, c, torus_row, &p, res, along, REVOLVE_WRAP);
}

/* Box [lo, hi] with n[d] cells along axis d. Faces are grids on the surface
 * lattice; a lattice-point index table makes neighbouring faces share their
 * edge vertices, so the mesh is closed. */
static void make_box(builder *b, const double lo[3], const double hi[3], const int n[3])
{
	size_t n0 = (size_t)n[0], n1 = (size_t)n[1], n2 = (size_t)n[2];
	size_t lattice = (n0 + 1) * (n1 + 1) * (n2 + 1);
	if (!b->m) {
		b->nv += lattice - (n0 - 1) * (n1 - 1) * (n2 - 1);
		b->nf += 4 * (n0 * n1 + n1 * n2 + n2 * n0);
		return;
	}
	uint32_t *index = dp_alloc_array(lattice, sizeof(uint32_t));
	if (!index) {
		b->nomem = 1;
		return;
	}
	for (size_t i = 0; i < lattice; i++)
		index[i] = UINT32_MAX;
	for (int axis = 0; axis < 3; axis++) {
		for (int side = 0; side < 2; side++) {
			/* (u, v) with e_u x e_v = outward normal. */
			int u = (axis + 1) % 3, v = (axis + 2) % 3;
			if (side == 0) {
				int t = u;
				u = v;
				v = t;
			}
			for (int i = 0; i < n[u]; i++) {
				for (int j = 0; j < n[v]; j++) {
					uint32_t corner[4];
					int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
					for (int q = 0; q < 4; q++) {
						int cell[3];
						cell[axis] = side ? n[axis] : 0;
						cell[u] = i + di[q];
						cell[v] = j + dj[q];
						size_t k = ((size_t)cell[0] * (n1 + 1) + (size_t)cell[1]) * (n2 + 1) +
							   (size_t)cell[2];
						if (index[k] == UINT32_MAX) {
							double p[3];
							for (int d = 0; d < 3; d++)
								p[d] = lo[d] + (hi[d] - lo[d]) * cell[d] / n[d];
							index[k] = add_vertex(b, p[0], p[1], p[2]);
						}
						corner[q] = index[k];
					}
					add_quad(b, corner[0], corner[1], corner[2], corner[3]);
				}
			}
		}
	}
	free(index);
}

static void normalize3(double v[3])
{
	double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	for (int k = 0; k < 3; k++)
		v[k] /= len;
}

/* Removes the tangential part of v and renormalises it. */
static void make_perpendicular(double v[3], const double t[3])
{
	double d = v[0] * t[0] + v[1] * t[1] + v[2] * t[2];
	for (int k = 0; k < 3; k++)
		v[k] -= d * t[k];
	normalize3(v);
}

static void cross(const double a[3], const double b[3], double out[3])
{
	out[0] = a[1] * b[2] - a[2] * b[1];
	out[1] = a[2] * b[0] - a[0] * b[2];
	out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The knot's starting normal: any unit vector across the tangent at t = 0. */
static void knot_start_normal(double n[3])
{
	double t0[3];
	dp_trefoil_tangent(0.0, t0);
	n[0] = 0;
	n[1] = 0;
	n[2] = 1;
	make_perpendicular(n, t0);
}

/* Tube around the trefoil with rotation-minimising (parallel transport)
 * frames. Transport around a closed curve comes back rotated by the
 * holonomy angle, which is spread evenly over the rings so the seam meets. */
static void make_knot(builder *b, double s, double tube, int res)
{
	int rings = divisions(dp_trefoil_length(s), 2.0 * M_PI * tube / res, 64 * DP_SHAPE_RESOLUTION_MAX);
	if (!b->m) {
		b->nv += (size_t)rings * res;
		b->nf += 2 * (size_t)rings * res;
		return;
	}
	double n[3], t[3], n0[3], t0[3], bin[3];
	knot_start_normal(n0);
	dp_trefoil_tangent(0.0, t0);
	memcpy(n, n0, sizeof n);
	for (int i = 1; i <= rings; i++) {
		dp_trefoil_tangent(2.0 * M_PI * i / rings, t);
		make_perpendicular(n, t);
	}
	cross(t0, n0, bin);
	double holonomy = atan2(n[0] * bin[0] + n[1] * bin[1] + n[2] * bin[2],
				n[0] * n0[0] + n[1] * n0[1] + n[2] * n0[2]);
	uint32_t base = (uint32_t)b->nv;
	memcpy(n, n0, sizeof n);
	for (int i = 0; i < rings; i++) {
		double tt = 2.0 * M_PI * i / rings, c[3];
		dp_trefoil(s, tt, c);
		dp_trefoil_tangent(tt, t);
		if (i > 0)
			make_perpendicular(n, t);
		cross(t, n, bin);
		double twist = -holonomy * i / rings;
		for (int j = 0; j < res; j++) {
			/* Decreasing angle so that tangent x (d angle) points out. */
			double a = twist - 2.0 * M_PI * j / res, ca = cos(a), sa = sin(a);
			add_vertex(b, c[0] + tube * (ca * n[0] + sa * bin[0]), c[1] + tube * (ca * n[1] + sa * bin[1]),
				   c[2] + tube * (ca * n[2] + sa * bin[2]));
		}
	}
	connect_rows(b, base, rings, res, 1);
}

/* The rectangle lo..hi (lo[axis] == hi[axis]) as a grid of cells about
 * `edge` across (at most `res` per side), facing +axis (`side` 1) or -axis. */
static void make_rect(builder *b, int axis, int side, const double lo[3], const double hi[3], double edge, int res)
{
	/* (u, v) with e_u x e_v = the outward normal, as in make_box */
	int u = (axis + 1) % 3, v = (axis + 2) % 3;
	if (!side) {
		int t = u;
		u = v;
		v = t;
	}
	int nu = divisions(hi[u] - lo[u], edge, res), nv = divisions(hi[v] - lo[v], edge, res);
	uint32_t base = (uint32_t)b->nv;
	for (int i = 0; i <= nu; i++)
		for (int j = 0; j <= nv; j++) {
			double p[3];
			p[axis] = lo[axis];
			p[u] = lo[u] + (hi[u] - lo[u]) * i / nu;
			p[v] = lo[v] + (hi[v] - lo[v]) * j / nv;
			add_vertex(b, p[0], p[1], p[2]);
		}
	for (int i = 0; i < nu; i++)
		for (int j = 0; j < nv; j++) {
			uint32_t c = base + (uint32_t)(i * (nv + 1) + j);
			add_quad(b, c, c + (uint32_t)(nv + 1), c + (uint32_t)(nv + 2), c + 1);
		}
}

/* The horizontal square of half-side `half` around the vertical line
 * through c, less the disc of `radius` (< half) round it, at height z,
 * facing down: where a leg meets the seat's underside. The disc's rim has
 * the leg's vertices (angles 2 pi j / res); the square's border has those
 * angles' rays and its four corners, and the two are zipped by angle. */
static void make_square_ring(builder *b, const double c[3], double half, double radius, int res)
{
	uint32_t inner = (uint32_t)b->nv;
	for (int j = 0; j < res; j++) {
		double phi = 2.0 * M_PI * j / res;
		add_vertex(b, c[0] + radius * cos(phi), c[1] + radius * sin(phi), c[2]);
	}
	/* The square's border: each ray's angle, with a corner inserted
	 * before the first ray past it unless a ray hits it. */
	uint32_t outer = (uint32_t)b->nv;
	int m = 0, corner = 0;
	double angle[DP_SHAPE_RESOLUTION_MAX + 4];
	for (int j = 0; j <= res; j++) {
		double phi = 2.0 * M_PI * j / res;
		for (; corner < 4 && M_PI * (2 * corner + 1) / 4 <= phi + 1e-12; corner++)
			if (fabs(M_PI * (2 * corner + 1) / 4 - phi) > 1e-12)
				angle[m++] = M_PI * (2 * corner + 1) / 4;
		if (j < res)
			angle[m++] = phi;
	}
	for (int k = 0; k < m; k++) {
		double x = cos(angle[k]), y = sin(angle[k]), big = fmax(fabs(x), fabs(y));
		x /= big;
		y /= big;
		/* the corners' cosine and sine differ in the last bit */
		if (fabs(fabs(x) - 1.0) < 1e-9)
			x = copysign(1.0, x);
		if (fabs(fabs(y) - 1.0) < 1e-9)
			y = copysign(1.0, y);
		add_vertex(b, c[0] + half * x, c[1] + half * y, c[2]);
	}
	/* Advance along whichever border's next vertex comes first by angle;
	 * clockwise seen from above, so the faces point down. */
	int i = 0, k = 0;
	while (i < res || k < m) {
		double next_in = 2.0 * M_PI * (i + 1) / res, next_out = k + 1 < m ? angle[k + 1] : 2.0 * M_PI;
		uint32_t a = inner + (uint32_t)(i % res), o = outer + (uint32_t)(k % m);
		if (k == m || (i < res && next_in <= next_out)) {
			add_triangle(b, a, inner + (uint32_t)((i + 1) % res), o);
			i++;
		} else {
			add_triangle(b, a, outer + (uint32_t)((k + 1) % m), o);
			k++;
		}
	}
}

/* The boundary of the chair's solid: where the back stands on the seat and
 * the legs meet it there are no faces (a face inside the solid is no part of
 * its surface, and a point beside the seam would be judged against whichever
 * of two coincident faces of opposite normals the search met first). The
 * pieces meet along their edges without sharing vertices. */
static void make_chair(builder *b, const dp_shape *s)
{
	dp_chair_parts c;
	dp_chair_layout(s, &c);
	int res = s->resolution;
	double edge = 2.0 * M_PI * s->radius / res;
	const double *slo = c.seat_lo, *shi = c.seat_hi;
	double half = DP_CHAIR_LEG_INSET * s->radius;
	dp_chair_rect rect[DP_CHAIR_RECTS];
	dp_chair_rects(&c, rect);
	/* the seat's five, the underside and legs, then the back's five: the
	 * order the evaluation's samples and ties were measured with */
	for (int k = 0; k < DP_CHAIR_SEAT_RECTS; k++)
		make_rect(b, rect[k].axis, rect[k].side, rect[k].lo, rect[k].hi, edge, res);
	/* the underside: a cross between the legs' squares, and each square
	 * less its leg */
	double z = slo[2];
	double mid_lo[3] = {slo[0] + 2.0 * half, slo[1], z}, mid_hi[3] = {shi[0] - 2.0 * half, shi[1], z};
	make_rect(b, 2, 0, mid_lo, mid_hi, edge, res);
	for (int side = 0; side < 2; side++) {
		double lo[3] = {side ? shi[0] - 2.0 * half : slo[0], slo[1] + 2.0 * half, z};
		double hi[3] = {side ? shi[0] : slo[0] + 2.0 * half, shi[1] - 2.0 * half, z};
		make_rect(b, 2, 0, lo, hi, edge, res);
	}
	for (int i = 0; i < 4; i++) {
		double at[3] = {c.leg[i][0], c.leg[i][1], z};
		make_square_ring(b, at, half, s->radius, res);
		make_cylinder(b, c.leg[i], s->radius, s->length, res, 1);
	}
	for (int k = DP_CHAIR_SEAT_RECTS; k < DP_CHAIR_RECTS; k++)
		make_rect(b, rect[k].axis, rect[k].side, rect[k].lo, rect[k].hi, edge, res);
}

static void generate(builder *b, const dp_shape *s)
{
	double origin[3] = {0, 0, 0};
	int res = s->resolution;
	switch (s->kind) {
	case DP_SHAPE_SPHERE: make_sphere(b, s->radius, res); break;
	case DP_SHAPE_CYLINDER: make_cylinder(b, origin, s->radius, s->length, res, 0); break;
	case DP_SHAPE_SLAB: {
		double h = 0.5 * s->width, t = 0.5 * s->thickness;
		double lo[3] = {-h, -h, -t}, hi[3] = {h, h, t};
		int n[3] = {res, res, divisions(s->thickness, s->width / res, res)};
		make_box(b, lo, hi, n);
		break;
	}
	case DP_SHAPE_TORUS: make_torus(b, s->radius, s->tube, res); break;
	case DP_SHAPE_KNOT: make_knot(b, s->radius, s->tube, res); break;
	case DP_SHAPE_CHAIR: make_chair(b, s); break;
	case DP_SHAPE_RODS: {
		double axes[4][3];
		dp_rods_layout(s, axes);
		for (int i = 0; i < 4; i++)
			make_cylinder(b, axes[i], s->radius, s->length, res, 0);
		break;
	}
	}
}

dp_status dp_shape_mesh(const dp_shape *shape, dp_cloud *mesh, dp_error *err)
{
	memset(mesh, 0, sizeof *mesh);
	dp_status st = dp_shape_check(shape, err);
	if (st != DP_OK)
		return st;
	builder count = {NULL, 0, 0, 0};
	generate(&count, shape);
	if (count.nv > UINT32_MAX)
		return dp_fail(err, DP_ERR_ARG, "shape %s: resolution %d gives %zu vertices, too many",
			       dp_shape_name(shape->kind), shape->resolution, count.nv);
	st = dp_cloud_alloc(mesh, count.nv, 0, err);
	if (st != DP_OK)
		return st;
	mesh->faces = dp_alloc_array(3 * count.nf, sizeof(uint32_t));
	if (!mesh->faces) {
		dp_cloud_free(mesh);
		return dp_fail(err, DP_ERR_NOMEM, "shape %s: out of memory for %zu faces", dp_shape_name(shape->kind),
			       count.nf);
	}
	mesh->nfaces = count.nf;
	builder fill = {mesh, 0, 0, 0};
	generate(&fill, shape);
	if (fill.nomem) {
		dp_cloud_free(mesh);
		return dp_fail(err, DP_ERR_NOMEM, "shape %s: out of memory", dp_shape_name(shape->kind));
	}
	if (fill.nv != count.nv || fill.nf != count.nf) {
		dp_cloud_free(mesh);
		return dp_fail(err, DP_ERR_INTERNAL, "shape %s: counted %zu/%zu vertices/faces, made %zu/%zu",
			       dp_shape_name(shape->kind), count.nv, count.nf, fill.nv, fill.nf);
	}
	return DP_OK;
}

