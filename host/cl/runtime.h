/* The OpenCL runtime: device choice, one context/queue/program per process,
 * kernel lookup and a generic launch that uploads inputs, runs one work-item
 * per point and reads the outputs back. */
#ifndef DP_CL_RUNTIME_H
#define DP_CL_RUNTIME_H

#include "dpoints.h"
#include "grid/grid.h"

#include <CL/cl.h>

/* Work-group size by device type; the global size is padded up to a multiple
 * of it and every kernel takes the real item count as its first argument
 * (DESIGN §3). A CPU runs a work-group as one loop (64 measured best on PoCL);
 * a GPU wants several warps per group to hide memory latency, 64-256 being the
 * usual best, and no more than the kernel allows (CL_KERNEL_WORK_GROUP_SIZE).
 * $DP_CL_LOCAL_SIZE overrides the choice; $DP_CL_DEVICE_TYPE (cpu or gpu)
 * makes every choice by device type (lanes too) as for that type, so that the
 * GPU choices run on PoCL in the tests. */
#define DP_CL_LOCAL_SIZE_CPU 64
#define DP_CL_LOCAL_SIZE_GPU 128
#define DP_CL_LOCAL_SIZE_MAX 1024
/* Options every program is built with: PoCL vectorises exp() across
 * work-items only with unsafe math, and -cl-fast-relaxed-math would also
 * assume no NaN/Inf (DESIGN §3); -cl-kernel-arg-info keeps the argument names
 * and types for dp_cl_check_signature. */
#define DP_CL_BUILD_OPTIONS "-cl-std=CL1.2 -cl-unsafe-math-optimizations -cl-kernel-arg-info"
#define DP_CL_MAX_KERNELS 64
/* Device buffers kept across launches (dp_cl_launch): at most this many, and
 * beyond this many bytes the least recently used ones not needed by the launch
 * at hand are released. */
#define DP_CL_CACHE_SLOTS 64
#define DP_CL_CACHE_BYTES ((size_t)1 << 30)
/* Candidates per work-item step: the kernels' DP_LANES (kernels/grid.cl).
 * PoCL vectorises explicit lanes; a GPU runs one candidate per work-item
 * step (its work-items are its lanes). $DP_CL_LANES overrides the choice by
 * CL_DEVICE_TYPE, so that both forms can be tested on one device. */
#define DP_CL_LANES_CPU 16
#define DP_CL_LANES_GPU 1

/* One kernel's launches, for benchmarks: wall seconds of dp_cl_launch (upload,
 * run, read-back), bytes moved each way, bytes not uploaded because the device
 * already held them, and the neighbour pairs its dispatcher counted. */
typedef struct dp_cl_kernel_stats {
	double launches, seconds, h2d_bytes, d2h_bytes, h2d_skipped_bytes, pairs;
} dp_cl_kernel_stats;

/* A device buffer that mirrors the host array [host, host + bytes): `shadow`
 * holds what the device holds, so a launch uploads the array only when its
 * contents differ (compared byte for byte: no caller has to say when its data
 * changed, and a freed array whose address is reused cannot be mistaken for
 * the old one). */
typedef struct dp_cl_cached {
	const void *host;
	size_t bytes;
	cl_mem mem;
	void *shadow;
	unsigned long long used; /* launch counter at the last use */
} dp_cl_cached;

typedef struct dp_cl {
	cl_platform_id platform;
	cl_device_id device;
	cl_context context;
	cl_command_queue queue;
	cl_program program;
	char name[512];
	int lanes;                /* DP_LANES the program was built with */
	size_t local_size;        /* work-group size asked for, before each kernel's limit */
	size_t nkernels;
	struct {
		char name[64];
		cl_kernel kernel;
		size_t local; /* local_size within CL_KERNEL_WORK_GROUP_SIZE */
		dp_cl_kernel_stats stats;
	} kernels[DP_CL_MAX_KERNELS];
	dp_cl_cached cache[DP_CL_CACHE_SLOTS];
	size_t cache_bytes;
	unsigned long long launches;
	/* Totals over every launch; pairs are read from *pair_counter (the
	 * context's count, which each dispatcher raises just before its launch). */
	double h2d_bytes, d2h_bytes, h2d_skipped_bytes;
	const double *pair_counter;
	double pairs_seen;
} dp_cl;

/* Kernel sources (every file of kernels/), embedded at build time. */
extern const char dp_kernel_source[];

/* Name of an OpenCL error code ("CL_OUT_OF_RESOURCES"). */
const char *dp_cl_error_name(cl_int code);

/* Opens the device chosen by `spec` (see dp_context_create) and builds the
 * program with DP_LANES by device type or $DP_CL_LANES (1, 4, 8 or 16);
 * prints nothing, the build log goes into err on failure. */
dp_status dp_cl_open(dp_cl *cl, const char *spec, dp_error *err);
/* Same, with a caller-chosen program source and options (tests use it to
 * check build failures). */
dp_status dp_cl_open_source(dp_cl *cl, const char *spec, const char *source, const char *options,
			    dp_error *err);
void dp_cl_close(dp_cl *cl);
/* Releases every cached device buffer (the next launches upload again). */
void dp_cl_cache_clear(dp_cl *cl);

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

/* Runs kernel `name` over n work-items (global size padded to a multiple of
 * the kernel's work-group size). Argument 0 is the cl_uint n; args follow from 1. Output
 * buffers are read back before returning. n == 0 does nothing. Every array
 * argument lives in a device buffer cached by (pointer, bytes): an input is
 * uploaded only when it differs from what that buffer holds, and an output read
 * back leaves the buffer equal to the host array, so a later launch taking it as
 * input uploads nothing. */
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

/* One kernel argument as a kernel must declare it. */
typedef enum dp_cl_param_space {
	DP_CL_PARAM_VALUE,        /* passed by value (private) */
	DP_CL_PARAM_GLOBAL_CONST, /* __global const T * */
	DP_CL_PARAM_GLOBAL        /* __global T * */
} dp_cl_param_space;

typedef struct dp_cl_param {
	const char *name;
	const char *type; /* OpenCL type name without qualifiers or blanks: "float*", "uint" */
	dp_cl_param_space space;
} dp_cl_param;

/* The DP_CL_GRID_NARGS arguments of GRID_ARGS (kernels/grid.cl). */
void dp_cl_grid_params(dp_cl_param out[DP_CL_GRID_NARGS]);

/* Checks kernel `name` of cl's program (built with -cl-kernel-arg-info)
 * against the expected arguments: their number, then each one's name, type
 * name, address space and const. DP_ERR_KERNEL_BUILD naming the kernel and the
 * first difference, or DP_ERR_CL when the device gives no argument info. */
dp_status dp_cl_check_signature(dp_cl *cl, const char *name, const dp_cl_param *want, size_t nwant,
				dp_error *err);

#endif
