/* The OpenCL runtime: device choice, one context/queue/program per process,
 * kernel lookup and a generic launch that uploads inputs, runs one work-item
 * per point and reads the outputs back. */
#ifndef DP_CL_RUNTIME_H
#define DP_CL_RUNTIME_H

#include "dpoints.h"
#include "grid/grid.h"

#include <CL/cl.h>

/* Fixed work-group size; the global size is padded up to a multiple of it and
 * every kernel takes the real item count as its first argument (DESIGN §3). */
#define DP_CL_LOCAL_SIZE 64
/* Options every program is built with: PoCL vectorises exp() across
 * work-items only with unsafe math, and -cl-fast-relaxed-math would also
 * assume no NaN/Inf (DESIGN §3). */
#define DP_CL_BUILD_OPTIONS "-cl-std=CL1.2 -cl-unsafe-math-optimizations"
#define DP_CL_MAX_KERNELS 64

typedef struct dp_cl {
	cl_platform_id platform;
	cl_device_id device;
	cl_context context;
	cl_command_queue queue;
	cl_program program;
	char name[512];
	size_t nkernels;
	struct {
		char name[64];
		cl_kernel kernel;
	} kernels[DP_CL_MAX_KERNELS];
} dp_cl;

/* Kernel sources (every file of kernels/), embedded at build time. */
extern const char dp_kernel_source[];

/* Name of an OpenCL error code ("CL_OUT_OF_RESOURCES"). */
const char *dp_cl_error_name(cl_int code);

/* Opens the device chosen by `spec` (see dp_context_create) and builds the
 * program; prints nothing, the build log goes into err on failure. */
dp_status dp_cl_open(dp_cl *cl, const char *spec, dp_error *err);
/* Same, with a caller-chosen program source and options (tests use it to
 * check build failures). */
dp_status dp_cl_open_source(dp_cl *cl, const char *spec, const char *source, const char *options,
			    dp_error *err);
void dp_cl_close(dp_cl *cl);

/* The kernel of that name, created once and cached. */
dp_status dp_cl_kernel(dp_cl *cl, const char *name, cl_kernel *kernel, dp_error *err);

typedef enum dp_cl_arg_kind {
	DP_CL_ARG_IN,    /* host array copied to a read-only buffer */
	DP_CL_ARG_OUT,   /* write-only buffer read back into the host array */
	DP_CL_ARG_VALUE  /* a scalar or vector passed by value */
} dp_cl_arg_kind;

typedef struct dp_cl_arg {
	dp_cl_arg_kind kind;
	const void *ptr;
	size_t bytes;
} dp_cl_arg;

#define DP_CL_IN(p, nbytes) ((dp_cl_arg){DP_CL_ARG_IN, (p), (nbytes)})
#define DP_CL_OUT(p, nbytes) ((dp_cl_arg){DP_CL_ARG_OUT, (p), (nbytes)})
#define DP_CL_VALUE(v) ((dp_cl_arg){DP_CL_ARG_VALUE, &(v), sizeof(v)})

/* Runs kernel `name` over n work-items (global size padded to
 * DP_CL_LOCAL_SIZE). Argument 0 is the cl_uint n; args follow from 1. Output
 * buffers are read back before returning. n == 0 does nothing. */
dp_status dp_cl_launch(dp_cl *cl, const char *name, size_t n, const dp_cl_arg *args, size_t nargs,
		       dp_error *err);

/* The 7 kernel arguments of GRID_ARGS (kernels/grid.cl) for grid g. The values
 * live in `storage`, which must outlive the launch. */
#define DP_CL_GRID_NARGS 7
typedef struct dp_cl_grid_storage {
	cl_float4 origin_cell;
	cl_int4 dim;
} dp_cl_grid_storage;
void dp_cl_grid_args(const dp_grid *g, dp_cl_grid_storage *storage, dp_cl_arg out[DP_CL_GRID_NARGS]);

#endif
