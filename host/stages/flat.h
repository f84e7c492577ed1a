/* The depth of flat faces scanned from one side (dpoints.h, sinking step 5;
 * not in the paper).
 *
 * Opposing fronts and the medial test stop a sinking point on geometric
 * evidence. A flat face scanned from one side has none in its middle: no
 * front opposes it, no ball touches it again. Its points stop by slow-down,
 * which creeps in from the face's rim one
 * neighbourhood at a time while every point still sinks half a step per
 * iteration, so the depth grows towards the middle. Measured on the demo
 * chair's seat (53 r wide, 4.2 r thick, scanned from above): 4.1 r at the
 * rim, 7.7 r 10-15 r in, 10.5 r in the middle, and the completed underside
 * bulged below it.
 *
 * The rim is where the face's thickness shows: its points meet the fronts of
 * the scanned edge faces, at depths from 0 at the crease to the full
 * thickness a thickness in, so the median over the evidence-settled points
 * (front or medial) around one that face its way is the face's half
 * thickness, and no single point settled at a crease sets it. A face that
 * stays flat from the rim inwards has no reason to be thicker than its rim
 * says, so that median travels from sample to sample within DP_FLAT_LINK_R r
 * of each other, as long as each normal stays within the angle of the
 * evidence point's, and a point that stopped without evidence takes it when
 * it is shallower than its own depth: one stopped by slow-down, or by the
 * width bound, which only keeps a point within a few widths of its part
 * (width.h) and is no measure of a plate's depth. Measured on the demo
 * chair's back rest (4.2 r thick, scanned from the front): 257 of its 487
 * front samples stopped by the width bound 2.7-3.4 r deep, and its completed
 * rear stood 1.5 r behind the true one; with them capped (mean of WLOP seeds
 * 1-6 at 4000 deep points) the chair's 95th percentile accuracy went from
 * 0.0174 to 0.0154 diagonals and its flipped normals from 3.0% to 2.9%, its
 * coverage from 0.969 to 0.961; the bunnies did not change. Measuring the angle from the evidence
 * point, not from link to link, keeps a curved surface from passing the
 * depth along: on a sphere of radius R the depth travels at most R
 * sin(angle) and stays R. The smallest depth travels first, and a sample
 * passes on only the first that reaches it: where two flat faces meet, each
 * keeps its own. A box's face is no plate, and needs no exception: its side
 * faces are tall, and its face's points settle by the medial test at every
 * depth before slow-down reaches them.
 *
 * The evidence at a rim overshoots: a top point meets the edge face's front
 * only where that face's samples are over the front test's far distance
 * away, and then settles on the partner's height, not on the corner's
 * bisector (the demo chair's seat: rim evidence 3.0-4.0 r deep, half
 * thickness 2.1 r). The edge band itself shows the thickness: the samples
 * within DP_FLAT_BAND_R whose normals are within the angle of perpendicular to
 * the evidence point's reach as far below its plane as the plate is thick,
 * so the face is at most half that deep, unless the band reaches
 * DP_FLAT_BAND_TALL of the depth the search ball shows beside the point (a
 * tall side: no plate). Like the depths, the half thickness is the median
 * over the evidence around that faces the same way, so one short band does
 * not set a face, and only a flat face (half the samples around facing its
 * way) with samples well below its plane has a band: a rounded part turning
 * away, or a wall rising from the face, is no edge. Measured on the chair at
 * 4000 deep points (mean of WLOP seeds 1-6): coverage 0.946 -> 0.969,
 * flipped normals 3.5% -> 3.0%, 95th percentile accuracy 0.022 -> 0.017
 * diagonals; its seat's top at 1.6 r (half thickness 2.1 r); the bunnies
 * within their seeds' spread.
 *
 * The band's reach falls about one spacing short of the plate's thickness:
 * its last row lies half a spacing or more inside the far edge, and WLOP
 * rounds both creases, lowering the rim samples the reach is measured from and
 * raising the last row (the chair at 4000 deep points, 4.2 r thick: the
 * seat's bands reached 3.2 r, the back rest's 2.8 r). Its height is read as
 * that reach plus DP_FLAT_BAND_END_R r. And the band is read beside every sample that stopped
 * without evidence, not only beside evidence points: where a plate's rim is a
 * crease, the evidence along it has normals turned halfway round the corner
 * (the demo chair's back rest: 20-50 degrees), too far for the band test and
 * for passing its depth on across the face, while the face's own samples a few
 * r in see the edge face square. Measured on the chair (4000 deep points):
 * the seat's top 1.6 r -> 2.1-2.2 r deep and the back rest's front face 3.2 r
 * (slow-down) and 3.8 r (capped from the top rim's evidence) -> 1.9 r, half
 * thickness 2.1 r; over WLOP seeds 1-6 coverage 0.964 -> 0.978, flipped
 * normals 2.63% -> 2.56%, 95th percentile accuracy 0.0146 -> 0.0152
 * diagonals, the bunnies within their seeds' spread. The back rest's
 * completed rear is still a cloud: its points hold no input, and their
 * normals follow their dpoints, which lean 60 degrees on average.
 *
 * The bands also act while sinking (dpoints.h, step 1e): a point twice as
 * deep as the band depth that reaches it has passed a plate's far face and
 * settles at that depth, so a one-sided plate's middle no longer waits for
 * slow-down to creep in from the rim (which a slow-down margin of 1 r never
 * did on the chair's back rest). The bands and links are geometry, so the
 * context (dp_flat) builds them once per run; the rim's evidence joins only
 * after the loop, as it is no measure of a plate while fronts are still
 * meeting (a closed cylinder's side would stop at the depth of its crease
 * with the end cap).
 *
 * A crease between a flat face and the next is rounded: WLOP and PCA turn
 * the normals of the samples along it halfway round, so no face depth
 * reaches them (their normals are beyond the angle), no front stops them
 * where the faces beyond are unscanned, and they sink along the bisector
 * until slow-down stops them. Measured on the demo chair (WLOP seed 1, 4000
 * deep points): the seat's top samples within 1.5 r of the back rest, their
 * normals turned 10-45 degrees towards the seat, settled by slow-down 4-5 r
 * deep at the seat's bottom face (anchors' median height 0.907; the seat
 * spans 0.90-0.98, its mid-plane 0.94), some outside it. The faces around a
 * crease sample still say where the middle is: the inner point of each
 * sample within DP_FLAT_LINK_R settled on evidence or on its face's depth
 * is taken to lie on its face's medial plane (the plane through it across
 * its normal), and the crease sample's line, from p through q, crosses that
 * plane at some depth. A sample stopped by slow-down or the width bound that
 * no face depth reached takes the median of those depths when it is
 * shallower than its own (a rim's evidence that overshoots the middle is one
 * of several), over at least DP_FLAT_CROSS_MIN faces turned from its normal
 * by more than the angle and by at most 60 degrees: one within the angle
 * would have passed its depth on, and counting those let a shallow face
 * depth spread a ring further on a curved surface. So the rule does nothing
 * at flat angles of 60 degrees and more. On a sphere every neighbour's plane
 * passes through the centre, where the line meets it too: the depth is R
 * (the chair's crease anchors: median height 0.932). Measured at the
 * defaults (bench_completion, WLOP seeds 1-12; README (30)): the chair's
 * flipped normals 1.14% -> 1.02% (lower at 7 seeds of 12) and its coverage
 * 0.974 -> 0.967 (its back rest's unscanned rear had been reached by
 * anchors sunk out through it), the 95th percentile accuracy of the two-view
 * bunny 0.0437 -> 0.0400 (better at 11 seeds), the one view unchanged; the
 * anchors outside the true body at seed 1 went chair 63 -> 53, one view 165
 * -> 157, two views 153 -> 143. */
#ifndef DP_STAGES_FLAT_H
#define DP_STAGES_FLAT_H

#include "dpoints.h"
#include "knn/kdtree.h"

/* Samples closer than this (in r) pass the depth on; an even sampling has
 * about 20 within it. */
#define DP_FLAT_LINK_R 2.5
/* Neighbours per sample considered for a link: the nearest 20 reach about
 * DP_FLAT_LINK_R on an even sampling. */
#define DP_FLAT_NEIGHBOURS 20
/* An evidence point passes on the median depth of the evidence points
 * within this (in r) that face its way, at most DP_FLAT_RIM_COUNT of them. */
#define DP_FLAT_RIM_R 5.0
#define DP_FLAT_RIM_COUNT 128
/* The edge band is sought within DP_FLAT_BAND_R (in r, at most
 * DP_FLAT_BAND_COUNT samples), needs DP_FLAT_BAND_MIN of them, and one
 * reaching DP_FLAT_BAND_TALL of the depth that ball shows at the band's
 * nearest sample is a tall side face, not a plate's edge: plates up to about
 * 6 r thick show their edge's end. */
#define DP_FLAT_BAND_R 8.0
#define DP_FLAT_BAND_COUNT 384
#define DP_FLAT_BAND_MIN 3
/* Band samples count only this far (in r) or more below the face's plane:
 * ones beside it or above it (a rounded part turning away) are no edge. */
#define DP_FLAT_BAND_BELOW_R 0.25
#define DP_FLAT_BAND_TALL 0.8
/* A band is read this much (in r, one spacing) taller than its deepest
 * sample reaches. */
#define DP_FLAT_BAND_END_R 1.0
/* While sinking, a point settles on its face once this many times deeper
 * than the face's depth: past the far face of a plate that thick, where an
 * opposing front would have stopped it had the far face been scanned. */
#define DP_FLAT_PAST 2.0f
/* ... and only around an evidence point with at least this fraction of the
 * samples within DP_FLAT_RIM_R facing its way (a flat face, not a rounded
 * part whose far side is turned a right angle away). */
#define DP_FLAT_FACE_FRACTION 0.5
/* A crease sample's faces are turned from its normal by at most 60 degrees
 * (this cosine), and its line crosses their planes no more obliquely. */
#define DP_FLAT_CROSS_COS 0.5f
/* ... and it needs at least this many of them. */
#define DP_FLAT_CROSS_MIN 3

/* The samples' fixed part of the face depths, kept across the iterations of
 * sinking: their neighbour links, search tree and edge bands (geometry
 * alone), with the face depth that last reached each sample. */
typedef struct dp_flat {
	size_t n;
	int k;                        /* links per sample */
	const float *p[3], *normal[3];
	dp_kdtree tree;
	int *idx;                     /* n x k nearest samples, ascending */
	float *d2;
	float *half;                  /* the band's half height beside each sample, or INFINITY */
	float *face_half;             /* its median over the facing samples around, or INFINITY */
	float *cap;                   /* the face depth that reached each sample, or INFINITY */
	float *cross;                 /* the depth its faces' medial planes give (dp_flat_cross), or INFINITY */
	uint32_t *origin;             /* the sample it came from */
	unsigned char *done;
	struct entry *heap;
	uint32_t *sidx;               /* search buffers, DP_FLAT_BAND_COUNT per range */
	float *sd2, *svalue;
	float min_cos, sin_a, band_end, rim2, band2, link2, below_min;
} dp_flat;

/* Builds the context for n samples p with unit normals (the arrays are kept
 * by reference: they must outlive it and not change); angle_deg > 0. Errors: DP_ERR_NOMEM,
 * and the neighbour search's. On failure nothing needs freeing. */
dp_status dp_flat_init(dp_flat *f, int threads, size_t n, const float *const p[3], const float *const normal[3],
		       double r, double angle_deg, dp_error *err);
/* The face depth reaching every sample from the evidence in settled_by
 * (DP_SETTLE_FRONT and DP_SETTLE_MEDIAL samples, at their depths |q - p|) and
 * the edge bands; from the edge bands alone if settled_by is NULL. Runs on up
 * to `threads` threads; the result does not depend on it. */
void dp_flat_update(dp_flat *f, int threads, float *const q[3], const unsigned char *settled_by);
/* Whether sample i's inner point lies deeper than `past` times the face
 * depth that reached it at the last update; if so it moves up to that depth
 * along its line. */
int dp_flat_too_deep(const dp_flat *f, float *const q[3], size_t i, float past);
/* The crease rule above: moves the inner point of every sample with
 * settled_by DP_SETTLE_SLOW or DP_SETTLE_WIDTH along its line up to the
 * (upper) median depth at which the line crosses its faces' medial planes,
 * when that is shallower, and marks it DP_SETTLE_FLAT. Call after the face
 * depths have capped the samples they reach (dp_flat_too_deep, relabelled
 * DP_SETTLE_FLAT), so that those count as faces and are left alone. Every
 * depth is read before any point moves. Returns how many moved; runs on up
 * to `threads` threads, and the result does not depend on it. */
size_t dp_flat_cross(dp_flat *f, int threads, float *const q[3], unsigned char *settled_by);
void dp_flat_free(dp_flat *f);

/*
 * Caps the depth |q_i - p_i| of every sample with settled_by[i] ==
 * DP_SETTLE_SLOW or DP_SETTLE_WIDTH at the face depth that reaches it as described above
 * (the median depth of the DP_SETTLE_FRONT and DP_SETTLE_MEDIAL samples
 * within DP_FLAT_RIM_R r of an evidence sample, with normals within
 * angle_deg (> 0) of its, or the median half height of the edge bands beside
 * the samples there if less), moving
 * q_i towards p_i, and marks it DP_SETTLE_FLAT; then the crease rule
 * (dp_flat_cross). p: the n samples with unit normals; q: their inner points,
 * updated in place. *capped receives how many moved. The searches run on up
 * to `threads` threads (core/parallel.h); the result does not depend on it.
 * Errors: DP_ERR_NOMEM,
 * and the neighbour search's (a span whose squared distances overflow).
 */
dp_status dp_flat_cap(int threads, size_t n, const float *const p[3], const float *const normal[3], float *const q[3],
		      unsigned char *settled_by, double r, double angle_deg, size_t *capped, dp_error *err);

#endif
