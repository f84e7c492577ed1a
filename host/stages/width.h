/* The width bound of sinking (dpoints.h, sinking step 1c; not in the paper).
 * A ball inscribed in a part and tangent to its surface at p is no wider than
 * the part. Where the part is thinner than the neighbourhoods (a pole, a chair
 * leg, an ear), its normals are often oriented across it, or its far side was
 * never scanned, and nothing else stops a point sinking out of it: measured on
 * pcl/lamppost.pcd, anchors a median 44 r and up to 96 r deep in the air
 * beside a pole 5-7 r thick, and a surface a median 10 r from the data. The
 * bound does not keep such a point inside the part; it keeps it within a few
 * widths of it.
 *
 * The part's width at p is read off the samples around p, whatever p's
 * normal says (a normal leaning along the surface is what sends a point out
 * of it): at scales rho = DP_WIDTH_MIN_SCALE_R r, doubling
 * DP_WIDTH_SCALES times, the second moments of the offsets c - p of the
 * samples c within rho. A patch of surface around p spreads rho/2 (rms)
 * along both of its directions; a strip of half-width a spreads a/sqrt(3)
 * (from its middle) to 2a/sqrt(3) (from its edge) across itself, a pole of
 * radius a about 1.2a, however large rho grows. The square root of the
 * middle eigenvalue is that narrower spread s. The first scale where
 * rho/2 > factor * s bounds the depth at rho/2: for the pole at factor 2,
 * between 2.4a and 4.9a.
 *
 * Where there is no part to speak of the bound is never reached. A plane
 * spreads rho/2 at every scale. So does the half-plane beside a scan's
 * straight boundary, nearly (no less than 0.43 rho), since the moments are
 * taken about p, not about their mean. A corner of a scan's
 * boundary spreads less: a right angle's margin over factor 2 is only 1.2,
 * and a convex corner sharper than about 75 degrees is bounded at 2 r. A
 * one-view scan of a sphere of radius R spreads R/sqrt(3) once rho holds the
 * whole visible half, so with factor >= 1.8 even the doubling scales bound
 * it beyond R, past the centre that sinking must reach. */
#ifndef DP_STAGES_WIDTH_H
#define DP_STAGES_WIDTH_H

#include "dpoints.h"
#include "grid/grid.h"

/* Smallest scale, in r: a disc of 4 r holds about 40 samples, enough for
 * three second moments. */
#define DP_WIDTH_MIN_SCALE_R 4.0
/* Scales 4, 8, 16, 32, 64 r: the bound never falls below 2 r nor exceeds
 * 32 r. */
#define DP_WIDTH_SCALES 5
/* A ball holding fewer of the samples its scale reads measures nothing; the
 * widest one (which reads one in 64: fewer than about 500 samples within
 * 64 r) bounds the point: an outlier or a stray cluster, no part around it. */
#define DP_WIDTH_MIN_COUNT 8

/* Scales beyond 8 r read one sample in 4, 16, 64 (chosen by a hash of the
 * index, whatever the order), about 200 in each ball, which estimates the
 * spread to about 10%: a factor of 2 leaves a plane unbounded with a margin
 * of two. */
typedef struct dp_width {
	const float *x, *y, *z; /* the samples (borrowed) */
	double r, factor;
	dp_grid grid[DP_WIDTH_SCALES];
	unsigned char *level;   /* per sample: scales read so far */
	float *bound;           /* per sample: the bound found, INFINITY until one is */
} dp_width;

/* Grids for every scale over the n samples (positions borrowed until
 * dp_width_free); r > 0 their spacing, factor > 0. */
dp_status dp_width_init(dp_width *w, size_t n, const float *x, const float *y, const float *z, double r,
			double factor, dp_error *err);
void dp_width_free(dp_width *w);
/* Whether an inner point `depth` deep below sample i has reached i's bound.
 * Reads the scales that depth makes relevant (rho / 2 <= depth) on first
 * need and remembers them, so a point that settles shallow never reads the
 * wide ones. It writes only sample i's own slots: calls for different i may
 * run at once. */
int dp_width_too_deep(dp_width *w, size_t i, float depth);

/* bound[i] = the depth, in the units of x, beyond which sample i's inner point
 * may not sink, or INFINITY where no scale bounds it: every scale read at
 * once. */
dp_status dp_width_bound(size_t n, const float *x, const float *y, const float *z, double r, double factor,
			 float *bound, dp_error *err);

#endif
