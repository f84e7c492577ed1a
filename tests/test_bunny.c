/* The real Stanford bunny scans through the library API: views brought into
 * the ground-truth frame with bun.conf, consolidated (one view, two views)
 * and evaluated against bun_zipper_res2.ply before and after. Prints the
 * numbers; skips when the shared data folder is absent. */
#include "testkit.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* A raw view lands on the mesh when its mean distance to it is below this
 * (units of the mesh's bbox diagonal). Measured with the right pose: 6.1e-4
 * to 6.4e-4 for bun000/090/180 (scanner noise plus the decimation of
 * res2); a wrong rotation puts bun090 at 0.09. */
#define LANDED_ACCURACY 1e-3

/* Deep points for the consolidations: the paper's default is 10% of the
 * input (4000-8000 here); 1000 are kept from the coarse level's 4000
 * (dp_refine_params), a few seconds a run on 2 CPU cores. */
#define BUNNY_SAMPLES 1000

/* Coverage must be "well above" the input's. The rule: consolidation at
 * least halves the uncovered fraction, 1 - after <= (1 - before) / 2.
 * Measured with BUNNY_SAMPLES = 1000: one view 0.378 -> 0.977 (the rule asks
 * 0.689: more than any one-sided view of a closed object can cover, about
 * half), two views 0.745 -> 0.998 (the rule asks 0.873). */
#define UNCOVERED_KEPT_AT_MOST 0.5

typedef struct pose {
	double t[3], q[4]; /* translation, quaternion x y z w */
} pose;

/* The `bmesh NAME tx ty tz qx qy qz qw` line of bun.conf for `name`. */
static void read_pose(const char *conf, const char *name, pose *p)
{
	FILE *f = fopen(conf, "r");
	char line[512], file[256];
	int found = 0;
	assert_non_null(f);
	while (!found && fgets(line, sizeof line, f))
		found = sscanf(line, "bmesh %255s %lf %lf %lf %lf %lf %lf %lf", file, &p->t[0], &p->t[1], &p->t[2],
			       &p->q[0], &p->q[1], &p->q[2], &p->q[3]) == 8 &&
			strcmp(file, name) == 0;
	fclose(f);
	if (!found)
		fail_msg("%s: no bmesh line for %s", conf, name);
}

/* world = M p + t with M = R(q)ᵀ (transposed) or R(q), R(q) the rotation of
 * the unit quaternion q = (x, y, z, w). bun.conf's convention is R(q)ᵀ:
 * test_pose_convention shows it numerically. */
static void apply_pose(dp_cloud *c, const pose *p, int transposed)
{
	double x = p->q[0], y = p->q[1], z = p->q[2], w = p->q[3];
	double r[3][3] = {
		{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
		{2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
		{2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)},
	};
	for (size_t i = 0; i < c->n; i++) {
		double v[3] = {c->x[i], c->y[i], c->z[i]}, o[3];
		for (int a = 0; a < 3; a++) {
			o[a] = p->t[a];
			for (int b = 0; b < 3; b++)
				o[a] += (transposed ? r[b][a] : r[a][b]) * v[b];
		}
		c->x[i] = (float)o[0];
		c->y[i] = (float)o[1];
		c->z[i] = (float)o[2];
	}
}

/* Paths in the shared data folder, or NULL (the test skips). */
typedef struct bunny_data {
	char conf[8192], mesh[8192];
} bunny_data;

static int find_data(bunny_data *d)
{
	const char *p = tk_data_path("stanford-bunny/bun.conf");
	if (!p)
		return 0;
	snprintf(d->conf, sizeof d->conf, "%s", p);
	if (!(p = tk_data_path("stanford-bunny/bun_zipper_res2.ply")))
		return 0;
	snprintf(d->mesh, sizeof d->mesh, "%s", p);
	return 1;
}

/* Reads view `name` into `view`, in the ground-truth frame (R(q)ᵀ when
 * `transposed`, else R(q)); 0 when the file is absent. */
static int read_view(const bunny_data *d, const char *name, int transposed, dp_cloud *view)
{
	char rel[256];
	snprintf(rel, sizeof rel, "stanford-bunny/%s", name);
	const char *path = tk_data_path(rel);
	if (!path)
		return 0;
	dp_error err = {0};
	if (dp_cloud_read(path, view, DP_READ_POINTS, &err) != DP_OK)
		fail_msg("%s", err.message);
	pose p;
	read_pose(d->conf, name, &p);
	apply_pose(view, &p, transposed);
	return 1;
}

static void read_mesh(const bunny_data *d, dp_cloud *mesh)
{
	dp_error err = {0};
	if (dp_cloud_read(d->mesh, mesh, DP_READ_MESH, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_true(mesh->nfaces > 0);
}

static void eval(const dp_cloud *mesh, const dp_cloud *points, double coverage_factor, dp_eval_result *r)
{
	dp_eval_params ep;
	dp_eval_params_default(&ep);
	if (coverage_factor > 0)
		ep.coverage_factor = coverage_factor;
	dp_error err = {0};
	if (dp_eval(mesh, points, &ep, r, &err) != DP_OK)
		fail_msg("%s", err.message);
}

static void print_row(const char *what, const dp_eval_result *r, double coverage_same_radius)
{
	char normals[64] = "none";
	if (r->has_normals)
		snprintf(normals, sizeof normals, "%.1f deg, %.1f%% flipped", r->normal_angle_deg,
			 100.0 * r->normal_flipped);
	printf("  %-22s %6zu points  accuracy %.5f (p95 %.5f)  coverage %.3f (radius %.4f; %.3f at the "
	       "output's radius)  completeness %.4f  normals %s\n",
	       what, r->points, r->accuracy_mean, r->accuracy_p95, r->coverage, r->coverage_radius,
	       coverage_same_radius, r->completeness_mean, normals);
}

/* Glues b's points after a's into `out`. */
static void concat(const dp_cloud *a, const dp_cloud *b, dp_cloud *out)
{
	dp_error err = {0};
	if (dp_cloud_alloc(out, a->n + b->n, 0, &err) != DP_OK)
		fail_msg("%s", err.message);
	memcpy(out->x, a->x, a->n * sizeof(float));
	memcpy(out->y, a->y, a->n * sizeof(float));
	memcpy(out->z, a->z, a->n * sizeof(float));
	memcpy(out->x + a->n, b->x, b->n * sizeof(float));
	memcpy(out->y + a->n, b->y, b->n * sizeof(float));
	memcpy(out->z + a->n, b->z, b->n * sizeof(float));
}

/* bun.conf's pose is world = R(q)ᵀ p + t: with it the 90° view lands on the
 * ground-truth mesh; with R(q) it does not. (bun000 has the identity and
 * bun180 a half turn, for which R and Rᵀ nearly agree: they cannot tell.) */
static void test_pose_convention(void **state)
{
	(void)state;
	bunny_data d;
	dp_cloud mesh = {0}, right = {0}, wrong = {0};
	if (!find_data(&d) || !read_view(&d, "bun090.ply", 1, &right) || !read_view(&d, "bun090.ply", 0, &wrong))
		skip();
	read_mesh(&d, &mesh);
	dp_eval_result rt, r;
	eval(&mesh, &right, 0, &rt);
	eval(&mesh, &wrong, 0, &r);
	printf("bun090 mean distance to the mesh: %.5f diagonals with R(q)^T, %.5f with R(q)\n", rt.accuracy_mean,
	       r.accuracy_mean);
	assert_true(rt.accuracy_mean < LANDED_ACCURACY);
	assert_true(r.accuracy_mean > 10 * LANDED_ACCURACY);
	dp_cloud_free(&mesh);
	dp_cloud_free(&right);
	dp_cloud_free(&wrong);
}

/* Consolidates `in` and checks and prints the numbers before and after. */
static void consolidate_and_compare(const char *label, const dp_cloud *mesh, const dp_cloud *in)
{
	dp_eval_result before, wlop, after, before_same, wlop_same;
	eval(mesh, in, 0, &before);
	/* the views must sit on the mesh, or nothing below means anything */
	assert_true(before.accuracy_mean < LANDED_ACCURACY);

	dp_params params;
	dp_params_default(&params);
	params.wlop.samples = BUNNY_SAMPLES;
	dp_result res = {0};
	dp_error err = {0};
	if (dp_consolidate(tk_cl_context(), in, &params, &res, &err) != DP_OK)
		fail_msg("%s", err.message);
	assert_int_equal(res.surface.n, BUNNY_SAMPLES);
	eval(mesh, &res.wlop, 0, &wlop);
	eval(mesh, &res.surface, 0, &after);
	/* Coverage is relative to each set's own spacing, and the consolidated
	 * points are 15-20 times sparser than the raw scan: also measure the
	 * input at the output's absolute radius, to show how much of the gain
	 * is completion rather than a wider radius. */
	eval(mesh, in, after.coverage_radius / before.spacing_mean, &before_same);
	eval(mesh, &res.wlop, after.coverage_radius / wlop.spacing_mean, &wlop_same);

	printf("%s (lengths in diagonals of the mesh's bbox, %.4f; %.1f s on %s)\n", label, before.diagonal,
	       res.seconds_total, dp_context_device_name(tk_cl_context()));
	print_row("input", &before, before_same.coverage);
	print_row("WLOP samples", &wlop, wlop_same.coverage);
	print_row("consolidated surface", &after, after.coverage);

	assert_true(1.0 - after.coverage <= UNCOVERED_KEPT_AT_MOST * (1.0 - before.coverage));
	/* at the same absolute radius the output must not cover less either
	 * (measured 0.629 -> 0.943 for one view, 0.948 -> 0.983 for two: with
	 * both sides scanned, little is more than that radius from the input) */
	assert_true(after.coverage >= before_same.coverage);
	dp_result_free(&res);
}

static void test_one_view(void **state)
{
	(void)state;
	bunny_data d;
	dp_cloud mesh = {0}, view = {0};
	if (!find_data(&d) || !read_view(&d, "bun000.ply", 1, &view))
		skip();
	read_mesh(&d, &mesh);
	consolidate_and_compare("bun000 (one view)", &mesh, &view);
	dp_cloud_free(&mesh);
	dp_cloud_free(&view);
}

/* The one view at the default deep-point count, with the medial test's
 * margin growing with depth (the default) and fixed at 1 r (its old
 * default): the body must sink deeper and its completion cover more. The
 * test fires when a sample of the visible shell comes nearer to the inner
 * point than its own surface point; here that witness is the same shell
 * curving away (median 56 degrees from the sinking direction, normals 52
 * degrees apart), and the gap it measures shifts by about depth x the
 * sinking line's direction error, so a fixed margin stopped the points it
 * settled at a median 14.6 r (19.1 r with the fraction; the coarse level's
 * r). Measured: coverage 0.841 -> 0.855, anchors' mean depth 10.3 -> 10.9 r;
 * over WLOP seeds 1-6 coverage 0.819 -> 0.848. (Before a fragment of the
 * hind foot took its orientation from the body, dp_orient_outward, its
 * inward normals cost the fixed margin more: 0.802 -> 0.843 here, 0.797 ->
 * 0.831 over the six seeds; the gain asked was 0.02.) With the scan's
 * outline (dp_surface_params.silhouette, its margin 2.5 r): 0.816 -> 0.860,
 * 10.11 -> 10.66 r. */
#define DEPTH_COVERAGE_GAIN 0.01

static double one_view_coverage(const dp_cloud *mesh, const dp_cloud *view, double margin_r, double fraction,
				double *mean_depth_r)
{
	dp_params params;
	dp_params_default(&params);
	params.sink.medial_margin_r = margin_r;
	params.sink.medial_fraction = fraction;
	/* the surface stage from every deep point, as measured above */
	params.refine.fill_samples = 0;
	dp_result res = {0};
	dp_error err = {0};
	if (dp_consolidate(tk_cl_context(), view, &params, &res, &err) != DP_OK)
		fail_msg("%s", err.message);
	dp_eval_result e;
	eval(mesh, &res.surface, 0, &e);
	double depth = 0;
	for (size_t i = 0; i < res.anchors.n; i++) {
		double dx = res.anchors.x[i] - res.wlop.x[i], dy = res.anchors.y[i] - res.wlop.y[i],
		       dz = res.anchors.z[i] - res.wlop.z[i];
		depth += sqrt(dx * dx + dy * dy + dz * dz);
	}
	*mean_depth_r = depth / (double)res.anchors.n / res.sink_r;
	printf("medial margin %.2f r + %.2f x depth: %zu deep points, anchors' mean depth %.2f r, coverage %.4f\n",
	       margin_r, fraction, res.surface.n, *mean_depth_r, e.coverage);
	dp_result_free(&res);
	return e.coverage;
}

static void test_one_view_depth(void **state)
{
	(void)state;
	bunny_data d;
	dp_cloud mesh = {0}, view = {0};
	if (!find_data(&d) || !read_view(&d, "bun000.ply", 1, &view))
		skip();
	read_mesh(&d, &mesh);
	dp_sink_params defaults;
	dp_sink_params_default(&defaults);
	double grown_depth, fixed_depth;
	double grown = one_view_coverage(&mesh, &view, defaults.medial_margin_r, defaults.medial_fraction, &grown_depth);
	double fixed = one_view_coverage(&mesh, &view, 1.0, 0.0, &fixed_depth);
	assert_true(grown_depth > fixed_depth);
	assert_true(grown >= fixed + DEPTH_COVERAGE_GAIN);
	dp_cloud_free(&mesh);
	dp_cloud_free(&view);
}

/* The mesh and bun000 + bun180 as one scan, or a skip without the data. */
static void read_two_views(dp_cloud *mesh, dp_cloud *both)
{
	bunny_data d;
	dp_cloud front = {0}, back = {0};
	if (!find_data(&d) || !read_view(&d, "bun000.ply", 1, &front) || !read_view(&d, "bun180.ply", 1, &back)) {
		dp_cloud_free(&front);
		skip();
	}
	read_mesh(&d, mesh);
	concat(&front, &back, both);
	dp_cloud_free(&front);
	dp_cloud_free(&back);
}

static void test_two_views(void **state)
{
	(void)state;
	dp_cloud mesh = {0}, both = {0};
	read_two_views(&mesh, &both);
	consolidate_and_compare("bun000 + bun180 (two views)", &mesh, &both);
	dp_cloud_free(&mesh);
	dp_cloud_free(&both);
}

/* The side view bun270 at the defaults, with and without the scan's outline
 * (dp_surface_params.silhouette). Its feet's tops face up with the soles never
 * scanned, so without the outline their anchors sink out below the base and
 * the completion hangs a skirt there: measured at WLOP seed 1, 243 of 4000
 * points more than 0.02 diagonals below the base (the deepest 0.23); with
 * it 4 (the same at the outline's margins of 3 r and 2.5 r), 340 anchors
 * moved back into the outline. The axis found lies 3 degrees from the
 * view's (x). */
#define SKIRT_DEPTH 0.02
#define SKIRT_AT_MOST 0.01
#define SKIRT_WITHOUT_AT_LEAST 0.03

static size_t below_base(const dp_cloud *mesh, const dp_cloud *points, double depth)
{
	double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
	for (size_t i = 0; i < mesh->n; i++) {
		const double v[3] = {mesh->x[i], mesh->y[i], mesh->z[i]};
		for (int c = 0; c < 3; c++)
			lo[c] = fmin(lo[c], v[c]), hi[c] = fmax(hi[c], v[c]);
	}
	double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
			   (hi[2] - lo[2]) * (hi[2] - lo[2]));
	size_t count = 0;
	for (size_t i = 0; i < points->n; i++)
		count += lo[1] - points->y[i] > depth * diag;
	return count;
}

static void test_side_view_outline(void **state)
{
	(void)state;
	bunny_data d;
	dp_cloud mesh = {0}, view = {0};
	if (!find_data(&d) || !read_view(&d, "bun270.ply", 1, &view))
		skip();
	read_mesh(&d, &mesh);
	dp_params p;
	dp_params_default(&p);
	dp_result on = {0}, off = {0};
	dp_error err = {0};
	if (dp_consolidate(tk_cl_context(), &view, &p, &on, &err) != DP_OK)
		fail_msg("%s", err.message);
	p.surface.silhouette = 0;
	if (dp_consolidate(tk_cl_context(), &view, &p, &off, &err) != DP_OK)
		fail_msg("%s", err.message);
	const double *a = on.surface_stats.silhouette_axis;
	size_t skirt_on = below_base(&mesh, &on.surface, SKIRT_DEPTH), skirt_off = below_base(&mesh, &off.surface, SKIRT_DEPTH);
	dp_eval_result e_on, e_off;
	eval(&mesh, &on.surface, 0, &e_on);
	eval(&mesh, &off.surface, 0, &e_off);
	printf("bun270: axis (%.3f %.3f %.3f), %zu anchors moved back in; points more than %.2f diagonals below the base "
	       "%zu of %zu (without the outline %zu); 95th percentile %.4f (%.4f)\n",
	       a[0], a[1], a[2], on.silhouette_capped, SKIRT_DEPTH, skirt_on, on.surface.n, skirt_off,
	       e_on.accuracy_p95, e_off.accuracy_p95);
	assert_true(fabs(a[0]) > cos(10.0 * M_PI / 180.0));
	assert_true(skirt_off >= SKIRT_WITHOUT_AT_LEAST * (double)off.surface.n);
	assert_true(skirt_on <= SKIRT_AT_MOST * (double)on.surface.n);
	assert_true(e_on.accuracy_p95 < e_off.accuracy_p95);
	dp_result_free(&on);
	dp_result_free(&off);
	dp_cloud_free(&mesh);
	dp_cloud_free(&view);
}

/* The two views bun000 + bun180 at the defaults: neither sees the base,
 * whose completion the volume prior bulges out as far as the outline lets
 * it. The true surface lies within 1.4 r of the scans' outline; measured at
 * WLOP seed 1, 196 of 8051 points hung more than 0.02 diagonals below the
 * base with the outline grown by 3 r, 64 with the default 2.5 r. */
#define BASE_BULGE_AT_MOST 0.015

static void test_two_views_base(void **state)
{
	(void)state;
	dp_cloud mesh = {0}, both = {0};
	read_two_views(&mesh, &both);
	dp_result res = {0};
	dp_error err = {0};
	if (dp_consolidate(tk_cl_context(), &both, NULL, &res, &err) != DP_OK)
		fail_msg("%s", err.message);
	size_t bulge = below_base(&mesh, &res.surface, SKIRT_DEPTH);
	printf("bun000 + bun180: %zu of %zu points more than %.2f diagonals below the base\n", bulge, res.surface.n,
	       SKIRT_DEPTH);
	assert_true(bulge <= BASE_BULGE_AT_MOST * (double)res.surface.n);
	dp_result_free(&res);
	dp_cloud_free(&mesh);
	dp_cloud_free(&both);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_pose_convention),
		cmocka_unit_test(test_one_view),
		cmocka_unit_test(test_one_view_depth),
		cmocka_unit_test(test_two_views),
		cmocka_unit_test(test_side_view_outline),
		cmocka_unit_test(test_two_views_base),
	};
	return tk_exit_status(cmocka_run_group_tests(tests, NULL, tk_teardown_contexts));
}
