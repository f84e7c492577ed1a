#include "cl/runtime.h"

#include "cl/device.h"
#include "core/common.h"

#include <stdlib.h>
#include <string.h>

#define CHECK(call, what)                                                                          \
	do {                                                                                       \
		cl_int rc_ = (call);                                                               \
		if (rc_ != CL_SUCCESS) {                                                           \
			st = dp_fail(err, rc_ == CL_MEM_OBJECT_ALLOCATION_FAILURE ||               \
						  rc_ == CL_OUT_OF_HOST_MEMORY ||                  \
						  rc_ == CL_OUT_OF_RESOURCES                       \
					      ? DP_ERR_NOMEM                                       \
					      : DP_ERR_CL,                                         \
				     "OpenCL: %s failed: %s", what, dp_cl_error_name(rc_));        \
			goto cleanup;                                                              \
		}                                                                                  \
	} while (0)

/* The build log goes into the error message, which holds its head only: a
 * compiler reports the first error first. */
static dp_status build_failure(dp_cl *cl, cl_int rc, dp_error *err)
{
	size_t len = 0;
	cl_int lrc = clGetProgramBuildInfo(cl->program, cl->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &len);
	char *log = lrc == CL_SUCCESS ? malloc(len + 1) : NULL;
	if (log)
		lrc = clGetProgramBuildInfo(cl->program, cl->device, CL_PROGRAM_BUILD_LOG, len, log, NULL);
	if (!log || lrc != CL_SUCCESS) {
		free(log);
		return dp_fail(err, DP_ERR_KERNEL_BUILD, "OpenCL: program build failed (%s) on %s; no build log (%s)",
			       dp_cl_error_name(rc), cl->name,
			       lrc != CL_SUCCESS ? dp_cl_error_name(lrc) : "out of memory");
	}
	log[len] = '\0';
	dp_status st = dp_fail(err, DP_ERR_KERNEL_BUILD,
			       "OpenCL: program build failed (%s) on %s; build log (%zu bytes, its head if cut):\n%s",
			       dp_cl_error_name(rc), cl->name, len, log);
	free(log);
	return st;
}

/* The device's type, or the one $DP_CL_DEVICE_TYPE names. */
static dp_status device_type(cl_device_id device, cl_device_type *type, dp_error *err)
{
	const char *env = getenv("DP_CL_DEVICE_TYPE");
	if (env && *env) {
		if (strcmp(env, "cpu") && strcmp(env, "gpu"))
			return dp_fail(err, DP_ERR_ARG, "DP_CL_DEVICE_TYPE must be cpu or gpu, not '%s'", env);
		*type = strcmp(env, "cpu") ? CL_DEVICE_TYPE_GPU : CL_DEVICE_TYPE_CPU;
		return DP_OK;
	}
	if (clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof *type, type, NULL) != CL_SUCCESS)
		*type = CL_DEVICE_TYPE_GPU;
	return DP_OK;
}

/* DP_CL_LOCAL_SIZE_* by device type, or $DP_CL_LOCAL_SIZE. */
static dp_status choose_local_size(cl_device_id device, size_t *local, dp_error *err)
{
	const char *env = getenv("DP_CL_LOCAL_SIZE");
	if (env && *env) {
		char *end;
		unsigned long v = strtoul(env, &end, 10);
		if (*end || *env == '-' || v < 1 || v > DP_CL_LOCAL_SIZE_MAX)
			return dp_fail(err, DP_ERR_ARG, "DP_CL_LOCAL_SIZE must be 1 to %d, not '%s'",
				       DP_CL_LOCAL_SIZE_MAX, env);
		*local = v;
		return DP_OK;
	}
	cl_device_type type = 0;
	dp_status st = device_type(device, &type, err);
	if (st == DP_OK)
		*local = (type & CL_DEVICE_TYPE_CPU) ? DP_CL_LOCAL_SIZE_CPU : DP_CL_LOCAL_SIZE_GPU;
	return st;
}

dp_status dp_cl_open_source(dp_cl *cl, const char *spec, const char *source, const char *options,
			    dp_error *err)
{
	dp_status st = DP_OK;
	cl_int rc = CL_SUCCESS;
	dp_cl_device dev;
	memset(cl, 0, sizeof *cl);
	st = dp_cl_choose(spec, &dev, err);
	if (st != DP_OK)
		return st;
	cl->platform = dev.platform;
	cl->device = dev.device;
	snprintf(cl->name, sizeof cl->name, "%s", dev.name);

	cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)cl->platform, 0};
	if ((st = choose_local_size(cl->device, &cl->local_size, err)) != DP_OK)
		goto cleanup;
	cl->context = clCreateContext(props, 1, &cl->device, NULL, NULL, &rc);
	CHECK(rc, "clCreateContext");
	cl->queue = clCreateCommandQueue(cl->context, cl->device, 0, &rc);
	CHECK(rc, "clCreateCommandQueue");
	cl->program = clCreateProgramWithSource(cl->context, 1, &source, NULL, &rc);
	CHECK(rc, "clCreateProgramWithSource");
	rc = clBuildProgram(cl->program, 1, &cl->device, options, NULL, NULL);
	if (rc != CL_SUCCESS) {
		st = build_failure(cl, rc, err);
		goto cleanup;
	}
	return DP_OK;
cleanup:
	dp_cl_close(cl);
	return st;
}

/* DP_LANES for the device: $DP_CL_LANES when set, else by its type. */
static dp_status choose_lanes(const char *spec, int *lanes, dp_error *err)
{
	const char *env = getenv("DP_CL_LANES");
	if (env && *env) {
		if (strcmp(env, "1") && strcmp(env, "4") && strcmp(env, "8") && strcmp(env, "16"))
			return dp_fail(err, DP_ERR_ARG, "DP_CL_LANES must be 1, 4, 8 or 16, not '%s'", env);
		*lanes = atoi(env);
		return DP_OK;
	}
	dp_cl_device dev;
	dp_status st = dp_cl_choose(spec, &dev, err);
	if (st != DP_OK)
		return st;
	cl_device_type type = 0;
	if ((st = device_type(dev.device, &type, err)) != DP_OK)
		return st;
	*lanes = (type & CL_DEVICE_TYPE_CPU) ? DP_CL_LANES_CPU : DP_CL_LANES_GPU;
	return DP_OK;
}

dp_status dp_cl_open(dp_cl *cl, const char *spec, dp_error *err)
{
	int lanes = 0;
	dp_status st = choose_lanes(spec, &lanes, err);
	if (st != DP_OK)
		return st;
	char options[256];
	snprintf(options, sizeof options, "%s -DDP_LANES=%d", DP_CL_BUILD_OPTIONS, lanes);
	st = dp_cl_open_source(cl, spec, dp_kernel_source, options, err);
	if (st == DP_OK)
		cl->lanes = lanes;
	return st;
}

/* Frees a cached buffer; the slot is empty afterwards either way. Returns
 * clReleaseMemObject's result: on the clean-up paths nothing is left to
 * report it to, so only an eviction in the middle of a run checks it. */
static cl_int cache_release(dp_cl *cl, dp_cl_cached *c)
{
	cl_int rc = c->mem ? clReleaseMemObject(c->mem) : CL_SUCCESS;
	free(c->shadow);
	cl->cache_bytes -= c->bytes;
	memset(c, 0, sizeof *c);
	return rc;
}

void dp_cl_cache_clear(dp_cl *cl)
{
	if (cl->queue)
		clFinish(cl->queue);
	for (size_t i = 0; i < DP_CL_CACHE_SLOTS; i++)
		if (cl->cache[i].mem)
			cache_release(cl, &cl->cache[i]);
}

/* The releases' results go unchecked: the caller is freeing the context and
 * has nothing left to hear a failure. */
void dp_cl_close(dp_cl *cl)
{
	dp_cl_cache_clear(cl);
	for (size_t i = 0; i < cl->nkernels; i++)
		clReleaseKernel(cl->kernels[i].kernel);
	if (cl->program)
		clReleaseProgram(cl->program);
	if (cl->queue)
		clReleaseCommandQueue(cl->queue);
	if (cl->context)
		clReleaseContext(cl->context);
	memset(cl, 0, sizeof *cl);
}

dp_status dp_cl_kernel(dp_cl *cl, const char *name, cl_kernel *kernel, dp_error *err)
{
	for (size_t i = 0; i < cl->nkernels; i++)
		if (strcmp(cl->kernels[i].name, name) == 0) {
			*kernel = cl->kernels[i].kernel;
			return DP_OK;
		}
	if (cl->nkernels == DP_CL_MAX_KERNELS || strlen(name) >= sizeof cl->kernels[0].name)
		return dp_fail(err, DP_ERR_INTERNAL, "OpenCL: kernel table full or name too long (%s)", name);
	cl_int rc;
	cl_kernel k = clCreateKernel(cl->program, name, &rc);
	if (rc != CL_SUCCESS)
		return dp_fail(err, DP_ERR_CL, "OpenCL: clCreateKernel(%s) failed: %s", name, dp_cl_error_name(rc));
	size_t limit = 0;
	rc = clGetKernelWorkGroupInfo(k, cl->device, CL_KERNEL_WORK_GROUP_SIZE, sizeof limit, &limit, NULL);
	if (rc != CL_SUCCESS) {
		clReleaseKernel(k);
		return dp_fail(err, DP_ERR_CL, "OpenCL: clGetKernelWorkGroupInfo(%s) failed: %s", name,
			       dp_cl_error_name(rc));
	}
	snprintf(cl->kernels[cl->nkernels].name, sizeof cl->kernels[0].name, "%s", name);
	cl->kernels[cl->nkernels].local = limit && limit < cl->local_size ? limit : cl->local_size;
	cl->kernels[cl->nkernels++].kernel = k;
	*kernel = k;
	return DP_OK;
}

/* A buffer of at least one float: OpenCL rejects zero-sized buffers. */
#define MIN_BUFFER_BYTES 16
#define MAX_LAUNCH_ARGS 48

static dp_cl_kernel_stats *kernel_stats(dp_cl *cl, const char *name)
{
	for (size_t i = 0; i < cl->nkernels; i++)
		if (strcmp(cl->kernels[i].name, name) == 0)
			return &cl->kernels[i].stats;
	return NULL;
}

static size_t kernel_local(const dp_cl *cl, const char *name)
{
	for (size_t i = 0; i < cl->nkernels; i++)
		if (strcmp(cl->kernels[i].name, name) == 0)
			return cl->kernels[i].local;
	return cl->local_size;
}

/* The cached buffer of (host, bytes), created (evicting the least recently
 * used buffer that this launch does not use) when there is none; *fresh says
 * the device holds nothing of it yet. */
static dp_status cache_get(dp_cl *cl, const void *host, size_t bytes, dp_cl_cached **out, int *fresh,
			   dp_error *err)
{
	dp_cl_cached *slot = NULL, *lru = NULL;
	for (size_t i = 0; i < DP_CL_CACHE_SLOTS; i++) {
		dp_cl_cached *c = &cl->cache[i];
		if (c->mem && c->host == host && c->bytes == bytes) {
			c->used = cl->launches;
			*out = c;
			*fresh = 0;
			return DP_OK;
		}
		if (!c->mem && !slot)
			slot = c;
		if (c->mem && c->used != cl->launches && (!lru || c->used < lru->used))
			lru = c;
	}
	/* Free room for this buffer: unused slots go first, least recent first. */
	while (lru && (!slot || cl->cache_bytes + bytes > DP_CL_CACHE_BYTES)) {
		cl_int rc = cache_release(cl, lru);
		if (rc != CL_SUCCESS)
			return dp_fail(err, DP_ERR_CL, "OpenCL: clReleaseMemObject (evicting a cached buffer) failed: %s",
				       dp_cl_error_name(rc));
		if (!slot)
			slot = lru;
		lru = NULL;
		for (size_t i = 0; i < DP_CL_CACHE_SLOTS; i++) {
			dp_cl_cached *c = &cl->cache[i];
			if (c->mem && c->used != cl->launches && (!lru || c->used < lru->used))
				lru = c;
		}
	}
	if (!slot)
		return dp_fail(err, DP_ERR_INTERNAL, "OpenCL: more than %d buffers in one launch", DP_CL_CACHE_SLOTS);
	cl_int rc;
	slot->mem = clCreateBuffer(cl->context, CL_MEM_READ_WRITE, bytes < MIN_BUFFER_BYTES ? MIN_BUFFER_BYTES : bytes,
				   NULL, &rc);
	if (rc != CL_SUCCESS) {
		slot->mem = NULL;
		return dp_fail(err, rc == CL_OUT_OF_HOST_MEMORY || rc == CL_MEM_OBJECT_ALLOCATION_FAILURE ||
					    rc == CL_OUT_OF_RESOURCES
				    ? DP_ERR_NOMEM
				    : DP_ERR_CL,
			       "OpenCL: clCreateBuffer failed: %s", dp_cl_error_name(rc));
	}
	slot->shadow = malloc(bytes ? bytes : 1);
	if (!slot->shadow) {
		clReleaseMemObject(slot->mem);
		slot->mem = NULL;
		return dp_fail(err, DP_ERR_NOMEM, "OpenCL: out of memory for a buffer's host copy");
	}
	slot->host = host;
	slot->bytes = bytes;
	slot->used = cl->launches;
	cl->cache_bytes += bytes;
	*out = slot;
	*fresh = 1;
	return DP_OK;
}

dp_status dp_cl_launch(dp_cl *cl, const char *name, size_t n, const dp_cl_arg *args, size_t nargs,
		       dp_error *err)
{
	dp_status st = DP_OK;
	dp_cl_cached *slots[MAX_LAUNCH_ARGS] = {0};
	cl_kernel kernel;
	if (n == 0)
		return DP_OK;
	if (nargs > MAX_LAUNCH_ARGS || n > UINT32_MAX)
		return dp_fail(err, DP_ERR_INTERNAL, "OpenCL: launch of %s has too many arguments or items", name);
	st = dp_cl_kernel(cl, name, &kernel, err);
	if (st != DP_OK)
		return st;
	double t0 = dp_seconds();
	dp_cl_kernel_stats *ks = kernel_stats(cl, name);
	double h2d = 0.0, d2h = 0.0, skipped = 0.0;
	cl->launches++;
	cl_uint count = (cl_uint)n;
	CHECK(clSetKernelArg(kernel, 0, sizeof count, &count), "clSetKernelArg");
	for (size_t a = 0; a < nargs; a++) {
		const dp_cl_arg *arg = &args[a];
		if (arg->kind == DP_CL_ARG_VALUE) {
			CHECK(clSetKernelArg(kernel, (cl_uint)(a + 1), arg->bytes, arg->ptr), "clSetKernelArg");
			continue;
		}
		int fresh = 0;
		if ((st = cache_get(cl, arg->ptr, arg->bytes, &slots[a], &fresh, err)) != DP_OK)
			goto cleanup;
		/* An output must not share its buffer with another argument of
		 * the launch (the kernel would read what it writes). */
		for (size_t b = 0; b < a; b++)
			if (arg->bytes && slots[b] == slots[a] && (arg->kind == DP_CL_ARG_OUT || args[b].kind == DP_CL_ARG_OUT)) {
				st = dp_fail(err, DP_ERR_INTERNAL, "OpenCL: an output of %s is also another argument",
					     name);
				goto cleanup;
			}
		if (arg->kind == DP_CL_ARG_IN && arg->bytes) {
			if (fresh || memcmp(slots[a]->shadow, arg->ptr, arg->bytes) != 0) {
				/* From the host copy, which stays put until the
				 * queue has run it (the caller's array need not). */
				memcpy(slots[a]->shadow, arg->ptr, arg->bytes);
				CHECK(clEnqueueWriteBuffer(cl->queue, slots[a]->mem, CL_FALSE, 0, arg->bytes,
							   slots[a]->shadow, 0, NULL, NULL),
				      "clEnqueueWriteBuffer");
				h2d += (double)arg->bytes;
			} else {
				skipped += (double)arg->bytes;
			}
		}
		CHECK(clSetKernelArg(kernel, (cl_uint)(a + 1), sizeof(cl_mem), &slots[a]->mem), "clSetKernelArg");
	}
	size_t local = kernel_local(cl, name);
	size_t global = (n + local - 1) / local * local;
	CHECK(clEnqueueNDRangeKernel(cl->queue, kernel, 1, NULL, &global, &local, 0, NULL, NULL),
	      "clEnqueueNDRangeKernel");
	/* Read into the host copies; the in-order queue runs the reads after
	 * the kernel, and one blocking wait covers them all. */
	for (size_t a = 0; a < nargs; a++)
		if (args[a].kind == DP_CL_ARG_OUT && args[a].bytes) {
			CHECK(clEnqueueReadBuffer(cl->queue, slots[a]->mem, CL_FALSE, 0, args[a].bytes,
						  slots[a]->shadow, 0, NULL, NULL),
			      "clEnqueueReadBuffer");
			d2h += (double)args[a].bytes;
		}
	CHECK(clFinish(cl->queue), "clFinish (kernel execution)");
	for (size_t a = 0; a < nargs; a++)
		if (args[a].kind == DP_CL_ARG_OUT && args[a].bytes)
			memcpy((void *)args[a].ptr, slots[a]->shadow, args[a].bytes);
cleanup:
	if (st != DP_OK) {
		/* Commands already queued may still use the buffers; what the
		 * device holds of this launch's arrays is unknown now. */
		clFinish(cl->queue);
		for (size_t a = 0; a < nargs; a++)
			if (slots[a] && slots[a]->mem)
				cache_release(cl, slots[a]);
		if (err)
			snprintf(err->message + strlen(err->message), sizeof err->message - strlen(err->message),
				 " (kernel %s, %zu items)", name, n);
	}
	cl->h2d_bytes += h2d;
	cl->d2h_bytes += d2h;
	cl->h2d_skipped_bytes += skipped;
	if (ks) {
		ks->launches += 1.0;
		ks->seconds += dp_seconds() - t0;
		ks->h2d_bytes += h2d;
		ks->d2h_bytes += d2h;
		ks->h2d_skipped_bytes += skipped;
		if (cl->pair_counter) {
			ks->pairs += *cl->pair_counter - cl->pairs_seen;
			cl->pairs_seen = *cl->pair_counter;
		}
	}
	return st;
}

void dp_cl_grid_args(const dp_grid *g, dp_cl_grid_storage *s, dp_cl_arg out[DP_CL_GRID_NARGS])
{
	s->origin_cell.s[0] = g->origin[0];
	s->origin_cell.s[1] = g->origin[1];
	s->origin_cell.s[2] = g->origin[2];
	s->origin_cell.s[3] = g->cell;
	for (int a = 0; a < 3; a++)
		s->dim.s[a] = g->dim[a];
	s->dim.s[3] = g->margin; /* GRID_PAIRS(_REACH) clamps queries by it */
	out[0] = DP_CL_IN(g->x, g->n * sizeof(float));
	out[1] = DP_CL_IN(g->y, g->n * sizeof(float));
	out[2] = DP_CL_IN(g->z, g->n * sizeof(float));
	out[3] = DP_CL_IN(g->cell_start, (size_t)g->ncells * sizeof(uint32_t));
	out[4] = DP_CL_IN(g->cell_count, (size_t)g->ncells * sizeof(uint32_t));
	out[5] = DP_CL_VALUE(s->origin_cell);
	out[6] = DP_CL_VALUE(s->dim);
}

void dp_cl_grid_params(dp_cl_param out[DP_CL_GRID_NARGS])
{
	out[0] = (dp_cl_param){"gx", "float*", DP_CL_PARAM_GLOBAL_CONST};
	out[1] = (dp_cl_param){"gy", "float*", DP_CL_PARAM_GLOBAL_CONST};
	out[2] = (dp_cl_param){"gz", "float*", DP_CL_PARAM_GLOBAL_CONST};
	out[3] = (dp_cl_param){"cell_start", "uint*", DP_CL_PARAM_GLOBAL_CONST};
	out[4] = (dp_cl_param){"cell_count", "uint*", DP_CL_PARAM_GLOBAL_CONST};
	out[5] = (dp_cl_param){"grid_origin_cell", "float4", DP_CL_PARAM_VALUE};
	out[6] = (dp_cl_param){"grid_dim", "int4", DP_CL_PARAM_VALUE};
}

static const char *space_name(dp_cl_param_space s)
{
	return s == DP_CL_PARAM_VALUE ? "by value" : s == DP_CL_PARAM_GLOBAL_CONST ? "__global const" : "__global";
}

/* The address space of argument a as a dp_cl_param_space; *space is left at
 * an impossible value for __local and __constant (no table row uses them). */
static cl_int arg_space(cl_kernel k, cl_uint a, int *space)
{
	cl_kernel_arg_address_qualifier aq;
	cl_kernel_arg_type_qualifier tq;
	cl_int rc = clGetKernelArgInfo(k, a, CL_KERNEL_ARG_ADDRESS_QUALIFIER, sizeof aq, &aq, NULL);
	if (rc == CL_SUCCESS)
		rc = clGetKernelArgInfo(k, a, CL_KERNEL_ARG_TYPE_QUALIFIER, sizeof tq, &tq, NULL);
	if (rc != CL_SUCCESS)
		return rc;
	if (aq == CL_KERNEL_ARG_ADDRESS_PRIVATE)
		*space = DP_CL_PARAM_VALUE;
	else if (aq == CL_KERNEL_ARG_ADDRESS_GLOBAL)
		*space = (tq & CL_KERNEL_ARG_TYPE_CONST) ? DP_CL_PARAM_GLOBAL_CONST : DP_CL_PARAM_GLOBAL;
	else
		*space = -1;
	return CL_SUCCESS;
}

dp_status dp_cl_check_signature(dp_cl *cl, const char *name, const dp_cl_param *want, size_t nwant,
				dp_error *err)
{
	cl_kernel k;
	dp_status st = dp_cl_kernel(cl, name, &k, err);
	if (st != DP_OK)
		return st;
	cl_uint nargs = 0;
	CHECK(clGetKernelInfo(k, CL_KERNEL_NUM_ARGS, sizeof nargs, &nargs, NULL), "clGetKernelInfo");
	if (nargs != nwant)
		return dp_fail(err, DP_ERR_KERNEL_BUILD,
			       "OpenCL: kernel %s takes %u arguments, its operator table row %zu", name, nargs, nwant);
	for (cl_uint a = 0; a < nargs; a++) {
		/* Names and type names are spelled as declared with blanks
		 * removed ("float*", PoCL 3.1 and the OpenCL 1.2 spec alike);
		 * const comes as a type qualifier, which the spec defines for
		 * pointed-to types only, so it is compared for arrays alone. */
		char aname[128] = "", atype[128] = "";
		int space = 0;
		cl_int rc = clGetKernelArgInfo(k, a, CL_KERNEL_ARG_NAME, sizeof aname, aname, NULL);
		if (rc == CL_SUCCESS)
			rc = clGetKernelArgInfo(k, a, CL_KERNEL_ARG_TYPE_NAME, sizeof atype, atype, NULL);
		if (rc == CL_SUCCESS)
			rc = arg_space(k, a, &space);
		CHECK(rc, "clGetKernelArgInfo (the program needs -cl-kernel-arg-info)");
		const dp_cl_param *w = &want[a];
		if (strcmp(aname, w->name) || strcmp(atype, w->type) || space != (int)w->space)
			return dp_fail(err, DP_ERR_KERNEL_BUILD,
				       "OpenCL: kernel %s argument %u is %s %s %s, its operator table row says %s %s %s",
				       name, a, space >= 0 ? space_name((dp_cl_param_space)space) : "__local/__constant",
				       atype, aname, space_name(w->space), w->type, w->name);
	}
cleanup:
	return st;
}
