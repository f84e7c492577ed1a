/*
 * dpoints — Deep Points Consolidation (Wu et al., SIGGRAPH Asia 2015) of raw,
 * noisy, incomplete 3D scans, with OpenCL kernels and a scalar reference.
 *
 * The library's one header (the scanner, shapes, metrics and renderer used
 * around it are in dpoints_tools.h). Conventions for every function below:
 *  - Functions return a dp_status; DP_OK is zero. When `err` is not NULL it
 *    receives one human-readable line naming the file or stage and the problem.
 *  - Structures the library fills (dp_cloud, dp_wlop_stats, ...) are owned by
 *    the caller once returned and are released with the matching _free function.
 *  - Lengths are in the units of the input coordinates unless a name says `_r`
 *    (multiples of r, the mean nearest-neighbour spacing of the surface samples).
 *  - Thread-safety: functions that take no dp_context are reentrant. A
 *    dp_context may be used by one thread at a time; different contexts may be
 *    used from different threads concurrently.
 */
#ifndef DPOINTS_H
#define DPOINTS_H

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

#include "dpoints_version.h"

/* Marks the functions the shared library exports: it is built with hidden
 * visibility, so nothing else (no internal helper) becomes part of its ABI. */
#if defined(_WIN32) && defined(DP_SHARED_BUILD)
#define DP_API __declspec(dllexport)
#elif defined(__GNUC__)
#define DP_API __attribute__((visibility("default")))
#else
#define DP_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------------------------------------------- version */

/* The library's version as "MAJOR.MINOR.PATCH", a static string. Compare it
 * with DP_VERSION_STRING to see whether the library a program runs with is
 * the one it was compiled against. Reentrant. */
DP_API const char *dp_version(void);

/* ------------------------------------------------------------------ errors */

typedef enum dp_status {
	DP_OK = 0,
	DP_ERR_ARG,          /* an argument or parameter is out of range */
	DP_ERR_IO,           /* a file could not be opened, read or written */
	DP_ERR_FORMAT,       /* a file's contents are malformed or unsupported */
	DP_ERR_EMPTY,        /* an input holds no usable points */
	DP_ERR_NOMEM,        /* host memory allocation failed */
	DP_ERR_NO_DEVICE,    /* no OpenCL platform/device, or none matches */
	DP_ERR_CL,           /* an OpenCL call failed (message has the cl_int name) */
	DP_ERR_KERNEL_BUILD, /* the OpenCL program failed to build (log in message) */
	DP_ERR_INTERNAL,     /* an invariant broke; a bug */
	DP_ERR_CANCELLED     /* the progress callback asked to stop (dp_progress_fn) */
} dp_status;

#define DP_ERROR_MESSAGE_MAX 1024

/* Error details. Caller-owned, usually on the stack; zero-initialise it. */
typedef struct dp_error {
	dp_status status;
	char message[DP_ERROR_MESSAGE_MAX];
} dp_error;

/* A static string naming the status ("file format error", ...). */
DP_API const char *dp_status_string(dp_status status);

/* ------------------------------------------------------------- point sets */

/*
 * A point set, structure-of-arrays. x, y, z hold n floats each. nx, ny, nz are
 * either all NULL or all hold n floats. faces, when not NULL, holds 3*nfaces
 * vertex indices of triangles (only filled when a mesh is asked for). rgb,
 * when not NULL, holds 3*n colour bytes (red, green, blue of point i at 3i),
 * as read from PLY red/green/blue, PCD rgb/rgba and XYZ/PTS colour columns;
 * intensity, when not NULL, n values as read (PLY intensity or
 * scalar_intensity, PCD intensity, the XYZ/PTS intensity column).
 * All arrays are malloc'ed and owned by the struct; release with dp_cloud_free.
 */
typedef struct dp_cloud {
	size_t n;
	float *x, *y, *z;
	float *nx, *ny, *nz;
	size_t nfaces;
	uint32_t *faces;
	unsigned char *rgb; /* last, so code built against the struct without it still lines up */
	float *intensity;
} dp_cloud;

/* Allocates arrays for n points (and normals when with_normals); the contents
 * are uninitialised. The struct is overwritten, not freed first; the caller
 * owns it (dp_cloud_free). DP_ERR_NOMEM, the struct zeroed. */
DP_API dp_status dp_cloud_alloc(dp_cloud *cloud, size_t n, int with_normals, dp_error *err);
/* Adds (uninitialised) normal arrays to a cloud that has none. */
DP_API dp_status dp_cloud_add_normals(dp_cloud *cloud, dp_error *err);
/* Frees every array and zeroes the struct. NULL and zeroed structs are fine. */
DP_API void dp_cloud_free(dp_cloud *cloud);
/* Deep copy of src (faces included) into dst, which is overwritten, not freed
 * first, and must not be src. DP_ERR_NOMEM; dst is zeroed on error. */
DP_API dp_status dp_cloud_copy(dp_cloud *dst, const dp_cloud *src, dp_error *err);

/* ---------------------------------------------------------------- file I/O */

typedef enum dp_read_flags {
	DP_READ_POINTS = 0,    /* positions (and normals when the file has them) */
	DP_READ_MESH = 1       /* also read triangle faces (polygons are fanned) */
} dp_read_flags;

/*
 * Reads PLY (ascii, binary little/big endian), XYZ (3 or 6 columns), PCD
 * (ascii, binary), OFF/NOFF or OBJ, chosen by the file extension (and the
 * PLY/OFF magic). Rejects missing, empty, truncated or lying files and
 * non-finite coordinates with DP_ERR_IO / DP_ERR_FORMAT / DP_ERR_EMPTY; on
 * error `cloud` is left zeroed. On success the caller owns `cloud`.
 */
DP_API dp_status dp_cloud_read(const char *path, dp_cloud *cloud, int flags, dp_error *err);

/*
 * Reads a point file that is already in memory: the `size` bytes at `data`
 * are parsed exactly as dp_cloud_read parses a file named `name`, whose
 * extension picks the format ("scan.ply", "cloud.xyz", ...) and which error
 * messages name as the file. `data` is only read, needs no terminating NUL,
 * and is not referenced after the call returns; the caller keeps it. Errors
 * and guarantees are dp_cloud_read's: DP_ERR_FORMAT for an unknown extension
 * or malformed contents, DP_ERR_EMPTY for size 0 or no points, DP_ERR_NOMEM,
 * DP_ERR_ARG for a NULL cloud or name, NULL data with size > 0 or unknown
 * flags; on error `cloud` is left zeroed, on success the caller owns it
 * (dp_cloud_free). Reentrant; owned by the I/O module (host/io).
 */
DP_API dp_status dp_cloud_read_memory(const void *data, size_t size, const char *name, dp_cloud *cloud, int flags,
			       dp_error *err);

/* A named per-vertex float property for dp_ply_write. */
typedef struct dp_ply_property {
	const char *name;
	const float *values; /* n floats */
} dp_ply_property;

/*
 * Writes a PLY file: n vertices with the given float properties (in order),
 * then optional edges (2*nedges vertex indices, `element edge`, so MeshLab and
 * CloudCompare draw segments) and faces (3*nfaces). Binary little endian unless
 * `ascii`. Written to a temporary name in the same folder and renamed, so a
 * failure never leaves a partial file at `path`.
 */
DP_API dp_status dp_ply_write(const char *path, size_t n, const dp_ply_property *props, size_t nprops,
		       const uint32_t *edges, size_t nedges, const uint32_t *faces, size_t nfaces,
		       int ascii, dp_error *err);

/* Writes x y z (and nx ny nz when present, faces when present) as PLY. */
DP_API dp_status dp_cloud_write_ply(const char *path, const dp_cloud *cloud, int ascii, dp_error *err);

/*
 * Reads the `element edge` (int vertex1, vertex2) of a PLY file, as
 * dp_ply_write writes it, into a malloc'ed array of 2 * *nedges vertex indices
 * (the caller frees it with free()). Other formats, and PLY files without an
 * edge element, give *edges = NULL, *nedges = 0 and DP_OK. Errors as for
 * dp_cloud_read, plus an edge index out of range (DP_ERR_FORMAT); on error
 * *edges is NULL and *nedges 0. Owner: the I/O module (host/io). Reentrant.
 */
DP_API dp_status dp_ply_read_edges(const char *path, uint32_t **edges, size_t *nedges, dp_error *err);

/* ------------------------------------------------------- OpenCL, backends */

typedef enum dp_backend_kind {
	DP_BACKEND_CL = 0,  /* OpenCL kernels on the chosen device */
	DP_BACKEND_REF = 1  /* scalar C reference: the specification, slow */
} dp_backend_kind;

/* Opaque: the backend, and for DP_BACKEND_CL the device, context, queue and
 * built program (built once, reused by every call on this context). */
typedef struct dp_context dp_context;

/*
 * Creates a context. For DP_BACKEND_CL, `device` picks the device: NULL means
 * the DPOINTS_DEVICE environment variable, else device 0; a decimal string is
 * an index into the list printed by dp_list_devices; anything else is matched
 * as a case-insensitive substring of "platform / device" names. Fails with
 * DP_ERR_NO_DEVICE or DP_ERR_KERNEL_BUILD (build log in err). For
 * DP_BACKEND_REF no OpenCL call is made. Free with dp_context_free.
 */
DP_API dp_status dp_context_create(dp_context **ctx, dp_backend_kind kind, const char *device, dp_error *err);
/* Releases the context and its OpenCL objects; NULL is fine. */
DP_API void dp_context_free(dp_context *ctx);
/* "reference (scalar C)" or the OpenCL platform and device name; the string
 * belongs to ctx and lives until dp_context_free. */
DP_API const char *dp_context_device_name(const dp_context *ctx);
DP_API dp_backend_kind dp_context_backend(const dp_context *ctx);

/*
 * Called after every iteration of a long stage with the stage name ("wlop",
 * "sink", "skeleton", "surface"; each refined level is another "surface"
 * run; "even" the even-spacing rounds; "coarser" the WLOP runs of the coarser
 * coarse levels a one-sided scan tries, dp_refine_params.coarse_min, the
 * last of them kept when any is; "denser" the WLOP samples that
 * dp_orient_from_denser takes signs from), the iteration (from 1), a
 * stage-specific value (sink: settled points; skeleton, surface and even:
 * mean move in r; WLOP runs: mean move in h) and the seconds since the
 * context was created. Runs on the
 * thread that called the stage, between iterations (an iteration of a large
 * input may take seconds, so a stop takes effect within one).
 * Return 0 to go on; any other value stops the running call, which frees
 * what it made, leaves its outputs zeroed as on any error and returns
 * DP_ERR_CANCELLED. `stage` is a static string; the callback must not use
 * the context it reports on.
 */
typedef int (*dp_progress_fn)(void *user, const char *stage, int iteration, double value, double elapsed);
/* Sets the callback of every later call on ctx; NULL turns reports off (the
 * default). `user` is passed through and stays the caller's. Not thread-safe
 * with a call running on ctx. */
DP_API void dp_context_set_progress(dp_context *ctx, dp_progress_fn fn, void *user);

/*
 * How many threads the host side of every later call on ctx may use for its
 * loops over points (the sinking's medial test, width bound and flat faces,
 * the skeleton's PCA frames, the surface stage's normals, pair accounting);
 * the OpenCL kernels are the device's business. 0 or less means the CPUs the
 * process may run on (its affinity: a Slurm job's or a container's share; the
 * default), 1 one thread; at most 64 are used. Results do not depend on it.
 * The threads are a pool shared by the whole process, started on first use
 * and kept, asleep between loops; every loop has finished when the call
 * returns. A process may fork at any time, from any thread: the child starts
 * with an idle pool of its own. Not thread-safe with a call running on ctx.
 */
DP_API void dp_context_set_threads(dp_context *ctx, int threads);
/* The thread count later calls use (never 0: the resolved default). */
DP_API int dp_context_threads(const dp_context *ctx);

typedef enum dp_device_type {
	DP_DEVICE_CPU = 0,
	DP_DEVICE_GPU = 1,
	DP_DEVICE_OTHER = 2   /* accelerators, custom devices */
} dp_device_type;

#define DP_DEVICE_NAME_MAX 400

/* One OpenCL device, as dp_devices lists it. */
typedef struct dp_device_info {
	size_t index;                  /* its place in the list: dp_context_create accepts it in decimal */
	char name[DP_DEVICE_NAME_MAX]; /* "platform / device"; any substring of it selects it too */
	dp_device_type type;
	unsigned compute_units;
	uint64_t global_mem_bytes;
} dp_device_info;

/*
 * Every OpenCL device of every platform, in the order of the indices
 * dp_context_create accepts. On success *list is a malloc'ed array of *count
 * entries that the caller releases with dp_devices_free; no OpenCL platform
 * installed is not an error (*list NULL, *count 0). Errors: DP_ERR_ARG (NULL
 * list or count), DP_ERR_CL when a query fails, DP_ERR_NOMEM; *list is NULL
 * and *count 0 on error. Reentrant.
 */
DP_API dp_status dp_devices(dp_device_info **list, size_t *count, dp_error *err);
/* Frees a list from dp_devices; NULL is fine. */
DP_API void dp_devices_free(dp_device_info *list);

/* Prints the list of dp_devices, one device per line with its index, type,
 * compute units and memory. DP_ERR_NO_DEVICE when there is none, DP_ERR_CL
 * when the query fails. Reentrant. */
DP_API dp_status dp_list_devices(FILE *out, dp_error *err);

/* ------------------------------------------------------------------- WLOP */
/*
 * Weighted locally optimal projection (Huang et al. 2009), owned
 * by host/stages/wlop.c: m samples of the input move to a denoised, evenly
 * spaced set on its surface. Uses only the dp_context passed in (one thread
 * at a time per context).
 */

typedef enum dp_wlop_weight {
	DP_WLOP_L1 = 0,      /* α = θ(d)/d: L1-median attraction (Huang et al. 2009) */
	DP_WLOP_GAUSSIAN = 1 /* α = θ(d): Gaussian mean (CGAL, the authors' tool) */
} dp_wlop_weight;

/*
 * Defaults are those measured to denoise and even out best the noisy
 * sphere (CGAL's sphere_20k, 21000 -> 2100: radial std 0.0040, NN-spacing
 * variation 0.13, 30 iterations): the Gaussian mean with theta_k = 4 and
 * h = 5 x the initial samples' spacing, as in CGAL (the authors' tool). Huang
 * et al.'s L1 weight with theta_k = 16 (weight = DP_WLOP_L1, theta_k = 16)
 * leaves radial std 0.078 there at h_factor 5 and 0.0075 at 12: θ with
 * theta_k = 16 has an effective radius of h/4, too short to average the noise,
 * and widening h costs h² in neighbour pairs.
 */
typedef struct dp_wlop_params {
	size_t samples;        /* m; 0 = use ratio */
	double ratio;          /* m = round(ratio * |C|) when samples == 0, in (0, 1]; default 0.1 */
	double h;              /* support radius; <= 0 = h_factor * mean NN spacing of the initial samples */
	double h_factor;       /* default 5 */
	double mu;             /* repulsion weight, in [0, 0.5); default 0.45 */
	int max_iters;         /* >= 0; default 200 */
	double tol;            /* stop when the mean move of an iteration < tol * h; default 0.002
	                          (the largest move never settles on real scans: host/stages/wlop.c) */
	double stall_tol;      /* ... or when it is < stall_tol * h and fell by less than min_drop over the last
	                          window iterations (on real scans the mean decays too slowly for tol); 0.01 */
	int window;            /* >= 1; default 10 */
	double min_drop;       /* in [0, 1); default 0.1 */
	double theta_k;        /* θ(d) = exp(-theta_k d²/h²); default 4 (Huang et al.: 16) */
	dp_wlop_weight weight; /* default DP_WLOP_GAUSSIAN */
	int sqrt_density;      /* sample density sqrt(1+Σθ) instead of 1+Σθ; default 0 */
	uint64_t seed;         /* initial sample choice; default 1 */
} dp_wlop_params;

DP_API void dp_wlop_params_default(dp_wlop_params *p);

typedef struct dp_wlop_stats {
	size_t samples;          /* m */
	double h;                /* support radius used */
	int iterations;          /* iterations run */
	int converged;           /* stopped by tol or the stall test (else max_iters stopped it) */
	int stalled;             /* ... and by the stall test */
	double last_mean_move;   /* mean move of the last iteration, in units of h */
	double last_max_move;    /* largest move of the last iteration, in units of h */
	double seconds;          /* whole call */
	double seconds_setup;    /* sample choice, h, input grid */
	double seconds_density;  /* input density v (once) */
	double seconds_iterations; /* all iterations; the four below are its parts */
	double seconds_grid, seconds_sample_density, seconds_attraction, seconds_repulsion;
	double pair_evaluations; /* neighbour pairs visited in total (27-cell candidates) */
} dp_wlop_stats;

/*
 * Runs WLOP on `input` (positions only are read) and writes the m samples to
 * `samples` (positions only; the struct is overwritten, caller frees with
 * dp_cloud_free). The initial samples are m distinct input positions chosen
 * at random (seeded); the order of the output is that choice. `params` NULL
 * means defaults; `stats` may be NULL. Errors (samples left zeroed):
 * DP_ERR_EMPTY for an empty input; DP_ERR_ARG for m == 0, m > |C|, fewer than
 * m distinct input positions, non-finite coordinates, coordinates spanning
 * so large a range that squared distances overflow a float (a far outlier),
 * or parameters out of range (h^2 too overflows a float); DP_ERR_NOMEM;
 * DP_ERR_CL from the device.
 */
DP_API dp_status dp_wlop(dp_context *ctx, const dp_cloud *input, const dp_wlop_params *params,
		  dp_cloud *samples, dp_wlop_stats *stats, dp_error *err);

/* ---------------------------------------------------------------- normals */

/* Owner: normals module (host/stages/normals.c, orient.c). Reentrant, no
 * dp_context: runs on the host (FLANN kNN, 3x3 eigen-decompositions). */
typedef struct dp_normal_params {
	int k;                 /* PCA neighbourhood: the point and its k nearest others; default 16, >= 2 */
	int k_graph;           /* orientation graph: k_graph nearest others, symmetrised; default 8, >= 1 */
	int use_viewpoint;     /* orient towards `viewpoint` instead of the MST; default 0 */
	double viewpoint[3];   /* the scanner position, in input coordinates */
} dp_normal_params;

DP_API void dp_normal_params_default(dp_normal_params *p);

/*
 * Estimates a unit normal for every point of `cloud` (adding normal arrays if
 * absent, overwriting them otherwise): the smallest-variance axis of the
 * point's PCA neighbourhood. A neighbourhood that is a line or one repeated
 * point gets some unit perpendicular (never NaN). Exact duplicates are one
 * point (they get the same normal and do not crowd neighbourhoods). Inputs
 * smaller than the neighbourhoods use every other point.
 * Orientation, unless params->use_viewpoint: a minimum spanning tree over the
 * symmetric k_graph-NN graph (after Hoppe 1992, Prim; the agreement test
 * mirrors n_i in the plane bisecting the step, so a step across a thin plate
 * or a gap between facing faces expects the opposite sign),
 * propagated in each connected component from the extreme point along ±x, ±y
 * or ±z whose normal is best aligned with that direction (turned to point along
 * it); then each component is flipped as a whole when the normals of its
 * extreme points along 26 directions vote against those directions, or, when
 * the vote is close to 0, when its area-weighted flux Σ a_i n_i·(p_i -
 * centroid) is negative (3 × the volume for a closed surface with outward
 * normals). A component within 10 mean spacings of the largest one is a
 * fragment of the same surface cut off by a gap: it takes its sign from the
 * largest across the gap instead, by the propagation's agreement test over
 * the links to its nearest points there, where those links agree clearly
 * (otherwise its own vote decides). A flat open sheet is oriented
 * consistently, to one side. With use_viewpoint every normal is turned
 * towards the viewpoint instead.
 * params NULL means defaults. Errors: DP_ERR_ARG (NULL cloud, k < 2,
 * k_graph < 1, a non-finite point or viewpoint, coordinates whose squared
 * distances overflow a float), DP_ERR_EMPTY (no points),
 * DP_ERR_NOMEM; on error the normal values are unspecified.
 */
DP_API dp_status dp_estimate_normals(dp_cloud *cloud, const dp_normal_params *params, dp_error *err);

/* The WLOP sample count from which orientation is trusted on its own: the
 * default coarse level of dp_consolidate (dp_refine_params). */
#define DP_ORIENT_DENSE_SAMPLES 4000

/*
 * Signs for the normals of sparse WLOP samples from denser ones. Below a few
 * thousand samples a part a sample or two thick (the demo chair's legs and
 * back rest at 1000 samples of a 2516-point scan, a knot's tube at 320) has
 * no normal of its own: the orientation's propagation crosses it at random
 * and the outward vote reads it, and whole shapes came out inwards (the
 * chair's samples 98% flipped, the knot's 53%). When `samples` (WLOP
 * samples of `input`, with the normals of dp_estimate_normals) are fewer than
 * `dense` and than the input's distinct positions, this runs dp_wlop on
 * `input` for min(dense, distinct positions) samples with `wlop`'s other
 * parameters, estimates their normals with `normals`, and turns each sample's
 * normal to agree with those of its 8 nearest dense samples (Gaussian weights
 * in the distance over the nearest one's): the chair's 2.5-4.9%, the knot's
 * 4.4%. Otherwise, and with normals->use_viewpoint, it changes nothing.
 * *dense_run receives the dense count (0: none) and *turned the normals
 * turned (either may be NULL). wlop and normals NULL mean defaults. Errors:
 * dp_wlop's and dp_estimate_normals', DP_ERR_ARG (samples without normals),
 * DP_ERR_NOMEM. Uses ctx exclusively for its duration.
 */
DP_API dp_status dp_orient_from_denser(dp_context *ctx, const dp_cloud *input, const dp_wlop_params *wlop,
				       const dp_normal_params *normals, size_t dense, dp_cloud *samples,
				       size_t *dense_run, size_t *turned, dp_error *err);

/* ---------------------------------------------------------------- sinking */

/*
 * Sinking the consolidated points into anchors (paper 4.1; owner:
 * host/stages/sink.c). Every dpoint starts with its inner point q_i on its
 * surface point p_i; lengths are in units of r (paper Eq. 1, passed in by the
 * caller). Each iteration, for every unsettled q_i:
 *  1. settle test: q_i settles when an inner point q_i' (settled or not) within
 *     settle_radius_r has n_i·n_i' <= cos ω and its surface point is far,
 *     |p_i - p_i'| > front_factor × settle radius (an opposing front; nearby
 *     surface points would make creases settle at once);
 *  1a. meeting point (not in the paper): a point that settles on a front moves
 *     along its line -n_i, by at most meet_shift_r and never above p_i, to
 *     where its partners (the q_i' of step 1, with their p_i', n_i') place
 *     the medial axis: where the two sinking lines pass closest, or for a
 *     near-opposite normal (a thin wall, whose lines nearly coincide) the
 *     centre of the ball touching p_i and the partner's tangent plane. The
 *     test stops it up to a settle radius and a step short of the axis;
 *     where every front comes from one side (a one-view scan) the skeleton
 *     inherits that offset and the volume prior copies it into the completed
 *     region (measured on a one-view sphere at 4000 deep points: skeleton
 *     1.9 r towards the scanner, far half 0.046 R too close;
 *     host/stages/meet.h);
 *  1b. medial test (not in the paper): q_i settles when some surface point
 *     is nearer to it than p_i by more than medial_margin_r plus
 *     medial_fraction × its depth |q_i - p_i| (that part at most
 *     medial_fraction_cap_r), i.e. q_i has passed the centre of its
 *     inscribed ball. Where the far side was never scanned no
 *     opposing front exists and nothing else stops the sinking (measured
 *     before this test: one-sided scans of a lamppost and an airplane ended
 *     with every point unsettled and deep points ~100 r long). The margin
 *     grows with depth because the gap the test reads does: q_i lies off the
 *     true normal line by about depth × the direction error of n_i (and the
 *     smoothing's pull), and a witness at the ball's side, such as the same
 *     visible shell curving away, comes nearer by that much (a one-sided
 *     hemisphere 22 r in radius, test_sink: a fixed 0.25 r margin stopped its
 *     points 0.61 R from the centre on average, the growing one 0.02 R;
 *     normals tilted about 4°, 0.61 and 0.10 R). On the one-view
 *     bunny the witnesses lay a median 56° from the sinking direction with
 *     normals 52° apart, and a fixed 1 r margin stopped the body's
 *     medial-settled points at a median 14.6 r (19.1 r at 0.25 r + 0.15 ×
 *     depth). Measured over WLOP seeds 1-6 (1 r + 0 -> 0.25 r + 0.15, cap
 *     3 r): one-view bunny coverage 0.797 -> 0.831, flipped 1.90% -> 1.86%,
 *     Poisson error (seeds 1-3) 0.0153 -> 0.0118; the bench chair flipped
 *     1.70% -> 1.46% (its back rest's top rim, whose crease normals sink it
 *     through the plate, stops sooner: anchors outside the chair 58 / 49 /
 *     39 -> 40 / 34 / 22 at seeds 1-3); the two-view bunny coverage 0.950 ->
 *     0.951, flipped 0.43% -> 0.42%, but its unseen underside sinks deeper too: 95th
 *     percentile 0.0389 -> 0.0423, Poisson error 0.00354 -> 0.00386. The
 *     cap: points whose normals came out inwards sink out of the body, and
 *     in empty space their gap to the nearest sample stays put while a
 *     growing margin runs away from it (fertility_1n: 28 points 50-63 r
 *     out at the iteration cap, against 13-25 r settled with 1 r); at 3 r
 *     they settle; uncapped the one view reached 0.837 / 1.79% / 0.0114,
 *     the chair and the two views the same);
 *  1c. width bound (not in the paper): q_i settles once its depth |q_i - p_i|
 *     reaches half the smallest scale rho (4, 8, ... 64 r) at which the
 *     samples within rho of p_i spread (the square root of the middle
 *     eigenvalue of their second moments about p_i) less than
 *     rho / (2 width_factor): an inscribed ball is no wider than its part.
 *     A surface patch spreads rho/2 at every scale, a pole or a leg of
 *     radius a about 1.2a, so a point leaving a thin part stops within a
 *     few of its widths. Where a part is thinner than σp its normals are
 *     often oriented across it, or its far side was never scanned, and
 *     nothing else stops the sinking (measured on pcl/lamppost.pcd: the
 *     skeleton a median 41 r from the data, 2.3 r with the bound; a
 *     sample with fewer than about 500 others within 64 r, an outlier,
 *     stops at 32 r; host/stages/width.h);
 *  1d. thin walls (not in the paper): in step 1 a partner whose surface
 *     point is nearer than the far distance still counts when its normal is
 *     more than 135° from n_i and p_i lies at least wall_min_r behind its
 *     tangent plane: the far face of a wall thinner than the far distance
 *     (2 r at the defaults), which otherwise never meets the point, so that
 *     it sank through the wall and out of it (the medial test fires only
 *     once a point is a margin past the middle). The tangent-plane test keeps
 *     out a neighbour on the point's own face whose normal came out flipped.
 *     Measured: a wall 1.4 r thick (test_sink), anchors 0.81 r from its
 *     mid-plane with 793 of 804 outside it, with the rule 0.06 r and none;
 *     the two-view bunny's ears (mean of six WLOP seeds) flipped normals
 *     2.0% -> 1.7%, spacing variation 0.36 -> 0.34, the one-view bunny, the
 *     chair and the scans of the data folder unchanged (over seeds 1-3,
 *     0.25 r: 1.5%, 0.5 r: 1.4%, 1 r: 1.8%);
 *  2. step t_i: first_step_r × r in the first iteration, then the mean over the
 *     static neighbourhood P_i (surface points within sigma_p × r, i included)
 *     of the distance each inner point moved in the previous iteration (settled
 *     ones count 0); t_i < slow_fraction × the first step settles q_i
 *     (slow-down: how points that never meet an opposing front stop). A
 *     settled neighbour counts only if it stopped no shallower than q_i's
 *     depth minus slow_margin_r (not in the paper): where a thin part's
 *     fronts meet early, its settled points otherwise slowed the thick part
 *     next to it, whose slowed points slowed theirs, until the whole scanned
 *     side stopped just below the surface (measured on the one-view bunny:
 *     3212 of 4000 points settled by slow-down within 31 iterations, the
 *     ears' first; with a margin of 1.5 r, Poisson error 0.026 -> 0.019; at
 *     1 r, with step 1e catching the plates, mean of WLOP seeds 1-6: coverage
 *     0.763 -> 0.814, Poisson error 0.017 -> 0.014). Stalls (not in the
 *     paper): a point that ends an iteration less than a fifth of the slow-down
 *     threshold deeper than it began settles as slowed too. Its step is
 *     undone by the smoothing towards settled neighbours it has passed by
 *     more than the margin, which therefore do not slow it; measured on the
 *     demo chair, six points under the seat's front edge stood 3.5-3.9 r deep
 *     from iteration 30 to the cap of 200. The slow-down threshold itself
 *     stopped the one-view bunny's body short of its middle (coverage 0.81 ->
 *     0.74, mean of WLOP seeds 1-6);
 *  1e. plates (not in the paper): a point twice as deep as the half
 *     thickness its face's edge band shows (step 5, the band alone) has
 *     passed the far face and settles at that depth (DP_SETTLE_FLAT). Slow-
 *     down creeps into a one-sided plate's middle from its rim while the
 *     middle sinks on, and with the 1 r margin it never caught up on the demo
 *     chair's back rest (74 r deep at the iteration cap). The rim's evidence
 *     does not set this test: along a closed cylinder's side it is the depth
 *     of the crease with the end cap, and the side's points, which meet the
 *     opposite side R deep, stopped a few r in;
 *  3. q_i ← q_i - t_i n_i;
 *  4. cross-bilateral smoothing (Eq. 3): q_i ← Σ θφ q_i' / Σ θφ over P_i, with
 *     the sunk positions of settled and unsettled neighbours,
 *     θ = exp(-(|p_i - p_i'|/r)²), φ = exp(-((1 - n_i·n_i')/(1 - cos ω))²).
 * A point's "move" in step 2 is its sinking step t_i (the paper's "moving
 * distance"); the smoothing adjusts positions without counting as a move, so
 * t never exceeds the first step. Counting the smoothing's displacement makes
 * t grow every iteration on convex shapes, where the smoothing pulls inward
 * (measured on a sphere of radius 17 r: 0.5 r to 0.8 r in 22 iterations); a
 * step beyond the settle radius would let fronts cross between two tests.
 * Settled points never move again: the smoothing pulls unsettled points
 * towards them, it does not move them (the paper smooths "unsettled inner
 * points"). Stops when every point has settled or after max_iters iterations.
 *  5. flat faces (not in the paper; after the loop): a point that stopped by
 *     slow-down, by the width bound or by step 1e (no evidence of its depth)
 *     takes at most the depth of its face's rim: the median depth
 *     of the points settled by step 1 or 1b within 5 r of a point so settled
 *     and facing its way, passed on through samples within 2.5 r of each
 *     other whose normals stay within flat_angle_deg of that point's. A flat face
 *     scanned from one side gives its middle no evidence, and slow-down
 *     creeps in from the rim while the middle keeps sinking (measured on the
 *     demo chair's seat, 4.2 r thick: 4.1 r deep at the rim, 10.5 r in the
 *     middle, and its completed underside bulged; host/stages/flat.h).
 *     Where an edge band shows below the face (samples within 8 r turned a
 *     right angle away and lying below its plane, not reaching as far down
 *     as the search shows), the face is at most half as deep as that band
 *     is tall, read one r taller than its deepest sample reaches and beside
 *     every sample that stopped without evidence as well: the rim's evidence
 *     overshoots a plate's middle, and along a crease its normals are turned
 *     too far to read the band (the seat's 3.5 r and the back rest's 3.2-3.8 r
 *     for a half thickness of 2.1 r; with the band 2.1-2.2 r and 1.9 r).
 *     A sample along a rounded crease, stopped by slow-down or the width
 *     bound and reached by no face depth, takes at most the depth where its
 *     line from p_i through q_i crosses the medial planes of the faces
 *     beside it (the planes through their samples' inner points across
 *     their normals; the median over at least 3 samples within 2.5 r that
 *     stopped on evidence or on their face's depth, with normals turned from
 *     its own beyond flat_angle_deg and by at most 60 degrees, so nothing
 *     at flat_angle_deg >= 60): the demo chair's seat samples along the back
 *     rest sank 4-5 r along the crease's bisector to the seat's far face.
 */
typedef struct dp_sink_params {
	double sigma_p;          /* static neighbourhood radius σp, in r; default 5 */
	double settle_radius_r;  /* settle test radius, in r; default 1 (the paper's σq = 2 stopped a torus'
	                            anchors 2 r off its axis, 1 r brought its skeleton to 0.14 r) */
	double front_factor;     /* opposing front: surface points farther apart than this × settle radius; default 2 */
	double omega_deg;        /* ω, in degrees, in (0, 180); default 45 */
	double first_step_r;     /* t of the first iteration, in r; default 0.5 */
	double slow_fraction;    /* settle when t_i < slow_fraction × first step, in [0, 1); default 0.5 */
	int max_iters;           /* iteration cap, >= 1; default 200 */
	double medial_margin_r;  /* medial test margin's fixed part, in r; 0 = off; default 0.25 (see 1b above) */
	double meet_shift_r;     /* largest move to the meeting point, in r; 0 = off; default 2 (see 1a above) */
	double slow_margin_r;    /* settled neighbours slow q_i only if they stopped no shallower than its depth
	                            minus this, in r; >= 0, inf (or 1e9) = the paper's rule; default 1 (see 2
	                            above); report.json writes a non-finite value as null */
	double width_factor;     /* width bound, >= 0; 0 = off; default 2 (see 1c above; below 1.8 it can stop a
	                            one-sided scan of a ball short of its centre) */
	double flat_angle_deg;   /* flat faces (steps 1e and 5), degrees in [0, 90); 0 = off; default 10 */
	double wall_min_r;       /* thin walls (step 1d), in r, finite >= 0; 0 = off; default 0.5 */
	double medial_fraction;  /* the medial test's margin grows by this fraction of the depth, in [0, 1); default
	                            0.15; no effect while medial_margin_r is 0 (see 1b above) */
	double medial_fraction_cap_r; /* by at most this, in r, finite >= 0; default 3 (see 1b above) */
} dp_sink_params;

DP_API void dp_sink_params_default(dp_sink_params *p);

typedef struct dp_sink_stats {
	int iterations;          /* iterations run */
	size_t settled_front;    /* settled by the front test */
	size_t settled_medial;   /* settled by the medial test */
	size_t settled_width;    /* settled by the width bound (and left there by step 5) */
	size_t settled_slow;     /* settled by slow-down (and left there by step 5) */
	size_t settled_flat;     /* settled by step 1e, or by slow-down or the width bound and then given a flat
	                            face's or a crease's depth (step 5); settled_slow and settled_width count the
	                            rest */
	size_t unsettled;        /* still moving when max_iters stopped the loop */
	double seconds;
	double pair_evaluations; /* neighbour pairs visited by the operators */
	int converged;           /* 1: every point settled within max_iters; 0: the cap stopped the loop (where
	                            dp_consolidate keeps a subset of the anchors, the counts above are those of
	                            the anchors kept, while this describes the whole run) */
} dp_sink_stats;

/* How a sinking point stopped (the steps above). */
typedef enum dp_settle {
	DP_SETTLE_NONE = 0,   /* still moving at the iteration cap */
	DP_SETTLE_FRONT = 1,  /* met an opposing front (1) */
	DP_SETTLE_MEDIAL = 2, /* passed the medial axis (1b) */
	DP_SETTLE_WIDTH = 3,  /* as deep as its part is wide (1c) */
	DP_SETTLE_SLOW = 4,   /* slowed down with its neighbours, or stalled (2) */
	DP_SETTLE_FLAT = 5    /* past its plate's far face (1e), or slowed down or width-bound, then given its
	                         flat face's or its crease's depth (5) */
} dp_settle;

/*
 * Sinks the points of `surface` (S, with outward unit normals) and writes the
 * anchors H to `anchors`: the inner points, in the same order and count as S,
 * with S's normals copied (an inner point carries its surface point's normal).
 * Points still unsettled at the cap are written where they stopped and counted
 * in stats->unsettled. `anchors` is overwritten, not freed first, and owned by
 * the caller on success (dp_cloud_free); zeroed on error. When `settled_by`
 * is not NULL it receives a dp_settle value for each point (the caller's n
 * bytes; unspecified on error). params NULL means
 * defaults; stats may be NULL. Uses only ctx (one thread at a time per
 * context); reports progress as ("sink", iteration, settled points).
 * Errors: DP_ERR_ARG (NULL arguments, no normals, r not a positive number,
 * non-finite points or normals, parameters out of range, coordinates whose
 * squared distances overflow a float), DP_ERR_EMPTY (no points),
 * DP_ERR_NOMEM, DP_ERR_CL from the device.
 */
DP_API dp_status dp_sink(dp_context *ctx, const dp_cloud *surface, double r, const dp_sink_params *p, dp_cloud *anchors,
		  unsigned char *settled_by, dp_sink_stats *stats, dp_error *err);

/* ---------------------------------------------------------- meso-skeleton */

/*
 * Forming the meso-skeleton (paper 4.2; owner: host/stages/skeleton.c).
 * Lengths are in units of r (the mean nearest-neighbour spacing of the surface
 * samples, paper Eq. 1, passed in by the caller). Q starts as the anchors H;
 * every iteration reads the old Q and writes a new one (Jacobi), for each q_i:
 *  - PCA of the inner points within sigma_q r of q_i (q_i included) gives the
 *    unit axes v^1, v^2, v^3;
 *  - semi-axes l^m = (mean over the same points i' of |n_i' · v^m| + eps)^-1
 *    (normals are normalised first; a zero normal counts as perpendicular);
 *  - ellipsoid distance u(x) = sqrt(Σ_m ((v^m · (q_i - x)) / l^m)²) / r and
 *    weight ϑ(x) = exp(-u²), summed only where u <= cutoff;
 *  - data term: the anisotropic L1-median step over the anchors,
 *    m_i = Σ_k α_k h_k / Σ_k α_k, α_k = ϑ(h_k) / |q_i - h_k|;
 *  - repulsion over the other inner points, ρ_i = Σ β (q_i - q') / Σ β,
 *    β = ϑ(q') / u(q')⁵, projected onto the long axes (the intent of the
 *    paper's μ|ℓ|² AᵀA, which taken literally would push hardest across a curve or sheet):
 *    P_i = Σ_{m: w_m >= min_axis_weight} w_m v^m v^mᵀ, w_m = (l^m)² / Σ_m' (l^m')²;
 *  - update q_i ← q_i + C_i (m_i - q_i) + mu · P_i ρ_i. The paper takes the
 *    whole median step, C_i = I (across_only = 0). With across_only (not in
 *    the paper; the default) only its part across the structure counts:
 *    C_i = Σ_m (l_min / l^m)² v^m v^mᵀ, l_min the shortest semi-axis, so a
 *    ball contracts fully, and a curve along itself and a sheet within
 *    itself at most (1/(1+ε))² / (1/ε)², under 1% at the default ε. Along a sheet the median of an ellipsoid ten
 *    times wider than deep drew points towards denser spots and away from
 *    the rim: the skeleton of the demo chair's seat tore into holes up to
 *    6.6 r across, the surface points above took inner ends up to 10 r aside,
 *    and the completed underside hung 3-5 r too low. Measured at the
 *    defaults over six WLOP seeds, full step -> across only: chair 95th
 *    percentile accuracy 0.050 -> 0.022 diagonals, flipped 4.2% -> 3.5%,
 *    spacing variation 0.52 -> 0.37, coverage 0.954 -> 0.946; one-view bunny
 *    coverage 0.758 -> 0.775, flipped 3.6% -> 2.5%; two-view bunny flipped
 *    2.3% -> 2.0%, coverage 0.961 -> 0.952.
 *    Without anchors in reach m_i = q_i; without inner neighbours in reach
 *    ρ_i = 0 (isolated points stay put).
 * Pairs closer than 1e-5 r are skipped (q_i itself, duplicates).
 * Stops when the mean move per iteration stops falling: at iteration t > window
 * when move_t > (1 - min_drop) · move_{t-window}, or when move_t < min_move_r;
 * otherwise after max_iters (stats->converged = 0).
 */
typedef struct dp_skeleton_params {
	double sigma_q;         /* PCA neighbourhood radius, r; default 2 */
	double eps;             /* semi-axis constant ε; default 0.1 (so l <= 10) */
	double mu;              /* repulsion weight μ; default 0.4 */
	double cutoff;          /* neighbour sums stop at ellipsoid distance cutoff r; default 3 */
	double min_axis_weight; /* repulsion ignores axes whose weight w_m is below; default 0 (all axes) */
	int across_only;        /* 1: the median step only across curves and sheets (default); 0: whole (paper) */
	int max_iters;          /* iteration cap; default 100 */
	int window;             /* iterations over which the mean move must fall; default 3 */
	double min_drop;        /* required relative fall of the mean move over the window; default 0.05 */
	double min_move_r;      /* stop when the mean move is below this, r; default 1e-3 */
} dp_skeleton_params;

DP_API void dp_skeleton_params_default(dp_skeleton_params *p);

typedef struct dp_skeleton_stats {
	int iterations;
	int converged;           /* 1 when stopped by the test above, 0 at max_iters */
	double last_mean_move;   /* mean move of the last iteration, in units of r */
	double seconds;
	double pair_evaluations; /* neighbour pairs visited by the operators */
} dp_skeleton_stats;

/*
 * Consolidates the anchors H (`anchors`, with normals: the inner points carry
 * their surface point's outward normal, as dp_sink returns them) into the
 * meso-skeleton Q, written to `skeleton` (same order and count, normals
 * copied; caller frees with dp_cloud_free; must not be `anchors`). r > 0 is
 * the surface spacing. `params` NULL means defaults; `stats` may be NULL.
 * Errors: DP_ERR_EMPTY (no anchors), DP_ERR_ARG (no normals, non-finite
 * positions or normals, r or a parameter out of range), DP_ERR_NOMEM, and
 * the backend's errors. Uses ctx exclusively for its duration.
 */
DP_API dp_status dp_skeleton(dp_context *ctx, const dp_cloud *anchors, double r, const dp_skeleton_params *params,
		      dp_cloud *skeleton, dp_skeleton_stats *stats, dp_error *err);

/* -------------------------------------------------- surface consolidation */

/*
 * Surface point consolidation (paper 4.3; owner:
 * host/stages/surface.c). Lengths are in units of r (paper Eq. 1, passed in
 * by the caller); θ(d) = exp(-(d/r)²). P starts as the samples S, Q as the
 * skeleton; every pass reads the old P and writes a new one (Jacobi). For each
 * p_i with unit normal n_i, inner end q_i, dpoint length ℓ_i = |p_i - q_i| and
 * orientation m_i = (p_i - q_i)/ℓ_i, one iteration is:
 *  1. data term over the input points C_i within sigma_p r: α_ij = θ/(d/r),
 *     η_i = 1 + Σ θ, c̄_i = Σ α c / Σ α (weighted L1-median);
 *     over the surface points P_i within sigma_p r (p_i included): L_i the
 *     θ-weighted mean of ℓ, γ_i = 1/(1 + variance of ℓ/r), W_i = Σ θ;
 *     tangential repulsion R_i = Σ β̂ T_i(p_i - p') / Σ β̂, T_i = I - n_i n_iᵀ,
 *     β̂ = θ / max(|T_i(p_i - p')|/r, tangent_floor_r)⁵ (p' ≠ p_i);
 *  2. slide: p_i += mu_hat R_i;
 *  3. re-attachment (when `reattach`; the paper's "refine the connection"):
 *     h_i ← the skeleton point within reattach_radius_r r of q_i, behind p_i,
 *     nearest to the line through p_i along ñ_i (the PCA normal of step 5 of
 *     the previous iteration; n_i itself is m_i where there is no input);
 *     h_i is the skeleton point the inner end hangs on (at the start, its row
 *     of `skeleton`), and q_i = h_i unless step 3b moves it;
 * 3b. lateral smoothing (when end_smoothing_r > 0): q_i ← h_i + T_i(a_i - h_i),
 *     a_i the mean of the h of the surface points on p_i's side (as in P_i)
 *     within min(3 end_smoothing_r, sigma_p) r of the slid p_i, weights
 *     exp(-(d/end_smoothing_r r)²): the inner end moves across n_i, under p_i,
 *     where the skeleton is clumped, never along n_i (also without
 *     `reattach`, about the h_i the stage started with);
 *  4. data and prior step at the slid p_i, with m_i, ℓ_i of the slid p_i and
 *     the q_i of steps 3 and 3b (the data term acts along the normal
 *     only: as Eq. 6 is printed it pins the boundaries of missing regions, and a
 *     one-view torus scan stayed at 51% coverage instead of 98%):
 *     p_i += [η Σα D_i + g_i] / (γ + η Σα), D_i = n_i n_iᵀ(c̄_i - p_i)
 *     (data_along_normal; else c̄_i - p_i as Eq. 6 is printed),
 *     volume prior (Eq. 8):  g_i = γ (q_i + L_i m_i - p_i) = γ (L_i - ℓ_i) m_i;
 *     minimal prior (Eq. 9): g_i = γ min(0, (c_i - p_i)·m_i) m_i, c_i the
 *     θ-weighted centroid of P_i: a membrane that only shortens dpoints, so
 *     missing regions close flat (Fig. 17) instead of bulging like their
 *     neighbours (Eq. 9 taken literally contracts every point onto the
 *     skeleton; measurements in host/stages/surface.c);
 *  5. normal update: n_i = normalize((η_i - 1) ñ_i + m_i), ñ_i the PCA normal
 *     of the new surface points within normal_radius_r r, oriented like n_i.
 * (The paper adds steps 2 and 4 in one update; sliding first has the same
 * fixed points and avoids an outward drift of unsupported regions.)
 * Stops when, over the last `window` iterations against the `window` before,
 * the mean move has not fallen by min_drop, the mean nearest-neighbour
 * spacing of P (the area per point grows with its square while points spread
 * into missing regions) has not grown by min_growth, and the spacing's
 * coefficient of variation has not fallen by min_growth either (points still
 * evening out into a sparse completed region: measured on a one-view sphere
 * at 3000 deep points, stopping on the spacing alone ended at 0.83 coverage,
 * with this at 0.91). It also stops when, in each of the last `window`
 * iterations, at most one point in 1000 (none below 1000 points) moved more
 * than min_move_r or escaped: the set is at rest. A complete, clean scan has
 * nothing to fill, yet its mean move and its spacing's variation kept
 * falling by a few per cent per window for ever (the knot of the data
 * folder, 3200 points: mean move 0.0085 r at iteration 30, 0.0017 r at the
 * cap of 200, variation 0.050 -> 0.035, and a warning that the stage stopped
 * at its cap). Otherwise it stops after max_iters (stats->converged = 0).
 */
typedef enum dp_surface_prior {
	DP_SURFACE_PRIOR_VOLUME = 0,  /* volume preserving, Eq. 8 (default) */
	DP_SURFACE_PRIOR_MINIMAL = 1  /* minimal volume, Eq. 9 */
} dp_surface_prior;

typedef struct dp_surface_params {
	double sigma_p;           /* neighbourhood radius of C_i and P_i, r; default 5 */
	double mu_hat;            /* tangential repulsion μ̂, in [0, 1]; default 0.2 (the paper's 0.4 never settles: surface.c) */
	dp_surface_prior prior;   /* default DP_SURFACE_PRIOR_VOLUME */
	int data_along_normal;    /* 1: data term n nᵀ(c̄ - p) (step 4 above); 0: c̄ - p as Eq. 6 is printed; default 1 */
	double tangent_floor_r;   /* smallest tangential distance in β̂, r (> 0); default 0.01 */
	double slide_reach_r;     /* a point slides tangentially only while its nearest same-sided neighbour is
	                             within this, r (>= 0; 0: always, the paper). R_i is a normalised mean, so a
	                             point whose neighbours are all far is still pushed by their whole offset and
	                             runs off until none is within σp r: the loose halo of completed regions.
	                             Stopping such points trades completion for accuracy (surface.c has the
	                             numbers); default 0 */
	double normal_radius_r;   /* PCA neighbourhood of ñ, r; default 3 */
	int reattach;             /* re-attach inner ends; default 1 */
	double reattach_radius_r; /* re-attachment search radius around q_i, r; default 2 */
	int max_iters;            /* iteration cap, >= 0; default 200 */
	int same_side;            /* 1: every neighbour sum counts only the point's own side: input in front of
	                             its inner end ((c - q)·m > 0), surface points with normals within 90°, so
	                             parts thinner than σp r stay two-sided; 0: the paper's plain balls; default 1 */
	int orient_by_dpoint;     /* 1: the PCA normal of a point no input holds (input support Σθ < 1: no input
	                             point within about 1 r) takes the sign of the dpoint orientation
	                             m = (p - q)/|p - q|, outward by construction; a held point's takes the sign of
	                             its old normal, the data's orientation (or the scanner's: face_scanner), which
	                             is right where an inner end sank out of a thin part (measured over six WLOP
	                             seeds: two-view bunny 1.5% -> 1.0% flipped, one-view 2.55% -> 2.42%, the chair
	                             the same); 0: the old normal's sign everywhere; default 1 */
	int window;               /* iterations per compared block, >= 1; default 10 */
	double min_drop;          /* relative fall of the mean move that keeps it going, in [0, 1); default 0.05 */
	double min_growth;        /* relative growth of the spacing, or fall of its variation, that keeps it
	                             going, >= 0; default 0.005 */
	double escape_margin_r;   /* inside test with `balls` (dp_surface): a point with input support Σθ < 1
	                             deeper than this, in r, in a ball whose centre it faces moves out to the
	                             ball's sphere; 0 = off; default 1 */
	double end_smoothing_r;   /* step 3b above: width σ, in r, of the weights exp(-(d/σ r)²) over P_i with
	                             which the skeleton points of the neighbours' inner ends are averaged; 0 = off
	                             (q_i is the skeleton point itself); default 2 (surface.c has the numbers) */
	double min_move_r;        /* at rest when in each of the last `window` iterations at most one point in
	                             1000 moved more than this, in r, >= 0; 0 = off; default 0.1 */
	int sheet_points;         /* 1: after the iterations, a point with input support Σθ < 1 that lies in a
	                             skeletal sheet, its deep point along the sheet, moves across it to the
	                             depth of the deep points near it that leave the sheet (a point stranded
	                             in a plate's middle; host/stages/sheet_points.h; dp_consolidate does it
	                             after the last level only); default 1 */
	int silhouette;           /* 1: hold every point inside the scan's outline seen along its view axis, grown
	                             by silhouette_margin_r: a scanner looking along an axis records all of the
	                             object that faces it, so nothing completion adds lies outside what the scan
	                             covers seen that way (host/stages/silhouette.h); moves are across the axis
	                             only. No axis, no outline. Default 1 */
	double silhouette_axis[3]; /* the view axis (any finite length > 0; opposite views share it); all zero
	                             (default): the direction to which the fewest of the samples' normals lie
	                             within 10° of perpendicular (a scanner sees grazing surfaces worst), taken when
	                             that is at most silhouette_grazing of at least 1000 samples and every other
	                             direction that passes lies within 45° of it (a box-like object passes many
	                             unrelated ones); else none */
	double silhouette_grazing; /* in [0, 1]; default 0.065 (normals spread over every direction: about 0.17) */
	double silhouette_margin_r; /* growth of the outline, r, >= 0 (room for what a scanner misses at grazing
	                             angles, and all the room completion has to bulge past the scan's edge);
	                             default 2.5; where the scan's edge faces the scanner, the smaller
	                             silhouette_edge_margin_r */
	int face_scanner;         /* 1: where the scan was taken from one side of the view axis (given or found
	                             as for silhouette, whether or not that is on): of the samples' normals that
	                             point within acos(face_scanner_cos) of the axis either way, no more than one
	                             in a hundred point the other way, or a quarter where the samples form one
	                             layer along the axis, as a single range image does. A range scanner records
	                             only what faces it, so the PCA normal of a point input holds takes the sign
	                             that faces the scanner wherever it points that clearly along the axis
	                             (host/stages/scanner.h); dp_consolidate turns the WLOP samples' normals the
	                             same way before sinking. Default 1 */
	double face_scanner_cos;  /* in [0, 1); default 0.5: views up to 30° off the axis leave every true normal
	                             alone */
	int scanner_side;         /* +1 or -1: the scan was taken from that side of silhouette_axis, which must
	                             then be given, whatever the normals say; 0 (default): read it off the samples'
	                             normals (dp_consolidate reads it off the WLOP samples once and passes it on to
	                             the levels, whose samples are the completed surface) */
	int use_viewpoint;        /* 1: the scan was taken from `viewpoint`, a perspective scanner's eye: with
	                             face_scanner a held point's PCA normal faces that point instead (where it
	                             points within acos(face_scanner_cos) of straight towards or away from it), with
	                             or without an axis, and dp_consolidate turns the WLOP samples so (none when the
	                             normals stage oriented them towards the same point). Not with scanner_side.
	                             dp_consolidate takes dp_normal_params' viewpoint when this is 0, no side is
	                             given and that has one. Default 0 */
	double viewpoint[3];      /* the scanner's eye, in input coordinates */
	double silhouette_edge_margin_r; /* growth of the outline, r, >= 0, from the scan's cells that hold no
	                             sample whose normal lies more than 50° from the view axis: a surface that
	                             faces the scanner up to the scan's edge ends there in a sharp edge (a flat
	                             base, a plate's rim), where the scanner missed nothing, while a surface
	                             that turns away from it is lost before its outline and the whole
	                             silhouette_margin_r is its room (host/stages/silhouette.h). The smaller of
	                             the two is used; equal to silhouette_margin_r: one margin everywhere.
	                             Default 1 */
} dp_surface_params;

DP_API void dp_surface_params_default(dp_surface_params *p);

typedef struct dp_surface_stats {
	int iterations;
	int converged;           /* 1 when stopped by the test above, 0 at max_iters */
	double last_mean_move;   /* mean move of the last iteration, in units of r */
	double spacing_growth;   /* mean nearest-neighbour distance of P when the last iteration began, over the
	                            initial one */
	size_t reattached;       /* inner ends moved to another skeleton point, over all iterations */
	size_t normals_disagreeing; /* last iteration: PCA normals that the old normal would have signed against
	                               the dpoint orientation m, held points included (orient_by_dpoint signs
	                               the others by m) */
	size_t escaped;          /* points moved out of a ball by the inside test, over all iterations */
	size_t sheet_points;     /* points moved across a skeletal sheet (sheet_points) */
	double silhouette_axis[3]; /* the axis of the outline the points were held in; all zero: none */
	double silhouette_grazing; /* the fraction of normals near perpendicular to the best axis tried; -1 when
	                              the axis was given, 1 with fewer than 1000 samples, 0 when neither the
	                              outline nor face_scanner looked for one */
	size_t silhouette_held;  /* points held back at the outline, over all iterations */
	double scanner[3];       /* unit direction towards the scanner the held points' normals faced
	                            (face_scanner); all zero: none, or each faced the eye (scanner_at_eye) */
	int scanner_at_eye;      /* 1: the held points' normals faced the scanner's eye (use_viewpoint) */
	size_t scanner_turned;   /* held points whose PCA normal took the scanner's sign against the one it
	                            would have had, over all iterations */
	double seconds;
	double pair_evaluations; /* neighbour pairs visited by the operators */
} dp_surface_stats;

/*
 * Balls known to lie inside the body, for the surface stage's inside test:
 * ball j has centre (x[j], y[j], z[j]) and radius[j] (<= 0: no ball) and
 * belongs to row j of the samples (n at most their count); a ball should
 * hold no input point. dp_consolidate passes the sinking balls settled on
 * evidence (DP_SETTLE_FRONT, DP_SETTLE_MEDIAL): centre the anchor, radius
 * its depth below its sample, cut to its distance from the nearest input
 * point (an anchor stopped a little off the medial axis reaches out of the
 * body on its far side, and a point moved to its sphere would land beyond
 * the data).
 * A surface point with no input to hold it turns about its inner end and,
 * past the end of its part of the skeleton, drifts through the body
 * (measured on the two-view bunny at 4000 deep points: 181 points more than
 * 0.01 diagonals inside, 80 of them with flipped normals; 78 and 11 with the
 * test, and 153 flipped normals in all down to 81). One deeper
 * than escape_margin_r in a ball, with its normal towards the ball's centre,
 * moves out to the ball's sphere along the ray from the centre and takes the
 * current inner end of row j. Arrays are borrowed for the call and read
 * only at its start (they may alias `skeleton`'s).
 */
typedef struct dp_balls {
	size_t n;
	const float *x, *y, *z;
	const float *radius;
} dp_balls;

/*
 * Consolidates the surface points: `input` = C (raw points, positions only),
 * `samples` = S with outward unit normals (the initial P), `skeleton` = Q, the
 * inner ends (same count as S), `balls` NULL or the inside test's balls
 * (above). Writes P with its normals to `surface`
 * (overwritten, not freed first; caller frees with dp_cloud_free; zeroed on
 * error) and, when `eta` is not NULL, η of every final p_i (input support; 1
 * where no input is in reach) into the caller's n floats. On success the
 * positions of `skeleton` are updated in place to the skeleton points h_i
 * the inner ends hang on (moved by re-attachment, and by the inside test
 * with `balls`; the stage's own inner end lies across n_i from there, step
 * 3b) and its
 * normals, when present, receive the
 * final surface normals (an inner point carries its surface point's normal);
 * on error `skeleton` is left as it was. r > 0 is the surface
 * spacing. `params` NULL means defaults; `stats` may be NULL. With an
 * outline (params->silhouette and a view axis), the samples' normals say
 * where the scan's edge faces the scanner (silhouette_edge_margin_r).
 * Reports progress as ("surface", iteration, mean move in r). Uses ctx exclusively
 * for its duration.
 * Errors: DP_ERR_ARG (NULL arguments, samples without normals or with a zero
 * normal, a skeleton of another size, `surface` aliasing an input, non-finite
 * points or normals, more balls than samples or a non-finite ball, r
 * or a parameter out of range), DP_ERR_EMPTY (no samples or no input points),
 * DP_ERR_NOMEM, and the backend's errors.
 */
DP_API dp_status dp_surface(dp_context *ctx, const dp_cloud *input, const dp_cloud *samples, dp_cloud *skeleton,
		     const dp_balls *balls, double r, const dp_surface_params *params, dp_cloud *surface,
		     float *eta, dp_surface_stats *stats, dp_error *err);

/* --------------------------------------------------------------- pipeline */

/*
 * Coarse-to-fine deep points. Completion spreads points into missing regions
 * by tangential repulsion, which works like diffusion: a hole D r across
 * needs on the order of D² iterations, so at a fixed iteration budget the
 * completed fraction fell as the count grew (one-view sphere: 0.91 of the
 * surface covered at 3000 deep points, 0.72 at 6000). dp_consolidate therefore
 * runs WLOP, sinking, the meso-skeleton and the surface stage on
 * coarse_samples deep points, where holes are few r across, then grows the
 * set level by level, by level_factor per level, to the requested count: each
 * level inserts surface points at midpoints of tangent-plane edges between
 * same-sided neighbours, every edge spanning a gap and an even random choice
 * of the others (the normal interpolated from the two ends, the inner end
 * that of the end nearer the new point's normal line),
 * and relaxes the whole set for level_iters surface iterations at the level's
 * own spacing r. Work grows about linearly with the count and the count may
 * exceed the input's (upsampling, paper Fig. 15). The coarse level holds at
 * most the input's distinct positions. A scan taken from one side with no
 * thin part may run a coarser coarse level (coarse_min), whose far side then
 * fills sooner; one whose coarse level stays above fill_samples (a thin part
 * keeps it at coarse_samples) starts its surface stage on a subset of that
 * level's deep points instead (fill_samples). A count below the coarse level
 * runs at the coarse level all the same and keeps a farthest-point subset of
 * the deep points (the same rows of every array of dp_result, the samples'
 * and anchors' among their own rows; ran_with says so): run at 1000, the demo
 * chair's WLOP normals pointed 98% inwards and its surface lay 0.034
 * diagonals off on average, kept from 4000 0.0048 (README).
 *
 * The data term holds the points on the scanned part while only repulsion
 * feeds the completed part, so the completed part ends up sparser: on the
 * one-view bunny (WLOP seed 1, fill_samples 0) the points without input
 * support (η <= 2) are 27% of them and cover about half of the surface, and
 * the spacing varies by 0.50 over the set (0.31 from the fill level).
 * even_rounds moves points across that step directly (dp_refine_even)
 * instead of waiting for repulsion to carry them, which takes on the order
 * of D² iterations over D r. Measured before fill_samples, three rounds of
 * three iterations, means of WLOP seeds 1-6 (coverage / flipped / spacing
 * variation / 95th-percentile accuracy; off first):
 * one-view bunny 0.845 / 0.94% / 0.50 / 0.034 -> 0.924 / 2.06% / 0.27 /
 * 0.072, two views 0.967 / 0.48% / 0.22 / 0.017 -> 0.974 / 0.58% / 0.21 /
 * 0.021, the demo chair 0.971 / 0.91% / 0.23 / 0.0119 -> 0.977 / 0.95% /
 * 0.17 / 0.0157 (README (38) has one and two rounds, (40) why these moved).
 * The completed part gets its share of the points, and with them the flips
 * and the distance of a shape the method guesses (the ears' back, the
 * base); the sparsest places, which take the points first, are often the
 * worst guessed (the one-view bunny's points without input support, seed
 * 1: 1075 -> 2146 of them, 1.6% -> 2.5% flipped, 0.021 -> 0.028 diagonals
 * off on average). Hence off by default; for an even sampling to mesh from
 * it helps (screened Poisson error of the one-view bunny 0.0103 -> 0.0086
 * diagonals, lower at all six seeds; two views 0.0026 -> 0.0025).
 */
#define DP_MAX_LEVELS 12

typedef struct dp_refine_params {
	size_t coarse_samples;    /* deep points of the coarse level; 0 = no refinement (everything at the
	                             requested count); default 4000: a coarser level loses parts thinner than its
	                             spacing (the demo chair at 1500: 0.065 diagonals off its surface, at 4000
	                             0.010) */
	size_t coarse_min;        /* a scan taken from one side (scanner.h, read off the coarse_samples level's
	                             normals) may have a coarser coarse level, down to this, doubling up to
	                             coarse_samples: the first whose WLOP samples show no part thinner than 16 r
	                             (no sample's width bound, sinking's step 1c, within 16 r). Fewer points
	                             across its far side fill it sooner. A side given (surface.scanner_side)
	                             counts as one-sided. The WLOP runs it tries count in seconds_total only
	                             (wlop_stats are the chosen level's). 0 = always coarse_samples, else at
	                             least 32; default 1000
	                             (one-view sphere at 2000 / 8000 / 32000 deep points covered 0.959 / 0.997 /
	                             0.984 from 4000, 1.000 each from 2000; README (42)) */
	double level_factor;      /* count growth per level, > 1 (midpoint insertion adds up to about 3 points
	                             per point); default 4 */
	int level_iters;          /* surface iterations relaxing each refined level, >= 1; default 15 */
	size_t samples_floor;     /* with wlop.samples 0 the count is max(ratio |C|, samples_floor), at most the
	                             input's distinct positions: 10% alone gave 75 deep points on a 750-point
	                             scan, too few to mean anything; default 4000 */
	int even_rounds;          /* even-spacing rounds after the last level, >= 0: each moves up to a tenth of
	                             the points from where the surface is densest to its longest gaps, then
	                             relaxes even_iters iterations (dp_consolidate's comment above has what it
	                             trades); default 0 */
	int even_iters;           /* surface iterations relaxing each even-spacing round, >= 1; default 3 */
	size_t fill_samples;      /* a scan taken from one side (as for coarse_min) whose coarse level holds more
	                             deep points than this (at the defaults: a thin part kept it at
	                             coarse_samples) runs WLOP, sinking and the meso-skeleton there, then the
	                             surface stage's first level on a farthest-point subset of this many of
	                             them, from which the levels grow as above: thin parts need the coarse
	                             level's spacing to sink right, while the far side fills in fewer spacings
	                             from the subset. 0 = off, else at least 32; default 2000 (one-view bunny,
	                             WLOP seeds 1-6: README (45)) */
} dp_refine_params;

DP_API void dp_refine_params_default(dp_refine_params *p);

/* One level of the coarse-to-fine surface: its size and what relaxing it cost. */
typedef struct dp_level_stats {
	size_t points;
	double r;                 /* the r the level ran at (Eq. 1: the coarse level's WLOP samples, a refined
	                             level's points just after insertion) */
	int iterations;
	double seconds;
	double pair_evaluations;
} dp_level_stats;

/* Every parameter of the whole pipeline. Defaults are the paper's where it works as printed, else
 * the measured choice documented beside each field. */
typedef struct dp_params {
	dp_wlop_params wlop;
	dp_normal_params normals;
	dp_sink_params sink;
	dp_skeleton_params skeleton;
	dp_surface_params surface;
	dp_refine_params refine;
} dp_params;

DP_API void dp_params_default(dp_params *p);

/*
 * Everything dp_consolidate makes. surface, skeleton, eta and length have
 * the deep-point count n in the same order: deep point i joins surface point
 * i and skeleton point i. wlop and anchors belong to the coarse level (its
 * n0 <= n points, or as many of them as were kept for a count below
 * it or as the surface stage started on: filled_from; n0 = n without
 * refinement): rows 0..n0-1 of the other
 * arrays are the deep points grown from them, the rest were inserted by the
 * refined levels, except that an even-spacing round (dp_refine_params) puts
 * each point it moves into the row of the point it removed (even_moved rows
 * at most). Owned by the caller; release with dp_result_free.
 */
typedef struct dp_result {
	dp_cloud wlop;      /* S: WLOP samples with oriented normals (coarse level) */
	dp_cloud anchors;   /* H: settled inner points after sinking (with S's normals) */
	unsigned char *settled_by; /* anchors.n: how each anchor stopped (dp_settle) */
	dp_cloud skeleton;  /* Q: the meso-skeleton, inner ends of the deep points */
	dp_cloud surface;   /* P: consolidated, completed surface with normals */
	float *eta;         /* n: input support η of each surface point (1 = no input near) */
	float *length;      /* n: dpoint length |p_i - q_i| */
	double r;           /* the spacing r the last level ran at (paper Eq. 1): the WLOP samples' with one
	                       level, else the level's points' just after insertion */
	size_t points_in;
	int levels;         /* surface levels run: 1 = no refinement */
	dp_level_stats level[DP_MAX_LEVELS]; /* level 0 is the coarse one */
	dp_wlop_stats wlop_stats;
	dp_sink_stats sink_stats;
	dp_skeleton_stats skeleton_stats;
	dp_surface_stats surface_stats;
	double seconds_normals, seconds_total;
	dp_params params;   /* the parameters it ran with (report.json lists them) */
	dp_backend_kind backend;
	char device[DP_DEVICE_NAME_MAX]; /* dp_context_device_name of the context it ran on */
	size_t even_moved;  /* points the even-spacing rounds moved (dp_refine_params.even_rounds) */
	size_t silhouette_capped; /* anchors sunk out of the scan's outline seen along its view axis, moved back
	                             along their lines into it (dp_surface_params.silhouette): the meso-skeleton
	                             lies inside the object */
	size_t samples_turned;    /* WLOP samples' normals turned to face the scanner before sinking
	                             (dp_surface_params.face_scanner) */
	size_t ran_with;          /* deep points the stages ran with: the count asked for, or the coarse level's
	                             when fewer were asked for (dp_refine_params.coarse_samples at most the
	                             distinct input positions, or coarse_min's choice: level[0].points, or
	                             filled_from where the surface started on a subset), of which the
	                             result keeps an even subset; r,
	                             level[], the stages' stats, even_moved, silhouette_capped and
	                             samples_turned then describe that run, the settle counts of sink_stats the
	                             anchors kept */
	size_t filled_from;       /* the coarse level's count when the surface stage's first level ran on a subset
	                             of it (dp_refine_params.fill_samples; level[0].points of them, at
	                             level[0].r, the subset's spacing): WLOP, sinking and the skeleton ran at
	                             this count (wlop_stats, skeleton_stats, sink_stats but its settle counts,
	                             silhouette_capped and samples_turned describe that run), while wlop,
	                             anchors, settled_by and the settle counts hold the subset (those of its
	                             rows kept, for a count below the coarse level), from whose samples every
	                             level takes the scan's outline; 0: no subset */
	double sink_r;            /* the spacing r sinking and the meso-skeleton ran at: the coarse level's WLOP
	                             samples' (level[0].r but where filled_from) */
} dp_result;

/*
 * The whole pipeline on a raw cloud: WLOP -> normals -> sinking ->
 * meso-skeleton -> surface consolidation. `input` positions only are read.
 * `params` NULL means the defaults. On success `result` is filled (caller
 * frees with dp_result_free); on error it is zeroed and err names the stage.
 * Errors: DP_ERR_ARG for NULL arguments and for an input that spans no
 * volume (fewer than 4 points, or all on a line or in a plane), then each
 * stage's errors (see dp_wlop, dp_estimate_normals, dp_sink, dp_skeleton,
 * dp_surface), DP_ERR_EMPTY when the samples have no spacing r, and
 * DP_ERR_ARG when a stage put a point outside the input's bounding box grown
 * by its diagonal on every side (an input too degenerate to consolidate). Uses ctx exclusively for
 * its duration.
 */
DP_API dp_status dp_consolidate(dp_context *ctx, const dp_cloud *input, const dp_params *params, dp_result *result,
			 dp_error *err);
/* Frees every array of the result and zeroes it; NULL is fine. */
DP_API void dp_result_free(dp_result *result);

/* What dp_result_write writes besides the three PLY files and report.json;
 * or'ed into dp_write_options.flags. */
typedef enum dp_write_flags {
	DP_WRITE_ASCII = 1 << 0,  /* ascii PLY instead of binary little endian */
	DP_WRITE_STAGES = 1 << 1, /* wlop.ply and anchors.ply: the coarse level's samples and anchors,
				     these with a float `settled`, how each stopped sinking (dp_settle) */
	DP_WRITE_RENDER = 1 << 2  /* input.png (needs options->input), skeleton.png, surface.png, dpoints.png */
} dp_write_flags;

typedef struct dp_write_options {
	unsigned flags;          /* dp_write_flags; default 0 */
	int up_axis;             /* vertical axis of the pictures: 0 x, 1 y, 2 z; default 1 */
	const dp_cloud *input;   /* the cloud that was consolidated, for input.png; may be NULL */
	const char *input_name;  /* "input" in report.json (a file name); NULL: "" */
	const char *output_name; /* "output" in report.json; NULL: `dir`. A caller writing into a staging
	                            folder it renames afterwards names the final folder here */
} dp_write_options;

/* flags 0, up_axis 1, no input, no names. */
DP_API void dp_write_options_default(dp_write_options *options);

/*
 * Writes a result into the folder `dir`, which must exist, as `dpoints
 * consolidate` does: surface.ply (x y z nx ny nz length eta), skeleton.ply (x y
 * z, the inner ends in the same order), dpoints.ply (surface ends as vertices
 * 0..n-1, inner ends n..2n-1, one `edge` per deep point), report.json (every
 * parameter, per-stage iterations, counts, seconds and the files written), and
 * what options->flags asks for. Every file is written to a temporary name and
 * renamed, so none is ever partial; a failure may leave the files written
 * before it. Files of the same names are replaced; nothing else in `dir` is
 * touched. `options` NULL means the defaults. Only reads `result` and the
 * options, which stay the caller's. Errors: DP_ERR_ARG (NULL result or dir, a
 * result without deep points, up_axis out of range), DP_ERR_IO naming the file
 * that could not be written, DP_ERR_NOMEM. Reentrant.
 */
DP_API dp_status dp_result_write(const dp_result *result, const char *dir, const dp_write_options *options,
				 dp_error *err);

/* The report.json that dp_result_write would write, as a NUL-terminated
 * malloc'ed string in *json that the caller frees with free(); its "files"
 * list is empty, as nothing was written. `options` NULL means the defaults
 * (only the names are used). Errors: DP_ERR_ARG (NULL result or json, no deep
 * points), DP_ERR_NOMEM; *json is NULL on error. Reentrant. */
DP_API dp_status dp_result_report(const dp_result *result, const dp_write_options *options, char **json,
				  dp_error *err);

#ifdef __cplusplus
}
#endif
#endif
