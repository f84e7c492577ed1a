/* Geometry of the built-in shapes shared by their definitions and distance
 * functions (shapes.c) and their triangulation (shape_mesh.c). */
#ifndef DP_TOOLS_SHAPES_H
#define DP_TOOLS_SHAPES_H

#include "dpoints_tools.h"

#define DP_SHAPE_RESOLUTION_MIN 3
#define DP_SHAPE_RESOLUTION_MAX 4096
/* Chair legs sit this many leg radii in from the seat's edges. */
#define DP_CHAIR_LEG_INSET 1.5

/* DP_ERR_ARG naming the shape when its kind, dimensions or resolution are
 * out of range (err may be NULL). */
dp_status dp_shape_check(const dp_shape *s, dp_error *err);

/* The trefoil core of the knot with scale s at parameter t in [0, 2 pi). */
void dp_trefoil(double s, double t, double p[3]);
/* Its unit tangent. */
void dp_trefoil_tangent(double t, double d[3]);
/* Its length. */
double dp_trefoil_length(double s);

/* The chair's parts: two boxes and four vertical legs. */
typedef struct dp_chair_parts {
	double seat_lo[3], seat_hi[3], back_lo[3], back_hi[3];
	double leg[4][3]; /* leg centres (the cylinder's mid-height) */
} dp_chair_parts;

void dp_chair_layout(const dp_shape *s, dp_chair_parts *c);

/* A flat face of the chair's boundary: the rectangle [lo, hi] (lo[axis] ==
 * hi[axis]) facing +axis (`side` 1) or -axis. */
typedef struct dp_chair_rect {
	double lo[3], hi[3];
	int axis, side;
} dp_chair_rect;

#define DP_CHAIR_RECTS 10
#define DP_CHAIR_SEAT_RECTS 5 /* the first five are the seat's */

/* The chair's flat boundary faces but its underside, which the legs pierce:
 * the seat's four sides and its top in front of the back, the back's sides,
 * front, rear and top. The mesh and the surface distance both read them. */
void dp_chair_rects(const dp_chair_parts *c, dp_chair_rect out[DP_CHAIR_RECTS]);

/* The rods' axis centres (each the cylinder's mid-height). */
void dp_rods_layout(const dp_shape *s, double axes[4][3]);

#endif
