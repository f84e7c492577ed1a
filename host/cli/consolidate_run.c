/* One consolidate run: the pipeline, then its folder through dp_result_write. */
#include "cli/caption.h"
#include "cli/consolidate.h"
#include "cli/input.h"
#include "core/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The stages of `r` that stopped at their iteration cap rather than on their
 * test, comma-separated into `out` ("-" when none). A capped stage's output
 * may be unfinished: say so. */
static void capped_stages(const dp_result *r, char *out, size_t size)
{
	const char *names[4] = {"wlop", "sink", "skeleton", "surface"};
	int capped[4] = {!r->wlop_stats.converged, !r->sink_stats.converged, !r->skeleton_stats.converged,
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
	if (job->samples_factor > 0.0) {
		/* beyond 32-bit indices the pipeline refuses the count; converting
		 * a larger double to size_t would be undefined */
		double want = fmax(1.0, round(job->samples_factor * (double)in->n));
		params.wlop.samples = want <= (double)UINT32_MAX ? (size_t)want : (size_t)UINT32_MAX + 1;
	}
	if (job->progress)
		job->progress->params = &params;
	dp_status cst = dp_consolidate(ctx, in, &params, res, &err);
	if (job->progress) {
		dp_cli_progress_end(job->progress, cst == DP_OK);
		job->progress->params = NULL;
	}
	if (cst == DP_OK && (in->rgb || in->intensity))
		cst = dp_cli_carry_colours(in, res, &err);
	if (cst != DP_OK) {
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
	dp_write_options wo;
	dp_write_options_default(&wo);
	wo.flags = (job->ascii ? DP_WRITE_ASCII : 0u) | (job->save_stages ? DP_WRITE_STAGES : 0u) |
		   (job->render ? DP_WRITE_RENDER : 0u);
	wo.up_axis = job->up_axis >= 0 ? job->up_axis : dp_cli_detect_up(in, 1);
	wo.input = in;
	wo.input_name = label;
	wo.output_name = dir; /* not the staging folder it is written into */
	if (dp_result_write(res, wdir, &wo, &err) != DP_OK) {
		if (job->staged)
			dp_cli_stage_abort(staging);
		goto fail;
	}
	if (job->staged && (rc = dp_cli_stage_commit(cmd, dir, staging)))
		goto fail_rc;
	summary->ok = 1;
	summary->points_out = res->surface.n;
	summary->points_run = res->ran_with;
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
	char kept[96] = "";
	int len = 0;
	if (res->ran_with > res->surface.n)
		len = snprintf(kept, sizeof kept, " (kept from %zu", res->ran_with);
	if (res->filled_from)
		len += snprintf(kept + len, sizeof kept - (size_t)len, "%ssurface from a subset of %zu", len ? "; " : " (",
				res->level[0].points);
	if (len)
		snprintf(kept + len, sizeof kept - (size_t)len, ")");
	if (!job->json_stdout)
		printf("consolidate: %s: %zu points -> %zu deep points%s, r = %.6g; iterations wlop %d, sink %d (%zu unsettled), "
	       "skeleton %d, surface %d; seconds wlop %.2f, normals %.2f, sink %.2f, skeleton %.2f, surface %.2f, "
	       "total %.2f -> %s\n",
	       label, in->n, res->surface.n, kept, res->r, res->wlop_stats.iterations, res->sink_stats.iterations,
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
	if (dp_cli_read_input(input, job->format, job->columns, &in, &err) != DP_OK) {
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
	fprintf(out, "\n%-*s %8s %8s %8s %10s %18s %8s %-24s %-*s  %s\n", width, "input", "points", "dpoints", "run",
		"r", "iters w/s/k/s", "seconds", "capped", dwidth, "device", "status");
	for (size_t i = 0; i < n; i++) {
		const dp_consolidate_summary *s = &rows[i];
		const char *device = s->device[0] ? s->device : "-";
		if (s->ok) {
			char iters[64];
			snprintf(iters, sizeof iters, "%d/%d/%d/%d", s->iterations[0], s->iterations[1],
				 s->iterations[2], s->iterations[3]);
			fprintf(out, "%-*s %8zu %8zu %8zu %10.4g %18s %8.2f %-24s %-*s  ok\n", width, inputs[i],
				s->points_in, s->points_out, s->points_run, s->r, iters, s->seconds, s->capped, dwidth, device);
			ok++;
			seconds += s->seconds;
		} else if (s->skipped) {
			fprintf(out, "%-*s %8s %8s %8s %10s %18s %8s %-24s %-*s  skipped: done before\n", width, inputs[i],
				"-", "-", "-", "-", "-", "-", "-", dwidth, "-");
			skipped++;
		} else {
			fprintf(out, "%-*s %8s %8s %8s %10s %18s %8s %-24s %-*s  FAILED: %s\n", width, inputs[i], "-", "-",
				"-", "-", "-", "-", "-", dwidth, device, s->error);
		}
	}
	fprintf(out, "%zu input%s: %zu ok, %zu failed", n, n == 1 ? "" : "s", ok, n - ok - skipped);
	if (skipped)
		fprintf(out, ", %zu skipped (done before)", skipped);
	fprintf(out, "; %.2f s in the pipeline\n", seconds);
}
