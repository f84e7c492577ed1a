/* dpoints wlop: raw cloud -> WLOP samples with oriented normals (stage 1). */
#include "cli/consolidate.h"
#include "cli/input.h"
#include "knn/attributes.h"
#include "core/common.h"

#include <string.h>

typedef struct wlop_run {
	const char *input, *output, *device_name;
	int backend;
	size_t points_in;
	dp_wlop_params wp;
	dp_normal_params np;
	dp_wlop_stats ws;
	size_t dense, turned; /* dp_orient_from_denser */
	double seconds_read, seconds_normals, seconds_write;
	double context_start; /* seconds since the command started when the context was made */
	int quiet;
	dp_params caps;                 /* the WLOP cap, for the progress lines */
	dp_cli_progress_state progress; /* their printer */
} wlop_run;

/* The library reports seconds since the context was made; reading came before
 * it, so the lines count from the command's start like the other lines here. */
static int wlop_progress(void *user, const char *stage, int iteration, double value, double elapsed)
{
	wlop_run *run = user;
	return dp_cli_progress(&run->progress, stage, iteration, value, run->context_start + elapsed);
}

/* A line before a step with no iterations to report, which on millions of
 * points takes long enough to look like a hang. Nothing is printed before the
 * first WLOP iteration, so an input or device error stays one line. */
static void wlop_step(wlop_run *run, double start, const char *step, size_t points)
{
	if (run->quiet)
		return;
	/* the WLOP run before it has ended: its line first */
	dp_cli_progress_end(&run->progress, 1);
	fprintf(stderr, "  [%7.1f s] %-9s %zu points\n", dp_seconds() - start, step, points);
}

static void fill_report(json_writer *w, const void *arg)
{
	const wlop_run *run = arg;
	json_object(w, NULL);
	json_str(w, "command", "wlop");
	json_str(w, "input", run->input);
	json_str(w, "output", run->output);
	json_str(w, "backend", run->backend ? "ref" : "cl");
	json_str(w, "device", run->device_name);
	json_object(w, "parameters");
	dp_json_wlop_params(w, &run->wp);
	dp_json_normal_params(w, &run->np);
	json_end_object(w);
	json_object(w, "results");
	json_int(w, "points_in", (long long)run->points_in);
	json_int(w, "points_out", (long long)run->wp.samples);
	json_num(w, "h", run->ws.h);
	json_int(w, "iterations", run->ws.iterations);
	json_bool(w, "converged", run->ws.converged);
	json_num(w, "last_mean_move_h", run->ws.last_mean_move);
	json_num(w, "last_max_move_h", run->ws.last_max_move);
	json_num(w, "pair_evaluations", run->ws.pair_evaluations);
	json_int(w, "normals_dense_samples", (long long)run->dense);
	json_int(w, "normals_turned", (long long)run->turned);
	json_object(w, "seconds");
	json_num(w, "read", run->seconds_read);
	json_num(w, "density", run->ws.seconds_density);
	json_num(w, "iterations", run->ws.seconds_iterations);
	json_num(w, "per_iteration", run->ws.iterations ? run->ws.seconds_iterations / run->ws.iterations : 0.0);
	json_num(w, "normals", run->seconds_normals);
	json_num(w, "write", run->seconds_write);
	json_end_object(w);
	json_end_object(w);
	json_end_object(w);
}

int dp_cmd_wlop(int argc, char **argv)
{
	const char *cmd = "wlop";
	wlop_run run;
	memset(&run, 0, sizeof run);
	dp_wlop_params_default(&run.wp);
	dp_normal_params_default(&run.np);
	const char *device = NULL, *report = NULL, *format = NULL, *columns = NULL;
	int ascii = 0, weight = (int)run.wp.weight;
	cli_opt opts[] = {
		{"--output", CLI_STRING, &run.output,
		 "output PLY (x y z nx ny nz, and red green blue when the input has colours); - for standard output",
		 NULL, NULL},
		{"--samples", CLI_SIZE, &run.wp.samples, "number of output points m", NULL, NULL},
		{"--ratio", CLI_DOUBLE, &run.wp.ratio, "m = ratio * input points, when --samples is not given", NULL,
		 NULL},
		{"--radius", CLI_DOUBLE, &run.wp.h, "support radius h (0 = h-factor * initial sample spacing)", NULL,
		 NULL},
		{"--h-factor", CLI_DOUBLE, &run.wp.h_factor, "default h in mean NN spacings of the initial samples",
		 NULL, NULL},
		{"--iters", CLI_INT, &run.wp.max_iters, "iteration cap", NULL, NULL},
		{"--tol", CLI_DOUBLE, &run.wp.tol, "stop when the mean move of an iteration is below tol * h", NULL,
		 NULL},
		{"--stall-tol", CLI_DOUBLE, &run.wp.stall_tol,
		 "also stop when the mean move is below this * h and fell by less than --min-drop over --window iterations",
		 NULL, NULL},
		{"--window", CLI_INT, &run.wp.window, "iterations of the stall test", NULL, NULL},
		{"--min-drop", CLI_DOUBLE, &run.wp.min_drop, "relative fall of the mean move that keeps WLOP going", NULL,
		 NULL},
		{"--mu", CLI_DOUBLE, &run.wp.mu, "repulsion weight", NULL, NULL},
		{"--theta-k", CLI_DOUBLE, &run.wp.theta_k, "theta(d) = exp(-k d^2/h^2); 16 (Huang 2009) or 4", NULL,
		 NULL},
		{"--weight", CLI_CHOICE, &weight, "attraction: L1 median (Huang 2009) or Gaussian mean (CGAL)",
		 "l1|gaussian", NULL},
		{"--sqrt-density", CLI_FLAG, &run.wp.sqrt_density, "sample density sqrt(1 + sum theta)", NULL, NULL},
		{"--seed", CLI_U64, &run.wp.seed, "seed of the initial sample choice", NULL, NULL},
		{"--normal-k", CLI_INT, &run.np.k, "PCA neighbours per normal", NULL, NULL},
		{"--graph-k", CLI_INT, &run.np.k_graph, "neighbours in the orientation graph", NULL, NULL},
		{"--viewpoint", CLI_VEC3, run.np.viewpoint, "orient normals towards this scanner position", NULL,
		 &run.np.use_viewpoint},
		CLI_BACKEND_OPTS(run.backend, device),
		{"--report", CLI_STRING, &report, "also write the summary and every parameter as JSON; - for standard output", NULL, NULL},
		{"--ascii", CLI_FLAG, &ascii, "write ascii PLY instead of binary", NULL, NULL},
		{"--quiet", CLI_FLAG, &run.quiet, "no progress on stderr", NULL, NULL},
		CLI_INPUT_OPTS(format, columns),
	};
	const char *pos[1];
	size_t npos;
	int help;
	int rc = cli_parse(cmd, "INPUT -o OUT.ply [options]", argc, argv, 2, opts, sizeof opts / sizeof opts[0], pos,
			   1, &npos, &help);
	if (rc || help)
		return rc;
	if (npos != 1 || !run.output) {
		fprintf(stderr, "dpoints %s: needs INPUT and -o OUT.ply (see dpoints %s --help)\n", cmd, cmd);
		return DP_EXIT_INPUT;
	}
	run.wp.weight = (dp_wlop_weight)weight;
	run.input = pos[0];
	int to_stdout = cli_is_stdout(run.output), report_stdout = report && cli_is_stdout(report);
	if (to_stdout && report_stdout) {
		fprintf(stderr, "dpoints %s: -o - and --report -: only one output can go to standard output\n", cmd);
		return DP_EXIT_INPUT;
	}
	if ((!to_stdout && (rc = cli_check_output(cmd, run.output))) ||
	    (report && !report_stdout && (rc = cli_check_output(cmd, report))))
		return rc;
	if ((!to_stdout && (rc = cli_check_not_input(cmd, run.output, pos, 1))) ||
	    (report && !report_stdout && (rc = cli_check_not_input(cmd, report, pos, 1))) ||
	    (report && !to_stdout && !report_stdout &&
	     (rc = cli_check_distinct_outputs(cmd, report, run.output))))
		return rc;

	dp_error err = {0};
	dp_cloud in = {0}, out = {0};
	dp_context *ctx = NULL;
	double start = dp_seconds(), t0 = start;
	if (dp_cli_read_input(run.input, format, columns, &in, &err) != DP_OK) {
		rc = dp_cli_fail(cmd, &err);
		goto done;
	}
	run.points_in = in.n;
	run.seconds_read = dp_seconds() - t0;
	run.context_start = dp_seconds() - start;
	if ((rc = cli_open_context(cmd, run.backend, device, &ctx)))
		goto done;
	run.device_name = dp_context_device_name(ctx);
	if (!run.quiet) {
		dp_params_default(&run.caps);
		run.caps.wlop = run.wp;
		run.progress.params = &run.caps;
		dp_context_set_progress(ctx, wlop_progress, &run);
	}
	if (dp_wlop(ctx, &in, &run.wp, &out, &run.ws, &err) != DP_OK) {
		dp_cli_name_input(&err, run.input);
		rc = dp_cli_fail(cmd, &err);
		goto done;
	}
	run.wp.samples = out.n;
	wlop_step(&run, start, "normals", out.n);
	t0 = dp_seconds();
	if (dp_estimate_normals(&out, &run.np, &err) != DP_OK) {
		dp_cli_name_input(&err, run.input);
		rc = dp_cli_fail(cmd, &err);
		goto done;
	}
	if (out.n < DP_ORIENT_DENSE_SAMPLES && !run.np.use_viewpoint)
		wlop_step(&run, start, "orient", out.n);
	if (dp_orient_from_denser(ctx, &in, &run.wp, &run.np, DP_ORIENT_DENSE_SAMPLES, &out, &run.dense, &run.turned,
				  &err) != DP_OK) {
		dp_cli_name_input(&err, run.input);
		rc = dp_cli_fail(cmd, &err);
		goto done;
	}
	run.seconds_normals = dp_seconds() - t0;
	if (dp_transfer_attributes(&out, &in, &err) != DP_OK) {
		dp_cli_name_input(&err, run.input);
		rc = dp_cli_fail(cmd, &err);
		goto done;
	}
	wlop_step(&run, start, "write", out.n);
	t0 = dp_seconds();
	if ((rc = cli_write_ply(cmd, run.output, &out, ascii)))
		goto done;
	run.seconds_write = dp_seconds() - t0;
	/* with -o - or --report - stdout is that file */
	char signs[80] = "";
	if (run.dense)
		snprintf(signs, sizeof signs, " (signs from %zu denser samples, %zu turned)", run.dense, run.turned);
	fprintf(to_stdout || report_stdout ? stderr : stdout, "wlop: %zu points in, %zu out, h = %.6g, %d iterations, %.3f s density + %.3f s iterations "
	       "(%.4f s/iteration), normals %.3f s%s, %s on %s -> %s\n",
	       run.points_in, out.n, run.ws.h, run.ws.iterations, run.ws.seconds_density, run.ws.seconds_iterations,
	       run.ws.iterations ? run.ws.seconds_iterations / run.ws.iterations : 0.0, run.seconds_normals, signs,
	       run.backend ? "ref" : "cl", run.device_name, run.output);
	if (report)
		rc = cli_write_json(cmd, report, fill_report, &run);
done:
	dp_context_free(ctx);
	dp_cloud_free(&in);
	dp_cloud_free(&out);
	return rc;
}
