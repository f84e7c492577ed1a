/* Facing the scanner (dpoints.h, dp_surface_params.face_scanner; not in the
 * paper). A range scanner records only what faces it, so every point of a
 * scan taken from one side has an outward normal towards that side. Normal
 * orientation has no such knowledge: spread over a one-sided scan it
 * propagates across neighbourhoods, and in the surface stage a point that
 * input holds keeps whatever sign its normal had. Measured on the Stanford
 * bunny's front view (bun000, WLOP seeds 1-6): 3-37 of its 4026 surface points
 * lying on the scan had normals facing away from it, up to 0.9 of the way
 * along the view axis, a third of all the flips of some seeds.
 *
 * Whether a scan is one-sided is read from its normals along the view axis
 * (silhouette.h finds it; opposite views share it): of the normals pointing
 * within acos(cos_min) of the axis either way, at most DP_SCANNER_MINORITY
 * point the minority's way (the bunny's single views: none of about 3000;
 * its opposite pairs: 47-50%). Only a normal within acos(cos_min) of pointing
 * straight away from the scanner is turned. Views spread up to
 * asin(cos_min) about the axis (30° at the default 0.5) see no surface whose
 * outward normal does that, so a scan merged from such views is still
 * one-sided and none of its true normals is turned. */
#ifndef DP_STAGES_SCANNER_H
#define DP_STAGES_SCANNER_H

#include <stddef.h>

/* The largest fraction of the clearly axial normals that may point the
 * other way in a scan still taken as one-sided. The bunny's four single
 * views (WLOP seeds 1-2): none of 2800-3300 at cos_min 0.5. A ring of four
 * views at 20° elevation, 70° off the vertical, sees a torus's outer rim
 * facing down: with the vertical given as the axis, 3.4% of 206 (at 300
 * samples), which turned true normals at 0.1. */
#define DP_SCANNER_MINORITY 0.01

/* Fewer normals pointing clearly along the axis than this say nothing (a
 * found axis needs DP_SILHOUETTE_MIN_NORMALS samples; a given one may come
 * with a handful). */
#define DP_SCANNER_MIN_NORMALS 100

/* The side of the unit `axis` the scan was taken from: +1 or -1 when the n
 * unit normals with |n·axis| > cos_min, at least DP_SCANNER_MIN_NORMALS of
 * them, point that way but for at most DP_SCANNER_MINORITY of them; else 0.
 * Reads only. */
int dp_scanner_side(size_t n, const float *nx, const float *ny, const float *nz, const float axis[3],
		    double cos_min);

/* Turns (negates) every normal with n·toward < -cos_min: `toward` is the
 * unit direction to the scanner. Returns how many it turned. */
size_t dp_scanner_face(size_t n, float *nx, float *ny, float *nz, const float toward[3], double cos_min);

#endif
