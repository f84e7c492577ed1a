/* Without any OpenCL platform: the CL backend fails with a clear message and
 * the reference backend still works. A program of its own, because the ICD
 * loader reads its vendor folder once per process. */
#include "testkit.h"

#include "files.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void test_no_platform(void **state)
{
	(void)state;
	dp_context *ctx = NULL;
	dp_error err = {0};
	assert_int_equal(dp_context_create(&ctx, DP_BACKEND_CL, NULL, &err), DP_ERR_NO_DEVICE);
	assert_null(ctx);
	assert_non_null(strstr(err.message, "no platform"));
	assert_non_null(strstr(err.message, "--backend ref"));
	assert_int_equal(dp_list_devices(stdout, &err), DP_ERR_NO_DEVICE);
	assert_int_equal(dp_context_create(&ctx, DP_BACKEND_REF, NULL, &err), DP_OK);
	assert_string_equal(dp_context_device_name(ctx), "reference (scalar C)");
	dp_context_free(ctx);
}

int main(void)
{
	/* the loader then finds no vendor file: no platform at all */
	char vendors[64];
	snprintf(vendors, sizeof vendors, "%s", tk_temp_dir());
	setenv("OCL_ICD_VENDORS", vendors, 1);
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_no_platform),
	};
	int rc = cmocka_run_group_tests(tests, NULL, NULL);
	tk_remove_dir(vendors);
	return rc;
}
