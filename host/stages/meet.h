/* Where opposing fronts meet (dpoints.h, sinking step 1a). A sinking point
 * settles when an inner point of an opposing front comes within the settle
 * radius, so it stops short of the medial axis by up to that radius plus a
 * step. Where the whole front comes from one side (a one-view scan of a ball
 * or a tube) every anchor stops short on the same side and the skeleton
 * inherits the offset: measured on a one-view sphere at 4000 deep points,
 * 1.9 r towards the scanner, which the volume prior then copies into the
 * completed far half. Both sinking lines pass through the medial axis, so
 * the settled point moves along its own line to where it passes closest to
 * its partners' lines. Where the partner's normal is nearly opposite (a thin
 * wall) the two lines nearly coincide and their crossing follows the
 * normals' noise (measured: a wall 3.5 r thick with 8° of normal noise,
 * anchors 0.98 r off the mid-plane, 15% outside the wall); there the point
 * takes the centre of the ball that touches its surface point and the
 * partner's tangent plane, which is the mid-plane (0.07 r off, none
 * outside; tests/test_sink.c test_thin_wall). */
#ifndef DP_STAGES_MEET_H
#define DP_STAGES_MEET_H

#include "grid/grid.h"

typedef struct dp_meet_args {
	const dp_grid *inner;        /* inner points; cell >= radius */
	const float *sx, *sy, *sz;   /* surface point of each grid point, grid order */
	const float *nx, *ny, *nz;   /* its normal */
	float radius;                /* the settle radius */
	float far_d2;                /* partners' surface points farther than this (squared) */
	float wall_min;              /* ... or, facing back across a wall, p this far behind them (0: off) */
	float cos_w;                 /* partners' normals at least ω apart */
	float max_shift;             /* the largest move along the line */
} dp_meet_args;

/* The signed distance along -n (deeper when positive) that brings the inner
 * point q of surface point p, normal n, to the medial axis as its partners
 * place it: the inner points within the radius that pass the settle test's
 * far (or thin-wall) and angle tests (host/ops/operators.h, sink_front). With n', s a partner's normal and surface point and
 * b = n·n': for b >= -cos 45° the depth where the two sinking lines pass
 * closest, weighted by 1 - b²; below, the radius t of the ball that touches
 * p and the partner's tangent plane, t (1 - b) = n'·(s - p), weighted 1. 0
 * without partners; never above p, and at most max_shift. */
float dp_meet_shift(const dp_meet_args *a, const float q[3], const float p[3], const float n[3]);

#endif
