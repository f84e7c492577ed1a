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

static dp_status build_failure(dp_cl *cl, cl_int rc, dp_error *err)
{
	size_t len = 0;
	clGetProgramBuildInfo(cl->program, cl->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &len);
	char *log = malloc(len + 1);
	if (!log)
		return dp_fail(err, DP_ERR_KERNEL_BUILD, "OpenCL: program build failed (%s) on %s",
			       dp_cl_error_name(rc), cl->name);
	clGetProgramBuildInfo(cl->program, cl->device, CL_PROGRAM_BUILD_LOG, len, log, NULL);
	log[len] = '\0';
	dp_status st = dp_fail(err, DP_ERR_KERNEL_BUILD, "OpenCL: program build failed (%s) on %s; build log:\n%s",
			       dp_cl_error_name(rc), cl->name, log);
	free(log);
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

dp_status dp_cl_open(dp_cl *cl, const char *spec, dp_error *err)
{
	return dp_cl_open_source(cl, spec, dp_kernel_source, DP_CL_BUILD_OPTIONS, err);
}

void dp_cl_close(dp_cl *cl)
{
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
	snprintf(cl->kernels[cl->nkernels].name, sizeof cl->kernels[0].name, "%s", name);
	cl->kernels[cl->nkernels++].kernel = k;
	*kernel = k;
	return DP_OK;
}

/* A buffer of at least one float: OpenCL rejects zero-sized buffers. */
#define MIN_BUFFER_BYTES 16
#define MAX_LAUNCH_ARGS 48

dp_status dp_cl_launch(dp_cl *cl, const char *name, size_t n, const dp_cl_arg *args, size_t nargs,
		       dp_error *err)
{
	dp_status st = DP_OK;
	cl_mem mems[MAX_LAUNCH_ARGS] = {0};
	cl_kernel kernel;
	if (n == 0)
		return DP_OK;
	if (nargs > MAX_LAUNCH_ARGS || n > UINT32_MAX)
		return dp_fail(err, DP_ERR_INTERNAL, "OpenCL: launch of %s has too many arguments or items", name);
	st = dp_cl_kernel(cl, name, &kernel, err);
	if (st != DP_OK)
		return st;
	cl_uint count = (cl_uint)n;
	CHECK(clSetKernelArg(kernel, 0, sizeof count, &count), "clSetKernelArg");
	for (size_t a = 0; a < nargs; a++) {
		const dp_cl_arg *arg = &args[a];
		if (arg->kind == DP_CL_ARG_VALUE) {
			CHECK(clSetKernelArg(kernel, (cl_uint)(a + 1), arg->bytes, arg->ptr), "clSetKernelArg");
			continue;
		}
		cl_int rc;
		size_t bytes = arg->bytes < MIN_BUFFER_BYTES ? MIN_BUFFER_BYTES : arg->bytes;
		if (arg->kind == DP_CL_ARG_IN) {
			mems[a] = clCreateBuffer(cl->context, CL_MEM_READ_ONLY, bytes, NULL, &rc);
			CHECK(rc, "clCreateBuffer (input)");
			if (arg->bytes)
				CHECK(clEnqueueWriteBuffer(cl->queue, mems[a], CL_FALSE, 0, arg->bytes, arg->ptr, 0,
							   NULL, NULL),
				      "clEnqueueWriteBuffer");
		} else {
			mems[a] = clCreateBuffer(cl->context, CL_MEM_WRITE_ONLY, bytes, NULL, &rc);
			CHECK(rc, "clCreateBuffer (output)");
		}
		CHECK(clSetKernelArg(kernel, (cl_uint)(a + 1), sizeof(cl_mem), &mems[a]), "clSetKernelArg");
	}
	size_t local = DP_CL_LOCAL_SIZE;
	size_t global = (n + local - 1) / local * local;
	CHECK(clEnqueueNDRangeKernel(cl->queue, kernel, 1, NULL, &global, &local, 0, NULL, NULL),
	      "clEnqueueNDRangeKernel");
	for (size_t a = 0; a < nargs; a++)
		if (args[a].kind == DP_CL_ARG_OUT && args[a].bytes)
			CHECK(clEnqueueReadBuffer(cl->queue, mems[a], CL_FALSE, 0, args[a].bytes, (void *)args[a].ptr,
						  0, NULL, NULL),
			      "clEnqueueReadBuffer");
	CHECK(clFinish(cl->queue), "clFinish (kernel execution)");
cleanup:
	if (st != DP_OK) {
		/* commands already queued may still use the buffers released below */
		clFinish(cl->queue);
		if (err)
			snprintf(err->message + strlen(err->message), sizeof err->message - strlen(err->message),
				 " (kernel %s, %zu items)", name, n);
	}
	for (size_t a = 0; a < nargs; a++)
		if (mems[a])
			clReleaseMemObject(mems[a]);
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
	s->dim.s[3] = g->margin; /* GRID_FOR_REACH clamps queries by it */
	out[0] = DP_CL_IN(g->x, g->n * sizeof(float));
	out[1] = DP_CL_IN(g->y, g->n * sizeof(float));
	out[2] = DP_CL_IN(g->z, g->n * sizeof(float));
	out[3] = DP_CL_IN(g->cell_start, (size_t)g->ncells * sizeof(uint32_t));
	out[4] = DP_CL_IN(g->cell_count, (size_t)g->ncells * sizeof(uint32_t));
	out[5] = DP_CL_VALUE(s->origin_cell);
	out[6] = DP_CL_VALUE(s->dim);
}
