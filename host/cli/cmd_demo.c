/* dpoints demo: a built-in shape with tubes and flat parts, scanned from two
 * sides with noise, consolidated, evaluated against its exact surface and
 * rendered — the whole product in one command, with no input file. */
#include "cli/consolidate.h"
#include "core/common.h"

#include <string.h>

typedef struct demo_eval {
	dp_eval_result before, after, wlop;
} demo_eval;

static void json_eval(json_writer *w, const char *key, const dp_eval_result *e)
{
	json_object(w, key);
	json_int(w, "points", (long long)e->points);
	json_num(w, "accuracy_mean", e->accuracy_mean);
	json_num(w, "accuracy_p95", e->accuracy_p95);
	json_num(w, "completeness_mean", e->completeness_mean);
	json_num(w, "coverage", e->coverage);
	json_num(w, "spacing_cv", e->spacing_cv);
	json_num(w, "scatter_median", e->scatter_median);
	if (e->has_normals) {
		json_num(w, "normal_angle_deg", e->normal_angle_deg);
		json_num(w, "normal_flipped", e->normal_flipped);
		json_num(w, "normal_flipped_clear", e->normal_flipped_clear);
	}
	json_end_object(w);
}

static void fill_eval(json_writer *w, const void *arg)
{
	const demo_eval *d = arg;
	json_object(w, NULL);
	json_str(w, "units", "bounding-box diagonals of the ground-truth mesh");
	json_eval(w, "input_scan", &d->before);
	json_eval(w, "wlop", &d->wlop);
	json_eval(w, "surface", &d->after);
	json_end_object(w);
}

static void print_row(const char *name, const dp_eval_result *e)
{
	printf("  %-12s %8zu %10.5f %10.5f %12.5f %9.3f %8.3f %8.3f", name, e->points, e->accuracy_mean,
	       e->accuracy_p95, e->completeness_mean, e->coverage, e->spacing_cv, e->scatter_median);
	if (e->has_normals)
		printf(" %9.2f %8.4f\n", e->normal_angle_deg, e->normal_flipped);
	else
		printf(" %9s %8s\n", "-", "-");
}

int dp_cmd_demo(int argc, char **argv)
{
	const char *cmd = "demo";
	const char *outdir = "demo-out", *device = NULL, *shape_name = "chair";
	int backend = 0, quiet = 0;
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = 2;
	sp.res = 256;
	sp.noise = 0.003;
	sp.normals = 0;
	dp_consolidate_job job;
	memset(&job, 0, sizeof job);
	dp_params_default(&job.params);
	job.params.wlop.samples = 4000;
	job.render = 1;
	job.save_stages = 1;
	job.up_axis = 2;
	cli_opt opts[] = {
		{"--output", CLI_STRING, &outdir, "output folder", NULL, NULL},
		{"--shape", CLI_STRING, &shape_name, "built-in shape: chair, sphere, cylinder, slab, torus, knot, rods", NULL,
		 NULL},
		{"--views", CLI_INT, &sp.views, "scanner viewpoints", NULL, NULL},
		{"--res", CLI_INT, &sp.res, "rays per view: res x res", NULL, NULL},
		{"--noise", CLI_DOUBLE, &sp.noise, "scan noise sigma, in bounding-box diagonals", NULL, NULL},
		{"--samples", CLI_SIZE, &job.params.wlop.samples, "number of deep points", NULL, NULL},
		{"--seed", CLI_U64, &sp.seed, "scan noise seed", NULL, NULL},
		CLI_BACKEND_OPTS(backend, device),
		{"--quiet", CLI_FLAG, &quiet, "no progress on stderr", NULL, NULL},
	};
	const char *pos[1];
	size_t npos;
	int help;
	int rc = cli_parse(cmd, "[-o OUTDIR] [options]", argc, argv, 2, opts, sizeof opts / sizeof opts[0], pos, 0,
			   &npos, &help);
	if (rc || help)
		return rc;
	if ((rc = cli_check_folder(cmd, outdir, "")) || (rc = dp_cli_mkdir(cmd, outdir)))
		return rc;

	dp_error err = {0};
	dp_shape shape;
	dp_cloud mesh = {0}, scan = {0};
	dp_result res = {0};
	dp_context *ctx = NULL;
	demo_eval ev;
	memset(&ev, 0, sizeof ev);
	char path[4096];
	if (dp_shape_default(shape_name, &shape, &err) != DP_OK || dp_shape_mesh(&shape, &mesh, &err) != DP_OK)
		goto fail;
	if (dp_scan(&mesh, &sp, &scan, NULL, &err) != DP_OK)
		goto fail;
	snprintf(path, sizeof path, "%s/ground_truth.ply", outdir);
	if (dp_cloud_write_ply(path, &mesh, 0, &err) != DP_OK)
		goto fail;
	snprintf(path, sizeof path, "%s/scan.ply", outdir);
	if (dp_cloud_write_ply(path, &scan, 0, &err) != DP_OK)
		goto fail;
	printf("demo: %s (%zu triangles) scanned from %d sides, %dx%d rays, noise %g diagonals: %zu points\n",
	       shape_name, mesh.nfaces, sp.views, sp.res, sp.res, sp.noise, scan.n);

	if ((rc = cli_open_context(cmd, backend, device, &ctx)))
		goto done;
	dp_cli_progress_state progress;
	memset(&progress, 0, sizeof progress);
	if (!quiet) {
		dp_context_set_progress(ctx, dp_cli_progress, &progress);
		job.progress = &progress;
	}
	job.backend_name = backend ? "ref" : "cl";
	job.device_name = dp_context_device_name(ctx);
	dp_consolidate_summary summary;
	memset(&summary, 0, sizeof summary);
	if ((rc = dp_cli_consolidate_cloud(cmd, ctx, &job, &scan, "scan.ply", outdir, &res, &summary)))
		goto done;

	if (dp_eval(&mesh, &scan, NULL, &ev.before, &err) != DP_OK ||
	    dp_eval(&mesh, &res.wlop, NULL, &ev.wlop, &err) != DP_OK ||
	    dp_eval(&mesh, &res.surface, NULL, &ev.after, &err) != DP_OK)
		goto fail;
	snprintf(path, sizeof path, "%s/eval.json", outdir);
	if ((rc = cli_write_json(cmd, path, fill_eval, &ev)))
		goto done;
	printf("\nagainst the exact surface (lengths in bounding-box diagonals):\n");
	printf("  %-12s %8s %10s %10s %12s %9s %8s %8s %9s %8s\n", "", "points", "acc.mean", "acc.p95", "complete",
	       "coverage", "spac.CV", "scatter", "normal°", "flipped");
	print_row("input scan", &ev.before);
	print_row("wlop", &ev.wlop);
	print_row("surface", &ev.after);
	printf("\nfiles in %s/: scan.ply ground_truth.ply wlop.ply anchors.ply skeleton.ply surface.ply dpoints.ply "
	       "report.json eval.json\n  pictures: input.png skeleton.png surface.png dpoints.png\n",
	       outdir);
	rc = DP_EXIT_OK;
	goto done;
fail:
	rc = dp_cli_fail(cmd, &err);
done:
	dp_result_free(&res);
	dp_context_free(ctx);
	dp_cloud_free(&mesh);
	dp_cloud_free(&scan);
	return rc;
}
