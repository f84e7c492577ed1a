/* Surface points stranded in a skeletal sheet (the surface stage's last
 * step; not in the paper). In a plate a few r thick, a completed point can
 * come to rest in the plate's middle with its normal and its deep point
 * lying along the plate. Its data term acts along that normal, its prior
 * along that deep point, and the repulsion across its tangent plane is
 * balanced, so nothing moves it out. Measured on the demo chair
 * (bench_completion, WLOP seed 1): 113 surface points within 0.6 r of the
 * back rest's mid-plane, a tenth of the back rest's points. Their normals lie
 * in the plate, so about half of them count as flipped. Lengths here are in
 * the points' spacing (`r` of the arguments).
 *
 * The skeleton knows the plate: the skeleton spots around the point's inner
 * end h form a sheet (smallest eigenvalue of their spread far below the
 * middle one), whose normal s is the plate's. A point without input support
 * that lies within half a spacing of the sheet's plane through h, over the
 * sheet (a spot near its foot on the plane: a rim face's points, beyond the
 * sheet's edge, stay), with its deep point within about 45° of the sheet, is
 * moved across it: to h + lateral offset + side · L · s, normal side · s. L
 * is the median depth across the sheet of the nearby deep points that do
 * leave it across (the plate's half thickness). side is the side of the plane the point already lies on,
 * or, right on the plane, the face less sampled around h (the completed one
 * that lacks points); on a tie, the side it lies on after all. */
#ifndef DP_STAGES_SHEET_POINTS_H
#define DP_STAGES_SHEET_POINTS_H

#include "dpoints.h"

typedef struct dp_sheet_points_args {
	size_t n;                        /* surface points */
	float *px, *py, *pz;             /* positions (moved) */
	float *nx, *ny, *nz;             /* normals (set for the moved points) */
	const float *hx, *hy, *hz;       /* the skeleton point each hangs on */
	const float *eta;                /* data weight η = 1 + Σθ of the input */
	float held_support;              /* points with η - 1 at least this are left alone */
	size_t spots;                    /* distinct skeleton positions */
	const float *sx, *sy, *sz;
	double r;                        /* the unit of the lengths below: the points' spacing */
	float *to_x, *to_y, *to_z, *chosen; /* scratch, n floats each */
} dp_sheet_points_args;

/* Moves the stranded points (above); returns how many in *moved. Every
 * decision is taken from the positions as they were on entry.
 * DP_ERR_NOMEM. */
dp_status dp_sheet_points_lift(const dp_sheet_points_args *a, size_t *moved, dp_error *err);

#endif
