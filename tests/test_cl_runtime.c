/* The OpenCL runtime: device listing and choice, build failures with the log,
 * readable errors, the reference backend without OpenCL. */
#include "testkit.h"

#include "cl/device.h"
#include "cl/runtime.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static void test_lists_pocl(void **state)
{
	(void)state;
	dp_cl_device list[DP_CL_MAX_DEVICES];
	size_t n = 0;
	dp_error err = {0};
	assert_int_equal(dp_cl_devices(list, DP_CL_MAX_DEVICES, &n, &err), DP_OK);
	assert_true(n >= 1);
	char *buf = NULL;
	size_t len = 0;
	FILE *out = open_memstream(&buf, &len);
	assert_int_equal(dp_list_devices(out, &err), DP_OK);
	fclose(out);
	assert_true(strncmp(buf, "0: ", 3) == 0);
	assert_non_null(strstr(buf, list[0].name));
	free(buf);
}

static void test_choose_by_index_and_name(void **state)
{
	(void)state;
	dp_cl_device d;
	dp_error err = {0};
	assert_int_equal(dp_cl_choose("0", &d, &err), DP_OK);
	char want[400];
	snprintf(want, sizeof want, "%s", d.name);
	/* a case-changed substring of the name finds the same device */
	char sub[8] = {0};
	const char *slash = strstr(want, "/ ");
	const char *from = slash ? slash + 2 : want;
	for (int i = 0; i < 5 && from[i]; i++)
		sub[i] = (char)((i % 2) ? toupper((unsigned char)from[i]) : tolower((unsigned char)from[i]));
	assert_int_equal(dp_cl_choose(sub, &d, &err), DP_OK);
	assert_int_equal(dp_cl_choose("99", &d, &err), DP_ERR_NO_DEVICE);
	assert_non_null(strstr(err.message, "out of range"));
	assert_int_equal(dp_cl_choose("no-such-device-xyz", &d, &err), DP_ERR_NO_DEVICE);
	assert_non_null(strstr(err.message, "no-such-device-xyz"));
	setenv("DPOINTS_DEVICE", "no-such-device-xyz", 1);
	assert_int_equal(dp_cl_choose(NULL, &d, &err), DP_ERR_NO_DEVICE);
	setenv("DPOINTS_DEVICE", "0", 1);
	assert_int_equal(dp_cl_choose(NULL, &d, &err), DP_OK);
	unsetenv("DPOINTS_DEVICE");
}

static void test_build_failure_prints_log(void **state)
{
	(void)state;
	dp_cl cl;
	dp_error err = {0};
	const char *bad = "__kernel void broken(__global float *a) { a[0] = undefined_symbol_here; }\n";
	assert_int_equal(dp_cl_open_source(&cl, NULL, bad, DP_CL_BUILD_OPTIONS, &err), DP_ERR_KERNEL_BUILD);
	assert_non_null(strstr(err.message, "build log"));
	assert_non_null(strstr(err.message, "undefined_symbol_here"));
}

static void test_embedded_program_builds_and_errors_are_named(void **state)
{
	(void)state;
	dp_context *ctx = tk_cl_context();
	assert_int_equal(dp_context_backend(ctx), DP_BACKEND_CL);
	assert_true(strlen(dp_context_device_name(ctx)) > 0);
	assert_string_equal(dp_cl_error_name(CL_OUT_OF_RESOURCES), "CL_OUT_OF_RESOURCES");
	assert_string_equal(dp_cl_error_name(CL_INVALID_KERNEL_NAME), "CL_INVALID_KERNEL_NAME");
	/* a kernel that does not exist is a readable error, not a crash */
	dp_cl cl;
	dp_error err = {0};
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	cl_kernel k;
	assert_int_equal(dp_cl_kernel(&cl, "no_such_kernel", &k, &err), DP_ERR_CL);
	assert_non_null(strstr(err.message, "CL_INVALID_KERNEL_NAME"));
	dp_cl_close(&cl);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_lists_pocl),
		cmocka_unit_test(test_choose_by_index_and_name),
		cmocka_unit_test(test_build_failure_prints_log),
		cmocka_unit_test(test_embedded_program_builds_and_errors_are_named),
	};
	int rc = cmocka_run_group_tests(tests, NULL, NULL);
	tk_teardown_contexts(NULL);
	return rc;
}
