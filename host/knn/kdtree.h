/* A static kd-tree over 3D points that answers two questions fast: does a
 * ball hold any of them, and which are the nearest ones in a ball? The
 * sinking stage's medial test asks the first of every unsettled inner point
 * each iteration; FLANN's exact nearest-neighbour query answered it at about
 * 1.4 us a query on the statue, over half of the stage's time. Every node
 * keeps its points' bounding box, so a ball that holds nothing is proved
 * empty by visiting only the nodes whose boxes it reaches, and a ball that
 * holds a point stops at the first one found. The second serves the flat-face
 * step's searches from several threads at once: the tree is read-only once
 * built, where every call of FLANN's C API writes its global log level. */
#ifndef DP_KNN_KDTREE_H
#define DP_KNN_KDTREE_H

#include "dpoints.h"

#include <stdint.h>

typedef struct dp_kdtree {
	size_t n;
	float *x, *y, *z;   /* the points in tree order */
	uint32_t *index;     /* the caller's index of each of them */
	unsigned char *axis; /* split axis of the node whose median is point k */
	float *box;          /* its points' bounding box: 6k..6k+2 low x, y, z, 6k+3..6k+5 high */
} dp_kdtree;

/* Builds the tree over n points (copied). Median splits along the widest
 * axis of each node's points. */
dp_status dp_kdtree_build(dp_kdtree *t, size_t n, const float *x, const float *y, const float *z, dp_error *err);
void dp_kdtree_free(dp_kdtree *t);

/* Whether some point p has (px - x)² + (py - y)² + (pz - z)², evaluated in
 * float in that order, below r2: the same predicate as a brute-force scan, so
 * also the same as FLANN's nearest squared distance < r2 (its L2 sums in that
 * order). False for r2 <= 0 or a NaN query. */
int dp_kdtree_any_within(const dp_kdtree *t, float x, float y, float z, float r2);

/* The points within r2 (the predicate above), the nearest `cap` of them when
 * there are more, as FLANN's radius search with a neighbour limit gives them:
 * their indices into the arrays the tree was built from in idx[0..k) and
 * their squared distances in d2[0..k), in no particular order. Returns k.
 * Reentrant: threads may query one tree at once. */
size_t dp_kdtree_nearest_within(const dp_kdtree *t, float x, float y, float z, float r2, size_t cap, uint32_t *idx,
				float *d2);

#endif
