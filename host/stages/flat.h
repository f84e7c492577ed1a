/* The depth of flat faces scanned from one side (dpoints.h, sinking step 5;
 * not in the paper).
 *
 * Opposing fronts, the medial test and the width bound stop a sinking point
 * on geometric evidence. A flat face scanned from one side has none in its
 * middle: no front opposes it, no ball touches it again, and a plate is wide.
 * Its points stop only by slow-down, which creeps in from the face's rim one
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
 * evidence point's, and a point that stopped by slow-down takes it when it
 * is shallower than its own depth. Measuring the angle from the evidence
 * point, not from link to link, keeps a curved surface from passing the
 * depth along: on a sphere of radius R the depth travels at most R
 * sin(angle) and stays R. The smallest depth travels first, and a sample
 * passes on only the first that reaches it: where two flat faces meet, each
 * keeps its own. A box's face is no plate, and needs no exception: its side
 * faces are tall, and its face's points settle by the medial test at every
 * depth before slow-down reaches them. */
#ifndef DP_STAGES_FLAT_H
#define DP_STAGES_FLAT_H

#include "dpoints.h"

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

/*
 * Caps the depth |q_i - p_i| of every sample with settled_by[i] ==
 * DP_SETTLE_SLOW at the face depth that reaches it as described above
 * (the median depth of the DP_SETTLE_FRONT and DP_SETTLE_MEDIAL samples
 * within DP_FLAT_RIM_R r of an evidence sample, with normals within
 * angle_deg (> 0) of its), moving q_i towards p_i, and marks it
 * DP_SETTLE_FLAT. p: the n samples with unit normals; q: their inner points,
 * updated in place. *capped receives how many moved. Errors: DP_ERR_NOMEM,
 * and the neighbour search's (a span whose squared distances overflow).
 */
dp_status dp_flat_cap(size_t n, const float *const p[3], const float *const normal[3], float *const q[3],
		      unsigned char *settled_by, double r, double angle_deg, size_t *capped, dp_error *err);

#endif
