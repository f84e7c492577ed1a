/* The operator table's check of kernel signatures (backend/ops.h): the
 * embedded program passes it, and a kernel whose arguments differ from its row
 * (swapped, missing, retyped, const dropped) is refused with a message naming
 * the kernel and the argument. */
#include "testkit.h"

#include "backend/ops.h"

#include <stdlib.h>
#include <string.h>

/* sink_step as its row declares it (kernels/sink.cl) is renamed away, and
 * `replacement` takes its name. */
#define SINK_STEP_HEAD "__kernel void sink_step("
#define OPTIONS DP_CL_BUILD_OPTIONS " -DDP_LANES=16"

static char *with_sink_step(const char *replacement)
{
	const char *at = strstr(dp_kernel_source, SINK_STEP_HEAD);
	assert_non_null(at);
	size_t head = (size_t)(at - dp_kernel_source), total = strlen(dp_kernel_source);
	const char *renamed = "__kernel void sink_step_as_declared(";
	char *src = malloc(total + strlen(renamed) + strlen(replacement) + 2);
	assert_non_null(src);
	memcpy(src, dp_kernel_source, head);
	strcpy(src + head, renamed);
	strcat(src, at + strlen(SINK_STEP_HEAD));
	strcat(src, "\n");
	strcat(src, replacement);
	return src;
}

/* Builds the program with sink_step replaced and runs the check. */
static dp_status check_with(const char *replacement, const char *options, dp_error *err)
{
	char *src = with_sink_step(replacement);
	dp_cl cl;
	dp_error build_err = {0};
	dp_status built = dp_cl_open_source(&cl, NULL, src, options, &build_err);
	free(src);
	if (built != DP_OK)
		fail_msg("build: %s", build_err.message);
	dp_status st = dp_ops_check_kernels(&cl, err);
	dp_cl_close(&cl);
	return st;
}

static void test_embedded_program_matches_the_table(void **state)
{
	(void)state;
	dp_cl cl;
	dp_error err = {0};
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	assert_int_equal(dp_ops_check_kernels(&cl, &err), DP_OK);
	dp_cl_close(&cl);
	/* and the check runs on every context */
	assert_int_equal(dp_context_backend(tk_cl_context()), DP_BACKEND_CL);
}

static void test_swapped_arguments_are_refused(void **state)
{
	(void)state;
	dp_error err = {0};
	assert_int_equal(check_with("__kernel void sink_step(const uint n, __global const float *px,"
				    " __global const float *py, __global const float *pz, __global const float *depth, GRID_ARGS,"
				    " const float radius, __global const float *move, __global const float *stop,"
				    " const float margin, __global float *mean) {}\n",
				    OPTIONS, &err),
			 DP_ERR_KERNEL_BUILD);
	assert_non_null(strstr(err.message, "kernel sink_step argument 12 is by value float radius"));
	assert_non_null(strstr(err.message, "row says __global const float* move"));
}

static void test_missing_argument_is_refused(void **state)
{
	(void)state;
	dp_error err = {0};
	assert_int_equal(check_with("__kernel void sink_step(const uint n, __global const float *px,"
				    " __global const float *py, __global const float *pz, __global const float *depth, GRID_ARGS,"
				    " __global const float *move, const float radius, const float margin,"
				    " __global float *mean) {}\n",
				    OPTIONS, &err),
			 DP_ERR_KERNEL_BUILD);
	assert_non_null(strstr(err.message, "kernel sink_step takes 16 arguments, its operator table row 17"));
}

static void test_retyped_or_writable_input_is_refused(void **state)
{
	(void)state;
	dp_error err = {0};
	assert_int_equal(check_with("__kernel void sink_step(const uint n, __global const float *px,"
				    " __global const float *py, __global const float *pz, __global const float *depth, GRID_ARGS,"
				    " __global const int *move, __global const float *stop, const float radius,"
				    " const float margin, __global float *mean) {}\n",
				    OPTIONS, &err),
			 DP_ERR_KERNEL_BUILD);
	assert_non_null(strstr(err.message, "argument 12 is __global const int* move"));
	assert_int_equal(check_with("__kernel void sink_step(const uint n, __global const float *px,"
				    " __global const float *py, __global const float *pz, __global const float *depth, GRID_ARGS,"
				    " __global float *move, __global const float *stop, const float radius,"
				    " const float margin, __global float *mean) {}\n",
				    OPTIONS, &err),
			 DP_ERR_KERNEL_BUILD);
	assert_non_null(strstr(err.message, "argument 12 is __global float* move"));
}

/* Without -cl-kernel-arg-info there may be nothing to compare: then the
 * check is an error, not a pass. Some implementations keep the names anyway
 * (Mesa's rusticl does); there the check runs on them and passes. */
static void test_no_argument_info_is_an_error(void **state)
{
	(void)state;
	dp_cl cl;
	dp_error err = {0};
	assert_int_equal(dp_cl_open_source(&cl, NULL, dp_kernel_source, "-cl-std=CL1.2 -DDP_LANES=16", &err), DP_OK);
	dp_status st = dp_ops_check_kernels(&cl, &err);
	cl_kernel k;
	dp_error kerr = {0};
	assert_int_equal(dp_cl_kernel(&cl, "sink_step", &k, &kerr), DP_OK);
	char name[16];
	if (clGetKernelArgInfo(k, 0, CL_KERNEL_ARG_NAME, sizeof name, name, NULL) == CL_KERNEL_ARG_INFO_NOT_AVAILABLE) {
		assert_int_not_equal(st, DP_OK);
		assert_non_null(strstr(err.message, "-cl-kernel-arg-info"));
	} else {
		assert_int_equal(st, DP_OK);
	}
	dp_cl_close(&cl);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_embedded_program_matches_the_table),
		cmocka_unit_test(test_swapped_arguments_are_refused),
		cmocka_unit_test(test_missing_argument_is_refused),
		cmocka_unit_test(test_retyped_or_writable_input_is_refused),
		cmocka_unit_test(test_no_argument_info_is_an_error),
	};
	int rc = cmocka_run_group_tests(tests, NULL, NULL);
	tk_teardown_contexts(NULL);
	return rc;
}
