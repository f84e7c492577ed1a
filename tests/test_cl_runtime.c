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

/* Device buffers persist across launches: an input is uploaded only when its
 * contents changed, an output read back is then an input already on the
 * device, and every launch still computes from the host arrays' contents. */
static void test_buffers_stay_on_the_device(void **state)
{
	(void)state;
	const char *src = "__kernel void axpy(const uint n, __global const float *x, __global const float *y,\n"
			  "                   const float a, __global float *out)\n"
			  "{ uint i = get_global_id(0); if (i < n) out[i] = a * x[i] + y[i]; }\n";
	dp_cl cl;
	dp_error err = {0};
	assert_int_equal(dp_cl_open_source(&cl, NULL, src, DP_CL_BUILD_OPTIONS, &err), DP_OK);
	enum { N = 1000 };
	static float x[N], y[N], out[N], out2[N];
	for (int i = 0; i < N; i++) {
		x[i] = (float)i;
		y[i] = 1.0f;
	}
	const double bytes = N * sizeof(float);
	float a = 2.0f;
	dp_cl_arg args[] = {DP_CL_IN(x, sizeof x), DP_CL_IN(y, sizeof y), DP_CL_VALUE(a), DP_CL_OUT(out, sizeof out)};
	assert_int_equal(dp_cl_launch(&cl, "axpy", N, args, 4, &err), DP_OK);
	assert_true(cl.h2d_bytes == 2 * bytes && cl.d2h_bytes == bytes && cl.h2d_skipped_bytes == 0.0);
	assert_true(out[10] == 21.0f);
	/* unchanged inputs: nothing uploaded */
	assert_int_equal(dp_cl_launch(&cl, "axpy", N, args, 4, &err), DP_OK);
	assert_true(cl.h2d_bytes == 2 * bytes && cl.h2d_skipped_bytes == 2 * bytes);
	/* one element of y changed: y alone goes up again */
	y[999] = 5.0f;
	assert_int_equal(dp_cl_launch(&cl, "axpy", N, args, 4, &err), DP_OK);
	assert_true(cl.h2d_bytes == 3 * bytes);
	assert_true(out[999] == 2.0f * 999.0f + 5.0f && out[0] == 1.0f);
	/* the output as an input: the device holds it already */
	dp_cl_arg chain[] = {DP_CL_IN(out, sizeof out), DP_CL_IN(y, sizeof y), DP_CL_VALUE(a),
			     DP_CL_OUT(out2, sizeof out2)};
	assert_int_equal(dp_cl_launch(&cl, "axpy", N, chain, 4, &err), DP_OK);
	assert_true(cl.h2d_bytes == 3 * bytes);
	assert_true(out2[10] == 2.0f * 21.0f + 1.0f);
	/* an output that is also an input of the same launch is refused */
	dp_cl_arg alias[] = {DP_CL_IN(out, sizeof out), DP_CL_IN(y, sizeof y), DP_CL_VALUE(a),
			     DP_CL_OUT(out, sizeof out)};
	assert_int_equal(dp_cl_launch(&cl, "axpy", N, alias, 4, &err), DP_ERR_INTERNAL);
	/* after clearing, everything is uploaded again and still right */
	dp_cl_cache_clear(&cl);
	double before = cl.h2d_bytes;
	x[10] = 0.0f;
	assert_int_equal(dp_cl_launch(&cl, "axpy", N, args, 4, &err), DP_OK);
	assert_true(cl.h2d_bytes == before + 2 * bytes && out[10] == 1.0f);
	assert_true(cl.kernels[0].stats.launches == 6.0); /* the refused one counts */
	dp_cl_close(&cl);
}

/* $DP_CL_LANES chooses the kernels' lane count whatever the device, so both
 * forms run here; a bad value is refused. */
static void test_lanes_forced(void **state)
{
	(void)state;
	const char *saved = getenv("DP_CL_LANES");
	char keep[16] = "";
	if (saved)
		snprintf(keep, sizeof keep, "%s", saved);
	dp_cl cl;
	dp_error err = {0};
	setenv("DP_CL_LANES", "1", 1);
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	assert_int_equal(cl.lanes, 1);
	dp_cl_close(&cl);
	setenv("DP_CL_LANES", "3", 1);
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "DP_CL_LANES"));
	unsetenv("DP_CL_LANES");
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	cl_device_type type = 0;
	assert_int_equal(clGetDeviceInfo(cl.device, CL_DEVICE_TYPE, sizeof type, &type, NULL), CL_SUCCESS);
	assert_int_equal(cl.lanes, (type & CL_DEVICE_TYPE_CPU) ? DP_CL_LANES_CPU : DP_CL_LANES_GPU);
	dp_cl_close(&cl);
	if (saved)
		setenv("DP_CL_LANES", keep, 1);
}

/* Restores an environment variable saved by env_save. */
typedef struct saved_env {
	const char *name;
	int set;
	char value[32];
} saved_env;

static saved_env env_save(const char *name)
{
	saved_env e = {.name = name};
	const char *v = getenv(name);
	if (v) {
		e.set = 1;
		snprintf(e.value, sizeof e.value, "%s", v);
	}
	unsetenv(name);
	return e;
}

static void env_restore(const saved_env *e)
{
	if (e->set)
		setenv(e->name, e->value, 1);
	else
		unsetenv(e->name);
}

/* The work-group size of the embedded program's kernel `name` on cl. */
static size_t kernel_local_size(dp_cl *cl, const char *name)
{
	cl_kernel k;
	dp_error err = {0};
	assert_int_equal(dp_cl_kernel(cl, name, &k, &err), DP_OK);
	for (size_t i = 0; i < cl->nkernels; i++)
		if (!strcmp(cl->kernels[i].name, name))
			return cl->kernels[i].local;
	fail_msg("kernel %s not in the table", name);
	return 0;
}

/* The work-group size follows the device type, which $DP_CL_DEVICE_TYPE can
 * force (the GPU choices then run here, on PoCL), and $DP_CL_LOCAL_SIZE
 * overrides it; bad values are refused. */
static void test_local_size_by_device_type(void **state)
{
	(void)state;
	saved_env type_env = env_save("DP_CL_DEVICE_TYPE"), local_env = env_save("DP_CL_LOCAL_SIZE"),
		  lanes_env = env_save("DP_CL_LANES");
	dp_cl cl;
	dp_error err = {0};
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	cl_device_type type = 0;
	assert_int_equal(clGetDeviceInfo(cl.device, CL_DEVICE_TYPE, sizeof type, &type, NULL), CL_SUCCESS);
	assert_int_equal(cl.local_size, (type & CL_DEVICE_TYPE_CPU) ? DP_CL_LOCAL_SIZE_CPU : DP_CL_LOCAL_SIZE_GPU);
	dp_cl_close(&cl);

	setenv("DP_CL_DEVICE_TYPE", "gpu", 1);
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	assert_int_equal(cl.local_size, DP_CL_LOCAL_SIZE_GPU);
	assert_int_equal(cl.lanes, DP_CL_LANES_GPU);
	size_t limit = 0;
	cl_kernel k;
	assert_int_equal(dp_cl_kernel(&cl, "wlop_density", &k, &err), DP_OK);
	assert_int_equal(clGetKernelWorkGroupInfo(k, cl.device, CL_KERNEL_WORK_GROUP_SIZE, sizeof limit, &limit, NULL),
			 CL_SUCCESS);
	assert_int_equal(kernel_local_size(&cl, "wlop_density"),
			 limit < DP_CL_LOCAL_SIZE_GPU ? limit : DP_CL_LOCAL_SIZE_GPU);
	dp_cl_close(&cl);
	setenv("DP_CL_DEVICE_TYPE", "cpu", 1);
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	assert_int_equal(cl.local_size, DP_CL_LOCAL_SIZE_CPU);
	assert_int_equal(cl.lanes, DP_CL_LANES_CPU);
	dp_cl_close(&cl);
	setenv("DP_CL_DEVICE_TYPE", "tpu", 1);
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_ERR_ARG);
	assert_non_null(strstr(err.message, "DP_CL_DEVICE_TYPE"));
	unsetenv("DP_CL_DEVICE_TYPE");

	setenv("DP_CL_LOCAL_SIZE", "32", 1);
	assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_OK);
	assert_int_equal(cl.local_size, 32);
	dp_cl_close(&cl);
	const char *bad[] = {"0", "-64", "64x", "100000"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		setenv("DP_CL_LOCAL_SIZE", bad[i], 1);
		assert_int_equal(dp_cl_open(&cl, NULL, &err), DP_ERR_ARG);
		assert_non_null(strstr(err.message, "DP_CL_LOCAL_SIZE"));
	}
	env_restore(&type_env);
	env_restore(&local_env);
	env_restore(&lanes_env);
}

/* Any size up to DP_CL_LOCAL_SIZE_MAX runs, a power of two or not, within
 * the kernel's own limit (PoCL's, 4096, is above every size allowed, so the
 * limit itself cannot bind here). */
static void test_odd_local_size_runs(void **state)
{
	(void)state;
	saved_env local_env = env_save("DP_CL_LOCAL_SIZE");
	const char *src = "__kernel void twice(const uint n, __global const float *x, __global float *out)\n"
			  "{ uint i = get_global_id(0); if (i < n) out[i] = 2.0f * x[i]; }\n";
	dp_cl cl;
	dp_error err = {0};
	setenv("DP_CL_LOCAL_SIZE", "96", 1);
	assert_int_equal(dp_cl_open_source(&cl, NULL, src, DP_CL_BUILD_OPTIONS, &err), DP_OK);
	enum { N = 1000 };
	static float x[N], out[N];
	for (int i = 0; i < N; i++)
		x[i] = (float)i;
	dp_cl_arg args[] = {DP_CL_IN(x, sizeof x), DP_CL_OUT(out, sizeof out)};
	if (dp_cl_launch(&cl, "twice", N, args, 2, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t limit = 0;
	assert_int_equal(clGetKernelWorkGroupInfo(cl.kernels[0].kernel, cl.device, CL_KERNEL_WORK_GROUP_SIZE,
						  sizeof limit, &limit, NULL),
			 CL_SUCCESS);
	assert_int_equal(cl.kernels[0].local, limit < 96 ? limit : 96);
	assert_true(out[999] == 1998.0f && out[0] == 0.0f);
	dp_cl_close(&cl);
	env_restore(&local_env);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_lists_pocl),
		cmocka_unit_test(test_choose_by_index_and_name),
		cmocka_unit_test(test_build_failure_prints_log),
		cmocka_unit_test(test_embedded_program_builds_and_errors_are_named),
		cmocka_unit_test(test_buffers_stay_on_the_device),
		cmocka_unit_test(test_lanes_forced),
		cmocka_unit_test(test_local_size_by_device_type),
		cmocka_unit_test(test_odd_local_size_runs),
	};
	int rc = cmocka_run_group_tests(tests, NULL, NULL);
	tk_teardown_contexts(NULL);
	return rc;
}
