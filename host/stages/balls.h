/* The inside test of the surface stage (dpoints.h, dp_balls; not in the
 * paper). A surface point with no input to hold it slides and turns about
 * its inner end; past the end of its part of the skeleton it turns inwards
 * and drifts through the body. Measured on the two-view bunny at 4000 deep
 * points (before the flat-face step of sinking): 161 points ended more than
 * 0.01 diagonals inside, 73 of them with flipped normals; each had started
 * on the data and left it within 60 iterations. Sinking knows what is inside: a point settled on geometric
 * evidence (an opposing front, the medial test) left behind a ball that
 * touches the surface at its sample and holds no other sample. A point deep
 * in such a ball and facing its centre is inside the body; it moves out to
 * the ball's sphere along the ray from the centre and takes the inner end of
 * the ball's own surface point.
 *
 * Most balls of a smooth part lie inside bigger ones, and a contained ball
 * is never deeper than its container, so the set is pruned to the balls no
 * other contains. Balls that touch the input (dp_consolidate cuts them to
 * it) are seldom exactly inside one another: a one-view sphere's 4000 kept
 * 3970, every query read them all, and the test cost 1.1 s at 32000 deep
 * points. Within a slack of half a spacing they nest again (2 to 9 kept),
 * and the deepest ball's depth is found to within that slack. Pruning also
 * drops the contained ball's centre from the facing test: a point that faces
 * a contained ball's centre but not its container's no longer moves. */
#ifndef DP_STAGES_BALLS_H
#define DP_STAGES_BALLS_H

#include "dpoints.h"
#include "grid/grid.h"

typedef struct dp_ball_set {
	size_t n;          /* balls kept */
	dp_grid grid;      /* their centres, cells no smaller than the largest radius */
	float *radius;     /* per kept ball, in the grid's order */
	uint32_t *row;     /* per kept ball, in the grid's order: its row of dp_balls */
} dp_ball_set;

/* Keeps the balls of `in` with a positive radius that no other contains
 * once grown by `slack` >= 0 (ties: the lower row). Zero-initialise `set`
 * first; free with dp_ball_set_free. DP_ERR_NOMEM, the grid's errors. */
dp_status dp_ball_set_build(dp_ball_set *set, const dp_balls *in, float slack, dp_error *err);
void dp_ball_set_free(dp_ball_set *set);

/* The kept ball that (x, y, z) lies deepest in, by more than `margin`, among
 * those whose centre lies ahead of the point along (nx, ny, nz): its index in
 * the grid's order, or -1. When one is found, *dist receives the point's
 * distance from its centre (untouched otherwise). Reads only; any number of
 * threads may query one set. */
int32_t dp_ball_set_deepest(const dp_ball_set *set, float x, float y, float z, float nx, float ny, float nz,
			    float margin, float *dist);

#endif
