/* Shared helpers for the cmocka tests. */
#ifndef DP_TESTKIT_H
#define DP_TESTKIT_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "dpoints_tools.h"
#include "core/common.h"

/* The OpenCL context shared by one test program (built once: program builds
 * cost seconds). Fails the test when no device is found: PoCL is a required
 * dependency, the suite must not pass without having compared kernels. */
dp_context *tk_cl_context(void);
/* A reference-backend context, also shared. */
dp_context *tk_ref_context(void);
/* Frees both; call from a group teardown. */
int tk_teardown_contexts(void **state);

/* Random points for kernel-vs-reference checks, n = n_uniform + extras, in a
 * box of side `extent`; the extras cover the awkward cases: exact duplicates,
 * an isolated far point, points exactly on cell borders of a grid with cell
 * `cell` anchored at 0, and a tight cluster. Allocates *x, *y, *z (free()). */
size_t tk_random_points(dp_rng *rng, size_t n_uniform, float extent, float cell, float **x, float **y, float **z);

/* Asserts |a-b| <= atol + rtol*|b| element-wise and prints the worst index. */
void tk_assert_close(const float *a, const float *b, size_t n, float rtol, float atol, const char *what);

/* Asserts that a result's surface and skeleton have n rows each and that
 * every row's length is |p - q|. */
void tk_assert_rows_in_step(const dp_result *res, size_t n);

/* Path of a file in the shared data folder, or NULL (and a printed message)
 * when the folder is absent: callers then skip(). Static buffer. */
const char *tk_data_path(const char *relative);

/* What main returns after cmocka_run_group_tests: the failure count, or
 * TK_EXIT_SKIPPED when nothing failed but tk_data_path found data missing, so
 * ctest (SKIP_RETURN_CODE) lists the program as skipped rather than passed. */
#define TK_EXIT_SKIPPED 77
int tk_exit_status(int failed);

/* The built-in shape `name` (into *shape when not NULL), its mesh (into
 * *mesh when not NULL) and a virtual scan of it without normals, on a ring
 * of `views` viewpoints, res x res rays, Gaussian noise in diagonals. Fails
 * the test on error. */
void tk_scan_shape(const char *name, int views, int res, double noise, uint64_t seed, dp_shape *shape,
		   dp_cloud *mesh, dp_cloud *scan);

/* A fresh temporary folder (mkdtemp); static buffer. */
const char *tk_temp_dir(void);

/* n unit normals spread evenly over the directions within `cap_deg` of
 * `axis` (a Fibonacci spiral; 180: the whole sphere). */
void tk_normals_in_cap(size_t n, const double axis[3], double cap_deg, float *nx, float *ny, float *nz);

#endif
