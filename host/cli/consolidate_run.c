/* One consolidate run: the pipeline, its output files and its report. */
#include "cli/consolidate.h"
#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct report_arg {
	const dp_consolidate_job *job;
	const char *input, *dir;
	const dp_result *res;
} report_arg;

static void json_sink_params(json_writer *w, const dp_sink_params *p)
{
	json_object(w, "sink");
	json_num(w, "sigma_p", p->sigma_p);
	json_num(w, "settle_radius_r", p->settle_radius_r);
	json_num(w, "front_factor", p->front_factor);
	json_num(w, "omega_deg", p->omega_deg);
	json_num(w, "first_step_r", p->first_step_r);
	json_num(w, "slow_fraction", p->slow_fraction);
	json_int(w, "max_iters", p->max_iters);
	json_num(w, "medial_margin_r", p->medial_margin_r);
	json_end_object(w);
}

static void json_skeleton_params(json_writer *w, const dp_skeleton_params *p)
{
	json_object(w, "skeleton");
	json_num(w, "sigma_q", p->sigma_q);
	json_num(w, "eps", p->eps);
	json_num(w, "mu", p->mu);
	json_num(w, "cutoff", p->cutoff);
	json_num(w, "min_axis_weight", p->min_axis_weight);
	json_int(w, "max_iters", p->max_iters);
	json_int(w, "window", p->window);
	json_num(w, "min_drop", p->min_drop);
	json_num(w, "min_move_r", p->min_move_r);
	json_end_object(w);
}

static void json_surface_params(json_writer *w, const dp_surface_params *p)
{
	json_object(w, "surface");
	json_num(w, "sigma_p", p->sigma_p);
	json_num(w, "mu_hat", p->mu_hat);
	json_str(w, "prior", p->prior == DP_SURFACE_PRIOR_MINIMAL ? "minimal" : "volume");
	json_num(w, "tangent_floor_r", p->tangent_floor_r);
	json_str(w, "data_term", p->data_along_normal ? "normal" : "full");
	json_num(w, "normal_radius_r", p->normal_radius_r);
	json_bool(w, "reattach", p->reattach);
	json_num(w, "reattach_radius_r", p->reattach_radius_r);
	json_int(w, "max_iters", p->max_iters);
	json_int(w, "window", p->window);
	json_num(w, "min_drop", p->min_drop);
	json_num(w, "min_growth", p->min_growth);
	json_bool(w, "same_side", p->same_side);
	json_bool(w, "orient_by_dpoint", p->orient_by_dpoint);
	json_end_object(w);
}

static void json_refine_params(json_writer *w, const dp_refine_params *p)
{
	json_object(w, "refine");
	json_int(w, "coarse_samples", (long long)p->coarse_samples);
	json_num(w, "level_factor", p->level_factor);
	json_int(w, "level_iters", p->level_iters);
	json_int(w, "samples_floor", (long long)p->samples_floor);
	json_end_object(w);
}

/* Whether a run of `job` writes the result file `name` (report.json aside). */
static int result_file_written(const dp_consolidate_job *job, const char *name)
{
	if (strcmp(name, "report.json") == 0)
		return 0;
	if (strcmp(name, "wlop.ply") == 0 || strcmp(name, "anchors.ply") == 0)
		return job->save_stages;
	if (strstr(name, ".png"))
		return job->render;
	return 1;
}

static void fill_report(json_writer *w, const void *varg)
{
	const report_arg *a = varg;
	const dp_result *r = a->res;
	json_object(w, NULL);
	json_str(w, "command", "consolidate");
	json_str(w, "input", a->input);
	json_str(w, "output", a->dir);
	json_str(w, "backend", a->job->backend_name);
	json_str(w, "device", a->job->device_name);
	json_object(w, "parameters");
	dp_cli_json_wlop_params(w, &a->job->params.wlop);
	dp_cli_json_normal_params(w, &a->job->params.normals);
	json_sink_params(w, &a->job->params.sink);
	json_skeleton_params(w, &a->job->params.skeleton);
	json_surface_params(w, &a->job->params.surface);
	json_refine_params(w, &a->job->params.refine);
	json_end_object(w);
	json_object(w, "results");
	json_int(w, "points_in", (long long)r->points_in);
	json_int(w, "deep_points", (long long)r->surface.n);
	json_num(w, "r", r->r);
	json_object(w, "wlop");
	json_num(w, "h", r->wlop_stats.h);
	json_int(w, "iterations", r->wlop_stats.iterations);
	json_bool(w, "converged", r->wlop_stats.converged);
	json_bool(w, "stalled", r->wlop_stats.stalled);
	json_num(w, "last_mean_move_h", r->wlop_stats.last_mean_move);
	json_num(w, "last_max_move_h", r->wlop_stats.last_max_move);
	json_num(w, "seconds", r->wlop_stats.seconds_density + r->wlop_stats.seconds_iterations);
	json_num(w, "pair_evaluations", r->wlop_stats.pair_evaluations);
	json_end_object(w);
	json_object(w, "normals");
	json_num(w, "seconds", r->seconds_normals);
	json_end_object(w);
	json_object(w, "sink");
	json_int(w, "iterations", r->sink_stats.iterations);
	json_int(w, "settled_front", (long long)r->sink_stats.settled_front);
	json_int(w, "settled_medial", (long long)r->sink_stats.settled_medial);
	json_int(w, "settled_slow", (long long)r->sink_stats.settled_slow);
	json_int(w, "unsettled", (long long)r->sink_stats.unsettled);
	json_num(w, "seconds", r->sink_stats.seconds);
	json_num(w, "pair_evaluations", r->sink_stats.pair_evaluations);
	json_end_object(w);
	json_object(w, "skeleton");
	json_int(w, "iterations", r->skeleton_stats.iterations);
	json_bool(w, "converged", r->skeleton_stats.converged);
	json_num(w, "last_mean_move_r", r->skeleton_stats.last_mean_move);
	json_num(w, "seconds", r->skeleton_stats.seconds);
	json_num(w, "pair_evaluations", r->skeleton_stats.pair_evaluations);
	json_end_object(w);
	json_object(w, "surface");
	json_int(w, "iterations", r->surface_stats.iterations);
	json_bool(w, "converged", r->surface_stats.converged);
	json_num(w, "last_mean_move_r", r->surface_stats.last_mean_move);
	json_num(w, "spacing_growth", r->surface_stats.spacing_growth);
	json_int(w, "reattached", (long long)r->surface_stats.reattached);
	json_int(w, "normals_disagreeing", (long long)r->surface_stats.normals_disagreeing);
	json_num(w, "seconds", r->surface_stats.seconds);
	json_num(w, "pair_evaluations", r->surface_stats.pair_evaluations);
	json_array(w, "levels");
	for (int l = 0; l < r->levels; l++) {
		json_object(w, NULL);
		json_int(w, "points", (long long)r->level[l].points);
		json_num(w, "r", r->level[l].r);
		json_int(w, "iterations", r->level[l].iterations);
		json_num(w, "seconds", r->level[l].seconds);
		json_num(w, "pair_evaluations", r->level[l].pair_evaluations);
		json_end_object(w);
	}
	json_end_array(w);
	json_end_object(w);
	json_num(w, "seconds_total", r->seconds_total);
	json_end_object(w);
	/* what --skip-done checks for: the folder is complete when all are there */
	json_array(w, "files");
	for (int k = 0; dp_cli_result_files[k]; k++)
		if (result_file_written(a->job, dp_cli_result_files[k]))
			json_str(w, NULL, dp_cli_result_files[k]);
	json_end_array(w);
	json_end_object(w);
}

static dp_status write_outputs(const dp_consolidate_job *job, const dp_cloud *in, const dp_result *r,
			       const char *dir, dp_error *err)
{
	char path[4096];
	size_t n = r->surface.n;
	dp_status st;
	const dp_ply_property surface_props[] = {
		{"x", r->surface.x},   {"y", r->surface.y},   {"z", r->surface.z},
		{"nx", r->surface.nx}, {"ny", r->surface.ny}, {"nz", r->surface.nz},
		{"length", r->length}, {"eta", r->eta},
	};
	snprintf(path, sizeof path, "%s/surface.ply", dir);
	if ((st = dp_ply_write(path, n, surface_props, 8, NULL, 0, NULL, 0, job->ascii, err)) != DP_OK)
		return st;
	const dp_ply_property skeleton_props[] = {{"x", r->skeleton.x}, {"y", r->skeleton.y}, {"z", r->skeleton.z}};
	snprintf(path, sizeof path, "%s/skeleton.ply", dir);
	if ((st = dp_ply_write(path, n, skeleton_props, 3, NULL, 0, NULL, 0, job->ascii, err)) != DP_OK)
		return st;

	/* deep points: surface ends 0..n-1, inner ends n..2n-1, edge i joins i and n+i */
	float *xyz = dp_alloc_array(6 * n, sizeof(float));
	uint32_t *edges = dp_alloc_array(2 * n, sizeof(uint32_t));
	if (!xyz || !edges) {
		free(xyz);
		free(edges);
		return dp_fail(err, DP_ERR_NOMEM, "out of memory writing %zu deep points", n);
	}
	float *x = xyz, *y = xyz + 2 * n, *z = xyz + 4 * n;
	for (size_t i = 0; i < n; i++) {
		x[i] = r->surface.x[i];
		y[i] = r->surface.y[i];
		z[i] = r->surface.z[i];
		x[n + i] = r->skeleton.x[i];
		y[n + i] = r->skeleton.y[i];
		z[n + i] = r->skeleton.z[i];
		edges[2 * i] = (uint32_t)i;
		edges[2 * i + 1] = (uint32_t)(n + i);
	}
	const dp_ply_property dp_props[] = {{"x", x}, {"y", y}, {"z", z}};
	snprintf(path, sizeof path, "%s/dpoints.ply", dir);
	st = dp_ply_write(path, 2 * n, dp_props, 3, edges, n, NULL, 0, job->ascii, err);
	if (st == DP_OK && job->render)
		st = dp_cli_render_result(in, r, x, y, z, edges, job->up_axis, dir, err);
	free(xyz);
	free(edges);
	if (st != DP_OK)
		return st;

	if (job->save_stages) {
		snprintf(path, sizeof path, "%s/wlop.ply", dir);
		if ((st = dp_cloud_write_ply(path, &r->wlop, job->ascii, err)) != DP_OK)
			return st;
		snprintf(path, sizeof path, "%s/anchors.ply", dir);
		if ((st = dp_cloud_write_ply(path, &r->anchors, job->ascii, err)) != DP_OK)
			return st;
	}
	return DP_OK;
}

/* The stages of `r` that stopped at their iteration cap rather than on their
 * test, comma-separated into `out` ("-" when none). A capped stage's output
 * may be unfinished: say so. */
static void capped_stages(const dp_result *r, char *out, size_t size)
{
	const char *names[4] = {"wlop", "sink", "skeleton", "surface"};
	int capped[4] = {!r->wlop_stats.converged, r->sink_stats.unsettled > 0, !r->skeleton_stats.converged,
			 !r->surface_stats.converged};
	size_t len = 0;
	out[0] = '\0';
	for (int k = 0; k < 4; k++)
		if (capped[k])
			len += (size_t)snprintf(out + len, size - len, "%s%s", len ? "," : "", names[k]);
	if (!len)
		snprintf(out, size, "-");
}

int dp_cli_consolidate_cloud(const char *cmd, dp_context *ctx, const dp_consolidate_job *job, const dp_cloud *in,
			     const char *label, const char *dir, dp_result *res, dp_consolidate_summary *summary)
{
	dp_error err = {0};
	int rc;
	summary->points_in = in->n;
	dp_params params = job->params;
	if (job->samples_factor > 0.0)
		params.wlop.samples = (size_t)fmax(1.0, round(job->samples_factor * (double)in->n));
	if (dp_consolidate(ctx, in, &params, res, &err) != DP_OK) {
		dp_cli_name_input(&err, label);
		goto fail;
	}
	/* only now, so that an input the pipeline rejects leaves no folder behind */
	char staging[3072];
	const char *wdir = dir;
	if (job->staged) {
		if ((rc = dp_cli_stage_begin(cmd, dir, staging, sizeof staging)))
			goto fail_rc;
		wdir = staging;
	} else if ((rc = dp_cli_mkdir(cmd, dir))) {
		goto fail_rc;
	}
	if (write_outputs(job, in, res, wdir, &err) != DP_OK) {
		if (job->staged)
			dp_cli_stage_abort(staging);
		goto fail;
	}
	char report[4096];
	snprintf(report, sizeof report, "%s/report.json", wdir);
	report_arg arg = {job, label, dir, res};
	if ((rc = cli_write_json(cmd, report, fill_report, &arg))) {
		if (job->staged)
			dp_cli_stage_abort(staging);
		goto fail_rc;
	}
	if (job->staged && (rc = dp_cli_stage_commit(cmd, dir, staging)))
		goto fail_rc;
	summary->ok = 1;
	summary->points_out = res->surface.n;
	summary->r = res->r;
	summary->seconds = res->seconds_total;
	summary->iterations[0] = res->wlop_stats.iterations;
	summary->iterations[1] = res->sink_stats.iterations;
	summary->iterations[2] = res->skeleton_stats.iterations;
	summary->iterations[3] = res->surface_stats.iterations;
	capped_stages(res, summary->capped, sizeof summary->capped);
	if (strcmp(summary->capped, "-") != 0)
		fprintf(stderr, "dpoints %s: %s: warning: stopped at the iteration cap before converging: %s "
				"(report.json has the numbers; raise --wlop-iters, --sink-iters, --skeleton-iters or "
				"--surface-iters)\n",
			cmd, label, summary->capped);
	if (!job->json_stdout)
		printf("consolidate: %s: %zu points -> %zu deep points, r = %.6g; iterations wlop %d, sink %d (%zu unsettled), "
	       "skeleton %d, surface %d; seconds wlop %.2f, normals %.2f, sink %.2f, skeleton %.2f, surface %.2f, "
	       "total %.2f -> %s\n",
	       label, in->n, res->surface.n, res->r, res->wlop_stats.iterations, res->sink_stats.iterations,
	       res->sink_stats.unsettled, res->skeleton_stats.iterations, res->surface_stats.iterations,
	       res->wlop_stats.seconds_density + res->wlop_stats.seconds_iterations, res->seconds_normals,
	       res->sink_stats.seconds, res->skeleton_stats.seconds, res->surface_stats.seconds, res->seconds_total,
	       dir);
	return 0;
fail:
	rc = dp_cli_fail(cmd, &err);
	snprintf(summary->error, sizeof summary->error, "%s", err.message);
	return rc;
fail_rc:
	snprintf(summary->error, sizeof summary->error, "cannot write into %s", dir);
	return rc;
}

int dp_cli_consolidate_one(const char *cmd, dp_context *ctx, const dp_consolidate_job *job, const char *input,
			   const char *dir, dp_consolidate_summary *summary)
{
	dp_error err = {0};
	dp_cloud in = {0};
	dp_result res = {0};
	if (dp_cloud_read(input, &in, DP_READ_POINTS, &err) != DP_OK) {
		snprintf(summary->error, sizeof summary->error, "%s", err.message);
		return dp_cli_fail(cmd, &err);
	}
	int rc = dp_cli_consolidate_cloud(cmd, ctx, job, &in, input, dir, &res, summary);
	dp_result_free(&res);
	dp_cloud_free(&in);
	return rc;
}

void dp_cli_print_batch_summary(FILE *out, const char *const *inputs, const dp_consolidate_summary *rows, size_t n)
{
	/* whole paths, however long: a cut path may not say which file failed */
	int width = (int)strlen("input"), dwidth = (int)strlen("device");
	for (size_t i = 0; i < n; i++) {
		if ((int)strlen(inputs[i]) > width)
			width = (int)strlen(inputs[i]);
		if ((int)strlen(rows[i].device) > dwidth)
			dwidth = (int)strlen(rows[i].device);
	}
	size_t ok = 0, skipped = 0;
	double seconds = 0.0;
	fprintf(out, "\n%-*s %8s %8s %10s %18s %8s %-24s %-*s  %s\n", width, "input", "points", "dpoints", "r",
		"iters w/s/k/s", "seconds", "capped", dwidth, "device", "status");
	for (size_t i = 0; i < n; i++) {
		const dp_consolidate_summary *s = &rows[i];
		const char *device = s->device[0] ? s->device : "-";
		if (s->ok) {
			char iters[64];
			snprintf(iters, sizeof iters, "%d/%d/%d/%d", s->iterations[0], s->iterations[1],
				 s->iterations[2], s->iterations[3]);
			fprintf(out, "%-*s %8zu %8zu %10.4g %18s %8.2f %-24s %-*s  ok\n", width, inputs[i], s->points_in,
				s->points_out, s->r, iters, s->seconds, s->capped, dwidth, device);
			ok++;
			seconds += s->seconds;
		} else if (s->skipped) {
			fprintf(out, "%-*s %8s %8s %10s %18s %8s %-24s %-*s  skipped: done before\n", width, inputs[i], "-",
				"-", "-", "-", "-", "-", dwidth, "-");
			skipped++;
		} else {
			fprintf(out, "%-*s %8s %8s %10s %18s %8s %-24s %-*s  FAILED: %s\n", width, inputs[i], "-", "-", "-",
				"-", "-", "-", dwidth, device, s->error);
		}
	}
	fprintf(out, "%zu input%s: %zu ok, %zu failed", n, n == 1 ? "" : "s", ok, n - ok - skipped);
	if (skipped)
		fprintf(out, ", %zu skipped (done before)", skipped);
	fprintf(out, "; %.2f s in the pipeline\n", seconds);
}
