/* Where opposing fronts meet (DESIGN 4.1). A sinking point settles when an
 * inner point of an opposing front comes within the settle radius, so it
 * stops short of the medial axis by up to that radius plus a step. Where the
 * whole front comes from one side (a one-view scan of a ball or a tube) every
 * anchor stops short on the same side and the skeleton inherits the offset:
 * measured on a one-view sphere at 4000 deep points, 1.9 r towards the
 * scanner, which the volume prior then copies into the completed far half.
 * Both points' sinking lines cross the medial axis, so the settled point is
 * moved along its own line to where it passes closest to its partners'. */
#ifndef DP_STAGES_MEET_H
#define DP_STAGES_MEET_H

#include "grid/grid.h"

typedef struct dp_meet_args {
	const dp_grid *inner;        /* inner points; cell >= radius */
	const float *sx, *sy, *sz;   /* surface point of each grid point, grid order */
	const float *nx, *ny, *nz;   /* its normal */
	float radius;                /* the settle radius */
	float far_d2;                /* partners' surface points farther than this (squared) */
	float cos_w;                 /* partners' normals at least ω apart */
	float max_shift;             /* the largest move along the line */
} dp_meet_args;

/* The signed distance along -n (deeper when positive) that brings the inner
 * point q of surface point p, normal n, to where its sinking line passes
 * closest to the lines of its partners: the inner points within the radius
 * that pass the settle test's far and angle tests. Each partner's crossing
 * is weighted by 1 - (n·n')², the conditioning of the two lines (opposite
 * normals are parallel lines, which fix no depth). 0 when no partner fixes
 * one; clamped to ±max_shift. */
float dp_meet_shift(const dp_meet_args *a, const float q[3], const float p[3], const float n[3]);

#endif
