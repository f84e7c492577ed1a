/* The scan's outline (dpoints.h, dp_surface_params.silhouette; not in the
 * paper). A range scanner looking along an axis records every part of the
 * object that faces it, so seen along that axis the object covers no more
 * than its scan does: whatever completion adds must lie inside the scan's
 * outline, grown by a margin for noise and for what the scanner misses at
 * grazing angles (the visual hull's argument, one view at a time; two
 * opposite views share the outline). The completed surface of a one-view
 * scan otherwise runs out beyond it: bun270 of the Stanford bunny, scanned
 * from the side, grew a skirt of 309 of 4000 points hanging up to 0.23
 * diagonals below the base, whose lowest edge the scan shows. The margin is
 * all the room completion has to bulge past the scan's edge, and it takes
 * it (surface.c has the measured choice of 2.5 r).
 *
 * Unless given, the axis is found: a scanner sees surfaces at a grazing
 * angle worst, so few sample normals lie within 10° of perpendicular to it
 * (0.6-2.7% on the bunny's four single views, 2.7-5.7% on its two opposite
 * pairs) while normals spread over every direction put about 17% there
 * (7.7-15.4% on the data folder's complete scans, at the emptiest
 * direction). A wrong axis on a complete scan is harmless: its outline holds
 * all of the object. */
#ifndef DP_STAGES_SILHOUETTE_H
#define DP_STAGES_SILHOUETTE_H

#include "dpoints.h"

#include <stdint.h>

typedef struct dp_silhouette {
	float u[3], v[3];          /* two directions across the view axis */
	double u0, v0, cell;       /* the grid's corner across the axis and its cell size */
	double margin;             /* the outline's growth beyond the input */
	int nu, nv;                /* cells along u and v */
	int32_t *nearest;          /* per cell: itself when inside the outline, else the nearest cell inside */
	float *inset;              /* per cell: distance from its centre to the nearest cell outside; 0 outside */
} dp_silhouette;

/* Of the unit directions of a fixed set over the half-sphere, the one to
 * which the fewest of the n unit normals lie within 10° of perpendicular.
 * *found = 1 and axis set when that is at most `grazing` of them, n is at
 * least DP_SILHOUETTE_MIN_NORMALS (fewer leave chance gaps in any direction)
 * and every direction of the set with at most `grazing` lies within 45° of
 * it (silhouette.c: a box-like object passes many); *fraction receives the
 * best direction's fraction either way (1 when too few). Reads only. */
#define DP_SILHOUETTE_MIN_NORMALS 1000
void dp_silhouette_axis(size_t n, const float *nx, const float *ny, const float *nz, double grazing, int *found,
			float axis[3], double *fraction);
/* Two unit directions u, v across the unit `axis`, u × v = axis. */
void dp_silhouette_across(const float axis[3], float u[3], float v[3]);

/* `given` scaled to unit length into axis: 1, or 0 when it is all zero or
 * not finite. */
int dp_silhouette_unit(const double given[3], float axis[3]);
/* The axis `given` scaled to unit length (*found = 1, *fraction = -1) or,
 * when it is all zero, dp_silhouette_axis's. */
void dp_silhouette_pick(const double given[3], size_t n, const float *nx, const float *ny, const float *nz,
			double grazing, int *found, float axis[3], double *fraction);

/* The outline of `input` seen along the unit `axis`: cells of `cell` across
 * it that an input point falls in, grown by `margin` (>= 0) and with every
 * hole the outline encloses filled. With `facing` (samples on the scan with
 * unit normals; NULL or none: one margin), only cells that hold a sample whose normal lies
 * more than DP_SILHOUETTE_EDGE_DEG from the axis grow by `margin`, every
 * other cell of the input by `edge_margin` (the smaller of the two): a
 * surface that faces the scanner up to the scan's edge ends there. s->margin
 * is `margin` either way. Zero-initialise `s` first; free with
 * dp_silhouette_free. DP_ERR_NOMEM, DP_ERR_ARG for an empty input, a cell
 * or margins that are not finite numbers (> 0, >= 0), an axis not of unit
 * length, or spans no grid fits. */
#define DP_SILHOUETTE_EDGE_DEG 50.0
dp_status dp_silhouette_build(dp_silhouette *s, const dp_cloud *input, const float axis[3], double cell, double margin,
			      const dp_cloud *facing, double edge_margin, dp_error *err);
void dp_silhouette_free(dp_silhouette *s);

/* Moves each point outside the outline across the axis (never along it)
 * to the nearest cell inside, onto that cell's nearest point; returns how
 * many moved. Any number of calls may run at once on disjoint points. */
size_t dp_silhouette_hold(const dp_silhouette *s, size_t n, float *x, float *y, float *z);

/* The meso-skeleton lies inside the object, so seen along the axis inside
 * the scan's own outline (the outline less its margin, where the inset is
 * at least the margin). An anchor sunk out of it, through a face never
 * scanned (the soles of bun270's feet, whose tops face up: 148 anchors down
 * to 13 r below the base), moves back along its line towards its sample p
 * to the last place inside (to within a 128th of its depth) and 1 is
 * returned; an anchor inside, or one whose sample is not inside either (at
 * an edge that faces the scanner, where the outline grew by the edge margin
 * only, the samples within the margin less that), stays (0). Only the centre is
 * bounded: the stronger bound that an anchor's ball, radius its depth,
 * lie inside the outline measured worse (README, result (35)). Reads
 * only s. */
int dp_silhouette_cap(const dp_silhouette *s, const float p[3], float q[3]);

#endif
