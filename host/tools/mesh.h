/* Triangle meshes held in a dp_cloud (positions + faces): validation and the
 * geometry that the scanner, the evaluator and the tests share. */
#ifndef DP_TOOLS_MESH_H
#define DP_TOOLS_MESH_H

#include "dpoints_tools.h"

/* Fails (naming `stage`) unless the mesh has faces, every index is in range
 * and every vertex is finite. */
dp_status dp_mesh_check(const dp_cloud *mesh, const char *stage, dp_error *err);

/* Bounding box of all vertices. */
void dp_mesh_bbox(const dp_cloud *mesh, double lo[3], double hi[3]);
/* Length of the bounding box diagonal. */
double dp_mesh_diagonal(const dp_cloud *mesh);

/* The corners of face f. */
void dp_mesh_triangle(const dp_cloud *mesh, size_t f, double a[3], double b[3], double c[3]);
/* Unit normal of face f by its winding (zero for a degenerate face); returns
 * the face's area. */
double dp_mesh_triangle_normal(const dp_cloud *mesh, size_t f, double n[3]);

/* Total area, and the signed volume enclosed (positive for a closed mesh wound
 * counter-clockwise seen from outside). */
double dp_mesh_area(const dp_cloud *mesh);
double dp_mesh_signed_volume(const dp_cloud *mesh);

#endif
