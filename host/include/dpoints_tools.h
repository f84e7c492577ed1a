/*
 * dpoints_tools — what the dpoints tool and tests use around the library:
 * built-in analytic shapes, a virtual range scanner, metrics against a
 * ground truth, and pictures of point sets. Not needed to consolidate a
 * scan; installed beside dpoints.h for programs that want them.
 *
 * The conventions of dpoints.h hold here: dp_status results, one line in
 * dp_error, caller-owned outputs released with dp_cloud_free or free().
 * Every function here takes no dp_context, keeps no global state and is
 * reentrant.
 */
#ifndef DPOINTS_TOOLS_H
#define DPOINTS_TOOLS_H

#include "dpoints.h"

#ifdef __cplusplus
extern "C" {
#endif

/* -------------------------------------------------------------- rendering */

/*
 * Pictures of point sets for people to look at (owner: render module,
 * host/tools/render.c). All functions here take no dp_context and are
 * reentrant; they only read the layers and clouds they are given.
 */

/* One set of points drawn in one colour. The layer and the arrays it points
 * to stay owned by the caller. */
typedef struct dp_render_layer {
	const dp_cloud *cloud;    /* positions; its normals, when present, shade the points */
	const uint32_t *edges;    /* 2*nedges indices into cloud, drawn as segments; may be NULL */
	size_t nedges;
	int segments_only;        /* draw the edges but not the points (deep points as sticks) */
	unsigned char rgb[3];
	float point_size_px;      /* splat diameter in pixels; 0 = from the image size and point count */
} dp_render_layer;

typedef struct dp_render_params {
	int width;                    /* pixels of each (square) view; default 512 */
	int views;                    /* K views side by side, 360/K degrees apart; default 3;
	                                 1..64, and views*width^2 at most 2^25 pixels */
	int up_axis;                  /* 0 = x, 1 = y, 2 = z is vertical; default 1 (the Stanford scans) */
	double elevation_deg;         /* camera height above the horizon, in (-90, 90); default 20 */
	double azimuth_deg;           /* first view; 0 = camera on the +axis (up_axis+1) mod 3; default 0 */
	unsigned char background[3];  /* default white */
} dp_render_params;

DP_API void dp_render_params_default(dp_render_params *p);

/*
 * Renders every layer into one RGB image of views*width x width pixels: the
 * views orbit the vertical axis of the union bounding box of all layers, share
 * one orthographic camera scale fitted to that box, and are laid left to
 * right. Points are z-buffered round splats, edges z-buffered 1-pixel lines
 * (depth interpolated along them), so nearer geometry hides farther geometry
 * of any layer. Shading: with normals, Lambert |n.v| towards the viewer (so
 * unoriented or flipped normals are lit too); without, nearer is brighter.
 * Non-finite points and edges touching them are skipped. `params` NULL means
 * defaults. On success *rgb is a malloc'ed buffer of 3*(*w)*(*h) bytes, rows
 * top to bottom, that the caller frees. Errors: DP_ERR_ARG (size, views, axis,
 * elevation or point size out of range, a NULL layer array or cloud, an edge
 * index out of range), DP_ERR_EMPTY (no finite point in any layer),
 * DP_ERR_NOMEM.
 */
DP_API dp_status dp_render_rgb(const dp_render_layer *layers, size_t nlayers, const dp_render_params *params,
			unsigned char **rgb, int *w, int *h, dp_error *err);

/*
 * dp_render_rgb, then writes the image as an 8-bit RGB PNG at `path`, through
 * a temporary file in the same folder renamed at the end, so a failure never
 * leaves a file (partial or temporary) behind. Errors as dp_render_rgb, plus
 * DP_ERR_IO naming `path` when it cannot be written.
 */
DP_API dp_status dp_render_png(const char *path, const dp_render_layer *layers, size_t nlayers,
			const dp_render_params *params, dp_error *err);

/*
 * Parses a colour: a name (red, green, blue, orange, purple, yellow, cyan,
 * magenta, pink, brown, grey/gray, black, white; any case) or #rgb / #rrggbb
 * hex. DP_OK and fills rgb, or DP_ERR_ARG naming the text (NULL arguments,
 * an unknown name, malformed hex) leaving rgb untouched.
 */
DP_API dp_status dp_parse_colour(const char *text, unsigned char rgb[3], dp_error *err);

/* A colour for layer `index`: neighbouring indices get clearly different
 * hues, all readable on the default white background; cycles after 8. */
DP_API void dp_render_default_colour(size_t index, unsigned char rgb[3]);

/* ------------------------------------------ Shapes, scanning, evaluation */
/*
 * Owned by host/tools/ (shapes.c, shape_mesh.c, mesh.c, bvh.c, scan.c,
 * eval.c). A triangle mesh is
 * a dp_cloud whose faces hold 3*nfaces vertex indices, as dp_cloud_read(...,
 * DP_READ_MESH) returns it; meshes made here are closed and wound
 * counter-clockwise seen from outside (outward normals). Every function is
 * reentrant (no global state); outputs are caller-owned (dp_cloud_free, free).
 * A mesh without faces, with face indices out of range or with non-finite
 * vertices fails with DP_ERR_ARG / DP_ERR_FORMAT naming the stage.
 */

typedef enum dp_shape_kind {
	DP_SHAPE_SPHERE = 0,   /* radius R, centred at the origin */
	DP_SHAPE_CYLINDER,     /* capped; radius R, length L along z, centred */
	DP_SHAPE_SLAB,         /* thin box W x W (x, y) x T (z), centred */
	DP_SHAPE_TORUS,        /* core radius R in the xy-plane, tube radius rho */
	DP_SHAPE_KNOT,         /* tube of radius rho around a trefoil curve */
	DP_SHAPE_CHAIR,        /* seat slab, 4 cylindrical legs, back slab; floor z = 0 */
	DP_SHAPE_RODS          /* thin parts: 4 capped rods of radius R and length L along z, their axes at
	                          (±W/2, ±W/2), centred at z = 0 */
} dp_shape_kind;

/*
 * An analytic shape. Field meaning per kind (defaults from dp_shape_default):
 *   sphere:   radius = R (1)
 *   cylinder: radius = R (0.25), length = L (2)
 *   slab:     width = W (2), thickness = T (0.2)
 *   torus:    radius = R (1), tube = rho (0.3)
 *   knot:     radius = scale s of the trefoil (sin t + 2 sin 2t, cos t - 2 cos 2t,
 *             -sin 3t) (0.35), tube = rho (0.12); rho <= 0.5 s keeps the tube
 *             free of self-intersection
 *   chair:    width = seat W (1), thickness = seat and back T (0.08),
 *             radius = leg radius (0.05), length = leg length = seat height
 *             (0.9), height = back height above the seat (1); width more
 *             than 6 leg radii. The legs and the back stand on the seat;
 *             the mesh and the distance functions are the solid's boundary,
 *             without faces where the parts touch (the pieces meet along
 *             their edges without sharing vertices).
 * resolution = segments around the smallest circumference (48; knot and
 * chair 32); other directions are divided so that triangles are roughly
 * equilateral (flat faces: at most `resolution` cells per side).
 */
typedef struct dp_shape {
	dp_shape_kind kind;
	double radius, length, width, thickness, tube, height;
	int resolution;
} dp_shape;

/* Fills `shape` with the defaults of the shape called `name` ("sphere",
 * "cylinder", "slab", "torus", "knot", "chair"); DP_ERR_ARG listing the valid
 * names otherwise. */
DP_API dp_status dp_shape_default(const char *name, dp_shape *shape, dp_error *err);
/* The name of a kind ("sphere", ...), or "unknown". */
DP_API const char *dp_shape_name(dp_shape_kind kind);
/* Triangulates the shape into `mesh` (positions and faces, no normals).
 * DP_ERR_ARG for non-positive or inconsistent dimensions or a resolution
 * outside [3, 4096]. */
DP_API dp_status dp_shape_mesh(const dp_shape *shape, dp_cloud *mesh, dp_error *err);
/* Exact volume of the analytic solid (knot: pi rho^2 times the curve length);
 * NAN for an invalid shape. */
DP_API double dp_shape_volume(const dp_shape *shape);
/* Unsigned distance from p to the analytic surface (closed form; knot: the
 * nearest core point is found numerically, to about 1e-9 s). NAN for an
 * invalid shape. Both distance functions are pure and reentrant. */
DP_API double dp_shape_surface_distance(const dp_shape *shape, const double p[3]);
/* Distance from p to the ideal meso-skeleton: sphere centre, cylinder axis
 * segment (|z| <= L/2), slab mid-plane rectangle, torus core circle, knot core
 * curve, chair: nearest of seat and back mid-plane rectangles and leg axes. */
DP_API double dp_shape_skeleton_distance(const dp_shape *shape, const double p[3]);
/* n >= 2 samples of the core curve into `out` (positions only): cylinder
 * axis from z = -L/2 to L/2, torus core circle, knot core curve (closed curves
 * are sampled without repeating the first point). DP_ERR_ARG for shapes
 * without a single core curve. */
DP_API dp_status dp_shape_core_curve(const dp_shape *shape, size_t n, dp_cloud *out, dp_error *err);

/*
 * n points sampled uniformly by area on the mesh surface (seeded,
 * reproducible), each with the unit normal of its triangle (outward for
 * outward-wound meshes), plus isotropic Gaussian noise of standard deviation
 * `noise` x the bbox diagonal per coordinate (0 = exact samples). DP_ERR_ARG
 * for n == 0, a negative noise or a mesh of zero area.
 */
DP_API dp_status dp_mesh_sample(const dp_cloud *mesh, size_t n, double noise, uint64_t seed,
			 dp_cloud *out, dp_error *err);

typedef enum dp_scan_layout {
	DP_SCAN_RING = 0,   /* eyes on a circle around the up axis at `elevation_deg` */
	DP_SCAN_SPHERE = 1  /* eyes spread evenly over a sphere (Fibonacci lattice) */
} dp_scan_layout;

typedef struct dp_scan_params {
	int views;             /* number of viewpoints; default 6 */
	int res;               /* rays per view: res x res grid; default 256 */
	double noise;          /* Gaussian sigma per coordinate, in bbox diagonals; default 0 */
	double distance;       /* eye distance from the bbox centre, in bbox diagonals (> 0.5); default 2 */
	int perspective;       /* 1 = pinhole rays from the eye (default); 0 = parallel rays */
	dp_scan_layout layout; /* default DP_SCAN_RING */
	int up_axis;           /* the ring's axis and the cameras' up: 0 = x, 1 = y, 2 = z; default 2 */
	double elevation_deg;  /* ring: eye height angle above the plane across up_axis; default 20 */
	double azimuth_deg;    /* ring: azimuth of view 0, from axis up+1 towards up+2; default 0 */
	int normals;           /* output the hit triangle's normal, turned to face the eye; default 1 */
	uint64_t seed;         /* noise seed; default 1 */
} dp_scan_params;

DP_API void dp_scan_params_default(dp_scan_params *p);
/* DP_ERR_ARG when a parameter is out of range or p is NULL (what dp_scan
 * checks first): lets a caller refuse them before reading a mesh.
 * Thread-safe. */
DP_API dp_status dp_scan_params_check(const dp_scan_params *p, dp_error *err);

/*
 * Range-scans `mesh` by ray casting (BVH, first hit per ray): every view
 * aims a res x res grid of rays at the bbox centre that just covers the
 * mesh's bounding sphere. `out` receives the hit points in view order (with
 * normals when params->normals). When `view_of_point` is not NULL it receives
 * a malloc'ed array of out->n view indices (caller frees). DP_ERR_ARG for
 * parameters out of range, DP_ERR_EMPTY when no ray hits.
 */
DP_API dp_status dp_scan(const dp_cloud *mesh, const dp_scan_params *params, dp_cloud *out,
		  uint32_t **view_of_point, dp_error *err);
/* The eye positions of the views of dp_scan (3 * params->views doubles). */
DP_API dp_status dp_scan_viewpoints(const dp_cloud *mesh, const dp_scan_params *params, double *eyes,
			     dp_error *err);

typedef struct dp_eval_params {
	size_t samples;         /* uniform surface samples for completeness/coverage; default 20000 */
	double coverage_factor; /* a sample is covered within factor x mean NN spacing; default 1.5 */
	uint64_t seed;          /* surface sampling seed; default 1 */
} dp_eval_params;

DP_API void dp_eval_params_default(dp_eval_params *p);
/* DP_ERR_ARG when a parameter is out of range (what dp_eval checks first);
 * NULL, dp_eval's defaults, passes. Thread-safe. */
DP_API dp_status dp_eval_params_check(const dp_eval_params *p, dp_error *err);

/* The neighbours of each point whose spread dp_eval_result.scatter_median
 * reads. */
#define DP_EVAL_SCATTER_NEIGHBOURS 15

/* Metrics of a point set against a ground-truth mesh. Every length is in
 * units of the mesh's bbox diagonal. Coverage is relative to the points' own
 * spacing: evenly spread points covering the whole surface score about 1,
 * uniformly random ones only 1 - exp(-pi 1.5^2 / 4) = 0.83 (Poisson), and
 * overlapping scan views, denser where they overlap, score lower still. */
typedef struct dp_eval_result {
	size_t points, samples;
	double diagonal;          /* bbox diagonal of the mesh, input units */
	double accuracy_mean;     /* mean distance of the points to the surface */
	double accuracy_p95;      /* its 95th percentile */
	double accuracy_rms;      /* root mean square (= noise sigma for noisy exact samples) */
	double accuracy_max;
	double completeness_mean; /* mean distance of surface samples to the nearest point */
	double coverage;          /* fraction of surface samples within coverage_radius of a point */
	double coverage_radius;   /* coverage_factor x spacing_mean */
	double spacing_mean;      /* mean nearest-neighbour distance among the points */
	double spacing_cv;        /* its coefficient of variation (std / mean): uniformity */
	/* How far the points scatter off a surface, needing no mesh: the median
	 * over the points of sqrt(w0 / w2), w0 <= w1 <= w2 the eigenvalues of
	 * the covariance of a point and its DP_EVAL_SCATTER_NEIGHBOURS nearest
	 * (fewer when there are not that many), read at up to 100000 of them
	 * chosen through the set. 0 where they lie in a plane, about 0.6 in a
	 * random cloud filling a volume, 0.68 sigma / h on a grid of spacing h
	 * with noise sigma across it; points on a curved surface score by its
	 * curvature over that neighbourhood (samples of the Stanford bunny at
	 * 2500 points: 0.11-0.14, as they are spread), and a part thinner than
	 * the neighbourhood reads high, its far face falling in. Coincident
	 * points are neighbours like any: repeated points read flat. A completed
	 * region guessed as a layer of scattered points reads high beside the
	 * scanned part (README "Results measured here", (38)). */
	double scatter_median;
	int has_normals;          /* normal metrics below are valid (0 when points have none) */
	size_t normals_used;      /* points with a usable (non-zero, finite) normal */
	double normal_angle_deg;  /* mean angle to the nearest triangle's normal, ignoring sign */
	double normal_flipped;    /* fraction more than 90 deg from the face normal (outward if the
				   * mesh is wound counter-clockwise seen from outside) */
	/* The fraction more than 90 deg from every face within their distance
	 * plus half spacing_mean: flips the points' own resolution settles. A
	 * normal in a part thinner than that, or beside a crease, that faces
	 * either of its faces counts as right whichever one is nearest; a point
	 * far off the surface reaches many faces and is excused more often. */
	double normal_flipped_clear;
	double seconds;
} dp_eval_result;

/*
 * Evaluates `points` (at least 2, finite; normals optional) against `mesh`.
 * params may be NULL for the defaults. Accuracy uses the exact point-triangle
 * distance; completeness and coverage use params->samples area-uniform
 * samples of the mesh. Errors: DP_ERR_EMPTY for fewer than 2 points;
 * DP_ERR_ARG for bad parameters, non-finite points, a mesh without faces,
 * of zero extent or zero area or with more vertices than 32-bit indices
 * reach, or coordinates whose span overflows the neighbour search; DP_ERR_FORMAT for a non-finite mesh vertex or a face
 * naming a vertex the mesh lacks; DP_ERR_NOMEM; DP_ERR_INTERNAL when the
 * neighbour search (FLANN) fails.
 */
DP_API dp_status dp_eval(const dp_cloud *mesh, const dp_cloud *points, const dp_eval_params *params,
		  dp_eval_result *result, dp_error *err);
/* Prints the result as one JSON object on one line; does not flush. */
DP_API void dp_eval_json(const dp_eval_result *result, FILE *out);

/* ------------------------------------------------ Fit to a built-in shape */
/*
 * Owner: host/tools/shape_fit.c (the end-to-end quality checks:
 * tests/test_pipeline_shapes.c, bench/bench_quality_sizes.c). Reentrant, no global
 * state. Lengths in shape units.
 */
typedef struct dp_shape_fit {
	size_t points;
	double surface_mean;  /* mean dp_shape_surface_distance of the points */
	double skeleton_mean; /* mean dp_shape_skeleton_distance of the points */
	size_t inside;        /* cylinder, slab, torus: points within the half thickness (R, T/2, rho)
	                         of the ideal skeleton; only these count for spread and largest_gap */
	double spread;        /* cylinder, torus: fraction of the core curve's length within cell/2 of
	                         an inside point's position along it; slab: fraction of the W x W
	                         mid-plane's squares (side about `cell`) holding an inside point;
	                         NAN for other shapes */
	double largest_gap;   /* cylinder, torus: longest stretch of the core curve between consecutive
	                         inside points (torus: cyclic; cylinder: between the first and the
	                         last), as a fraction of its length; NAN for other shapes */
} dp_shape_fit;

/*
 * Measures `points` against `shape` (positions only). `cell` > 0 sets the
 * resolution of `spread`. Errors: DP_ERR_ARG (invalid shape, cell, or a
 * non-finite point), DP_ERR_EMPTY (no points), DP_ERR_NOMEM; on error *fit
 * is zeroed with spread and largest_gap NAN.
 */
DP_API dp_status dp_shape_fit_points(const dp_shape *shape, const dp_cloud *points, double cell, dp_shape_fit *fit,
			      dp_error *err);

#ifdef __cplusplus
}
#endif
#endif
