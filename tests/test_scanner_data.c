/* Facing the scanner (host/stages/scanner.h) on a real one-sided scan from
 * the shared data folder; skips when that is absent. */
#include "testkit.h"

#include <math.h>

/* CGAL's hippo1, a one-sided partial scan from the data folder (skipped
 * when absent): its WLOP normals point a tenth the wrong way along the axis
 * found (whole patches on the legs), but its samples lie in one layer along
 * it, so it is one-sided; every sample faces the scanner afterwards, and
 * fewer anchors sink out of the outline than without the rule (169 -> 35
 * when measured). */
static void test_hippo(void **state)
{
	(void)state;
	const char *path = tk_data_path("cgal/hippo1.ply");
	if (!path)
		skip();
	dp_error err = {0};
	dp_cloud scan = {0};
	if (dp_cloud_read(path, &scan, DP_READ_POINTS, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_result with = {0}, without = {0};
	dp_params p;
	dp_params_default(&p);
	if (dp_consolidate(tk_cl_context(), &scan, &p, &with, &err) != DP_OK)
		fail_msg("%s", err.message);
	p.surface.face_scanner = 0;
	if (dp_consolidate(tk_cl_context(), &scan, &p, &without, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double *t = with.surface_stats.scanner;
	printf("hippo1: scanner (%.3f %.3f %.3f), %zu of %zu samples turned; anchors moved back into the outline %zu "
	       "(%zu without)\n",
	       t[0], t[1], t[2], with.samples_turned, with.wlop.n, with.silhouette_capped, without.silhouette_capped);
	assert_true(fabs(sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) - 1.0) < 1e-6);
	assert_true(with.samples_turned * 20 > with.wlop.n);
	for (size_t i = 0; i < with.wlop.n; i++)
		assert_true(with.wlop.nx[i] * t[0] + with.wlop.ny[i] * t[1] + with.wlop.nz[i] * t[2] >=
			    -p.surface.face_scanner_cos);
	assert_true(with.silhouette_capped * 2 < without.silhouette_capped);
	dp_result_free(&with);
	dp_result_free(&without);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_hippo),
	};
	return tk_exit_status(cmocka_run_group_tests(tests, NULL, tk_teardown_contexts));
}
