/* Bounding volume hierarchy over the triangles of a mesh: first-hit ray casts
 * (the scanner) and nearest-triangle queries (the evaluator). Built once by
 * median splits of triangle centroids into a flat node array; queries use a
 * fixed stack and never allocate, so one built BVH may be queried from many
 * threads at once. */
#ifndef DP_TOOLS_BVH_H
#define DP_TOOLS_BVH_H

#include "dpoints_tools.h"

/* Triangles per leaf: small enough that leaves are cheap to test, large
 * enough to keep the tree shallow. */
#define DP_BVH_LEAF_SIZE 4
/* Median splits halve the triangle count per level, so 64 levels bound any
 * mesh that 32-bit indices can address. */
#define DP_BVH_MAX_DEPTH 64

typedef struct dp_bvh_node {
	double lo[3], hi[3];
	uint32_t first; /* leaf: first triangle slot; inner: the right child (the left one is next) */
	uint32_t count; /* leaf: number of triangles (> 0); inner: 0 */
} dp_bvh_node;

typedef struct dp_bvh {
	size_t ntris, nnodes;
	dp_bvh_node *nodes;
	uint32_t *face;  /* slot -> face index in the mesh */
	double *tri;     /* per slot 9 doubles: corner a, edge b - a, edge c - a */
} dp_bvh;

typedef struct dp_bvh_hit {
	double t;       /* ray parameter: hit = origin + t * dir */
	uint32_t face;  /* face index in the mesh */
} dp_bvh_hit;

/* Builds the BVH of a mesh that passed dp_mesh_check. */
dp_status dp_bvh_build(dp_bvh *bvh, const dp_cloud *mesh, dp_error *err);
void dp_bvh_free(dp_bvh *bvh);

/* First hit with t in (0, tmax]; returns 1 and fills `hit`, or 0. */
int dp_bvh_raycast(const dp_bvh *bvh, const double origin[3], const double dir[3], double tmax,
		   dp_bvh_hit *hit);
/* Nearest triangle to p: returns the squared distance, the closest point and
 * the face index. */
double dp_bvh_nearest(const dp_bvh *bvh, const double p[3], double closest[3], uint32_t *face);

/* Whether some triangle within squared distance r2 of p faces along n (its
 * normal by winding, (b - a) x (c - a), makes an acute angle with n). */
int dp_bvh_facing_within(const dp_bvh *bvh, const double p[3], double r2, const double n[3]);

/* The primitives, exposed so tests can check the BVH against brute force. */
/* Möller–Trumbore: returns 1 and t when the ray hits triangle (a, a+e1, a+e2)
 * at t > 0. */
int dp_ray_triangle(const double o[3], const double d[3], const double a[3], const double e1[3],
		    const double e2[3], double *t);
/* Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision
 * Detection 5.1.5; degenerate triangles fall back to their edges). */
void dp_closest_point_triangle(const double p[3], const double a[3], const double b[3],
			       const double c[3], double out[3]);

#endif
