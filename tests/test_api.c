/* The library's public surface beside the stages: version, device list as
 * data, progress callbacks that cancel, and dp_result_write. */
#include "testkit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void test_version(void **state)
{
	(void)state;
	char want[64];
	snprintf(want, sizeof want, "%d.%d.%d", DP_VERSION_MAJOR, DP_VERSION_MINOR, DP_VERSION_PATCH);
	assert_string_equal(dp_version(), want);
	assert_string_equal(dp_version(), DP_VERSION_STRING);
	assert_string_equal(dp_status_string(DP_ERR_CANCELLED), "cancelled");
}

static void test_devices(void **state)
{
	(void)state;
	dp_error err = {0};
	dp_device_info *list = NULL;
	size_t n = 0;
	assert_int_equal(dp_devices(&list, &n, &err), DP_OK);
	assert_true(n >= 1); /* PoCL is a required dependency */
	for (size_t i = 0; i < n; i++) {
		assert_int_equal(list[i].index, i);
		assert_true(strlen(list[i].name) > 0);
		assert_true(list[i].type <= DP_DEVICE_OTHER);
		assert_true(list[i].compute_units >= 1);
	}
	/* the index and the name select the device they describe */
	char index[16];
	snprintf(index, sizeof index, "%zu", list[0].index);
	dp_context *ctx = NULL;
	assert_int_equal(dp_context_create(&ctx, DP_BACKEND_CL, index, &err), DP_OK);
	assert_non_null(strstr(list[0].name, dp_context_device_name(ctx)) ? list[0].name
									 : strstr(dp_context_device_name(ctx), list[0].name));
	dp_context_free(ctx);
	dp_devices_free(list);
	assert_int_equal(dp_devices(NULL, &n, &err), DP_ERR_ARG);
	dp_devices_free(NULL);
}

typedef struct cancel_at {
	const char *stage;
	int iteration;
	int calls;
	char last_stage[16];
} cancel_at;

static int cancel_cb(void *user, const char *stage, int iteration, double value, double elapsed)
{
	cancel_at *c = user;
	(void)value;
	(void)elapsed;
	c->calls++;
	snprintf(c->last_stage, sizeof c->last_stage, "%s", stage);
	return strcmp(stage, c->stage) == 0 && iteration >= c->iteration;
}

static void scan_torus(dp_cloud *scan)
{
	tk_scan_shape("torus", 3, 64, 0.003, 1, NULL, NULL, scan);
}

/* Stopping in every stage: the call returns DP_ERR_CANCELLED within the
 * iteration the callback asked in, names the stage, and leaves the result
 * zeroed; the context stays usable. */
static void test_cancel(void **state)
{
	(void)state;
	dp_context *ctx = tk_cl_context();
	dp_cloud scan = {0};
	scan_torus(&scan);
	dp_params params;
	dp_params_default(&params);
	params.wlop.samples = 600;
	const char *stages[] = {"wlop", "sink", "skeleton", "surface"};
	for (int s = 0; s < 4; s++) {
		cancel_at c = {stages[s], 2, 0, ""};
		dp_context_set_progress(ctx, cancel_cb, &c);
		dp_error err = {0};
		dp_result res;
		memset(&res, 0xff, sizeof res);
		assert_int_equal(dp_consolidate(ctx, &scan, &params, &res, &err), DP_ERR_CANCELLED);
		assert_int_equal(err.status, DP_ERR_CANCELLED);
		assert_non_null(strstr(err.message, stages[s]));
		assert_non_null(strstr(err.message, "cancelled"));
		assert_string_equal(c.last_stage, stages[s]);
		assert_null(res.surface.x);
		assert_int_equal(res.surface.n, 0);
		assert_null(res.eta);
	}
	/* a single stage too, and then a full run on the same context */
	cancel_at c = {"wlop", 1, 0, ""};
	dp_context_set_progress(ctx, cancel_cb, &c);
	dp_error err = {0};
	dp_cloud samples = {0};
	assert_int_equal(dp_wlop(ctx, &scan, &params.wlop, &samples, NULL, &err), DP_ERR_CANCELLED);
	assert_int_equal(c.calls, 1);
	assert_null(samples.x);
	dp_context_set_progress(ctx, NULL, NULL);
	assert_int_equal(dp_wlop(ctx, &scan, &params.wlop, &samples, NULL, &err), DP_OK);
	assert_int_equal(samples.n, 600);
	dp_cloud_free(&samples);
	dp_cloud_free(&scan);
}

static int file_size_ok(const char *dir, const char *name)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	FILE *f = fopen(path, "rb");
	if (!f)
		return 0;
	fseek(f, 0, SEEK_END);
	long size = ftell(f);
	fclose(f);
	return size > 0;
}

/* The folder the tool writes, from the library: the PLY files, the report
 * naming what was written, the stages and pictures on request. */
static void test_result_write(void **state)
{
	(void)state;
	dp_context *ctx = tk_cl_context();
	dp_context_set_progress(ctx, NULL, NULL);
	dp_cloud scan = {0};
	scan_torus(&scan);
	dp_params params;
	dp_params_default(&params);
	params.wlop.samples = 600;
	dp_error err = {0};
	dp_result res = {0};
	assert_int_equal(dp_consolidate(ctx, &scan, &params, &res, &err), DP_OK);
	assert_int_equal(res.params.wlop.samples, 600);
	assert_string_equal(res.device, dp_context_device_name(ctx));

	const char *dir = tk_temp_dir();
	assert_int_equal(dp_result_write(&res, dir, NULL, &err), DP_OK);
	const char *files[] = {"surface.ply", "skeleton.ply", "dpoints.ply", "report.json"};
	for (int k = 0; k < 4; k++)
		assert_true(file_size_ok(dir, files[k]));
	assert_false(file_size_ok(dir, "wlop.ply"));
	dp_cloud surface = {0};
	char path[4096];
	snprintf(path, sizeof path, "%s/surface.ply", dir);
	assert_int_equal(dp_cloud_read(path, &surface, DP_READ_POINTS, &err), DP_OK);
	assert_int_equal(surface.n, res.surface.n);
	assert_float_equal(surface.x[7], res.surface.x[7], 0.0f);
	dp_cloud_free(&surface);
	uint32_t *edges = NULL;
	size_t nedges = 0;
	snprintf(path, sizeof path, "%s/dpoints.ply", dir);
	assert_int_equal(dp_ply_read_edges(path, &edges, &nedges, &err), DP_OK);
	assert_int_equal(nedges, res.surface.n);
	assert_int_equal(edges[1], res.surface.n);
	free(edges);

	dp_write_options wo;
	dp_write_options_default(&wo);
	wo.flags = DP_WRITE_STAGES | DP_WRITE_RENDER | DP_WRITE_ASCII;
	wo.input = &scan;
	wo.input_name = "torus scan";
	assert_int_equal(dp_result_write(&res, dir, &wo, &err), DP_OK);
	const char *more[] = {"wlop.ply", "anchors.ply", "input.png", "skeleton.png", "surface.png", "dpoints.png"};
	for (int k = 0; k < 6; k++)
		assert_true(file_size_ok(dir, more[k]));
	snprintf(path, sizeof path, "%s/report.json", dir);
	FILE *f = fopen(path, "r");
	assert_non_null(f);
	char text[65536];
	size_t len = fread(text, 1, sizeof text - 1, f);
	text[len] = '\0';
	fclose(f);
	assert_non_null(strstr(text, "\"input\": \"torus scan\""));
	assert_non_null(strstr(text, "\"anchors.ply\""));
	assert_non_null(strstr(text, "\"dpoints.png\""));
	assert_non_null(strstr(text, "\"samples\": 600"));

	/* errors: nothing to write, a folder that is not there, a bad axis */
	dp_result empty = {0};
	assert_int_equal(dp_result_write(&empty, dir, NULL, &err), DP_ERR_ARG);
	assert_int_equal(dp_result_write(&res, "/nonexistent/folder", NULL, &err), DP_ERR_IO);
	assert_non_null(strstr(err.message, "/nonexistent/folder"));
	wo.up_axis = 3;
	assert_int_equal(dp_result_write(&res, dir, &wo, &err), DP_ERR_ARG);
	dp_result_free(&res);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_version),
		cmocka_unit_test(test_devices),
		cmocka_unit_test(test_cancel),
		cmocka_unit_test(test_result_write),
	};
	return tk_exit_status(cmocka_run_group_tests(tests, NULL, tk_teardown_contexts));
}
