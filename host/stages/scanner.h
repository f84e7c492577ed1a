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
 * its opposite pairs: 47-50%), or up to DP_SCANNER_SLIPS where the samples
 * form one layer along the axis, as a single range image does. Only a normal
 * within acos(cos_min) of pointing straight away from the scanner is turned.
 * Views spread up to asin(cos_min) about the axis (30° at the default 0.5)
 * see no surface whose outward normal does that, so a scan merged from such
 * views is still one-sided and none of its true normals is turned. With the
 * scanner's eye given (a perspective scanner near the object, whose rays
 * spread too wide for one axis), each point faces the eye itself and no side
 * is read. */
#ifndef DP_STAGES_SCANNER_H
#define DP_STAGES_SCANNER_H

#include "dpoints.h"

#include <stddef.h>

/* The largest fraction of the clearly axial normals that may point the
 * other way in a scan taken as one-sided by its normals alone. The bunny's
 * four single views (WLOP seeds 1-2): none of 2800-3300 at cos_min 0.5. A
 * ring of four views at 20° elevation, 70° off the vertical, sees a
 * torus's outer rim facing down: with the vertical given as the axis, 3.4%
 * of 206 (at 300 samples), which turned true normals at 0.1. */
#define DP_SCANNER_MINORITY 0.01

/* Fewer normals pointing clearly along the axis than this say nothing (a
 * found axis needs DP_SILHOUETTE_MIN_NORMALS samples; a given one may come
 * with a handful). */
#define DP_SCANNER_MIN_NORMALS 100

/* A scan taken from one side is a depth map along the axis: one layer of
 * samples. When at most DP_SCANNER_LAYERED of the samples lie where a second
 * layer is (below), up to DP_SCANNER_SLIPS of the axial normals may point
 * the other way, orientation's mistakes: CGAL's one-sided hippo1 has 11.5%
 * (whole legs' patches, the fragments orientation reaches across a gap) in
 * a single layer (none layered), while the ring above has 4.3% layered and
 * the bunny's opposite pairs 84-91%, its single views 0.7-11% (the found
 * axis lies a few degrees off the true one, and the ears' edges overlap
 * what they hide), which their normals pass anyway. */
#define DP_SCANNER_SLIPS 0.25
#define DP_SCANNER_LAYERED 0.01
/* Layers are read in columns of DP_SCANNER_CELL_R r across the axis: a
 * second layer is a gap of more than DP_SCANNER_GAP_R r between
 * consecutive depths in one column. A single surface, however steep, is
 * sampled about 1 r apart along itself, so its depths in a column step by
 * no more than that (1.5 r with WLOP's uneven spacing). */
#define DP_SCANNER_CELL_R 2.0
#define DP_SCANNER_GAP_R 3.0

/* The fraction of the n points that lie in a column (along the unit `axis`,
 * DP_SCANNER_CELL_R r across) holding two layers, into *layered.
 * DP_ERR_ARG unless r > 0 gives finite columns, DP_ERR_NOMEM. Reads only. */
dp_status dp_scanner_layered(size_t n, const float *x, const float *y, const float *z, const float axis[3],
			     double r, double *layered, dp_error *err);

/* The side of the unit `axis` the scan of the n samples (spacing r, unit
 * normals) was taken from, into *side: +1 or -1 when at least
 * DP_SCANNER_MIN_NORMALS normals have |n·axis| > cos_min and they point
 * that way but for at most DP_SCANNER_MINORITY of them, or for at most
 * DP_SCANNER_SLIPS of them with the samples in one layer along the axis;
 * else 0. DP_ERR_NOMEM. Reads only. */
dp_status dp_scanner_side(size_t n, const float *x, const float *y, const float *z, const float *nx,
			  const float *ny, const float *nz, const float axis[3], double cos_min, double r, int *side,
			  dp_error *err);

/* The facing parameters of `p` (face_scanner_cos, scanner_side and the axis
 * it needs, the viewpoint, not both a side and an eye): DP_OK, or
 * DP_ERR_ARG with one line naming the parameter, after `prefix` (the
 * caller's name, or ""). */
dp_status dp_scanner_check(const dp_surface_params *p, const char *prefix, dp_error *err);

/* Turns (negates) every normal with n·toward < -cos_min: `toward` is the
 * unit direction to the scanner. Returns how many it turned. */
size_t dp_scanner_face(size_t n, float *nx, float *ny, float *nz, const float toward[3], double cos_min);

/* The same with the scanner's eye at `eye`: toward is the unit direction
 * from each point (x, y, z) to it (a point at the eye is left alone). */
size_t dp_scanner_face_eye(size_t n, const float *x, const float *y, const float *z, float *nx, float *ny, float *nz,
			   const double eye[3], double cos_min);

#endif
