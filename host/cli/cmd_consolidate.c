/* dpoints consolidate: the whole pipeline on one input, or a batch of inputs
 * sharing one OpenCL context and built program. */
#include "cli/batch_run.h"
#include "cli/consolidate.h"
#include "cli/input.h"
#include "core/common.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int dp_cli_mkdir(const char *cmd, const char *dir)
{
	char path[4096];
	snprintf(path, sizeof path, "%s", dir);
	for (char *p = path + 1; *p; p++) {
		if (*p != '/')
			continue;
		*p = '\0';
		if (mkdir(path, 0777) != 0 && errno != EEXIST)
			goto fail;
		*p = '/';
	}
	if (mkdir(path, 0777) != 0 && errno != EEXIST)
		goto fail;
	struct stat sb;
	if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode))
		return 0;
fail:
	fprintf(stderr, "dpoints %s: %s: cannot create output folder: %s\n", cmd, dir, strerror(errno));
	return DP_EXIT_INPUT;
}

/* OUTDIR/<input name without folder and extension>, made unique in the batch. */
/* OUTDIR/<input name without folder and extension>, with -N (N its position
 * in the batch, then more while taken) when an earlier input already has that
 * folder. names[0..index) are the folders given out so far. */
static char *batch_dir(const char *outdir, const char *input, size_t index, char *const *names)
{
	const char *base = strrchr(input, '/');
	base = base ? base + 1 : input;
	const char *dot = strrchr(base, '.');
	int len = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
	char dir[4096];
	snprintf(dir, sizeof dir, "%s/%.*s", outdir, len, base);
	for (size_t suffix = index + 1;; suffix++) {
		size_t j = 0;
		while (j < index && strcmp(names[j], dir) != 0)
			j++;
		if (j == index)
			break;
		snprintf(dir, sizeof dir, "%s/%.*s-%zu", outdir, len, base, suffix);
	}
	return strdup(dir);
}

#define MAX_INPUTS 4096

/* "N" (a count) or "Fx" (F times the input's points, F > 0). */
static int parse_samples(const char *text, size_t *count, double *factor)
{
	char *end;
	if (text[0] < '0' || text[0] > '9')
		return -1;
	errno = 0;
	double v = strtod(text, &end);
	if ((end[0] == 'x' || end[0] == 'X') && end[1] == '\0') {
		if (!(v > 0.0) || !isfinite(v) || errno == ERANGE)
			return -1;
		*factor = v;
		return 0;
	}
	errno = 0;
	unsigned long long n = strtoull(text, &end, 10);
	if (*end || n == 0 || errno == ERANGE)
		return -1;
	*count = (size_t)n;
	return 0;
}

static int run_batch(const char *cmd, dp_consolidate_job *job, int backend, int quiet, const char *outdir,
		     const dp_cli_list *all, int listed, size_t shard, size_t nshards, int skip_done,
		     const dp_cli_list *devices);
static void print_json(const dp_batch *b, int batch, size_t shard, size_t nshards);

int dp_cmd_consolidate(int argc, char **argv)
{
	const char *cmd = "consolidate";
	dp_consolidate_job job;
	memset(&job, 0, sizeof job);
	dp_params_default(&job.params);
	const char *outdir = NULL, *device = NULL;
	int backend = 0, quiet = 0, prior = 0, no_reattach = 0, weight = (int)job.params.wlop.weight, data_term = 0;
	int any_side = 0, old_orient = 0, along = 0, no_sheet_points = 0, no_silhouette = 0, no_face_scanner = 0;
	const char *samples = NULL;
	const char *list_file = NULL, *shard_text = NULL;
	int skip_done = 0, up_given = 0;
	job.up_axis = 1;
	job.staged = 1;
	double sigma_p = job.params.sink.sigma_p;
	dp_params *p = &job.params;
	cli_opt opts[] = {
		{"--output", CLI_STRING, &outdir, "output folder (one sub-folder per input in a batch)", NULL, NULL},
		{"--samples", CLI_STRING, &samples,
		 "deep points m: a count, or Fx for F times the input's points (above the input: upsampling)", NULL,
		 NULL},
		{"--ratio", CLI_DOUBLE, &p->wlop.ratio, "m = ratio * input points, when --samples is not given", NULL,
		 NULL},
		{"--radius", CLI_DOUBLE, &p->wlop.h, "WLOP support radius h (0 = h-factor * initial sample spacing)",
		 NULL, NULL},
		{"--h-factor", CLI_DOUBLE, &p->wlop.h_factor, "default h in mean NN spacings of the initial samples",
		 NULL, NULL},
		{"--wlop-iters", CLI_INT, &p->wlop.max_iters, "WLOP iteration cap", NULL, NULL},
		{"--wlop-tol", CLI_DOUBLE, &p->wlop.tol, "WLOP stops when the mean move of an iteration is below tol * h",
		 NULL, NULL},
		{"--wlop-stall-tol", CLI_DOUBLE, &p->wlop.stall_tol,
		 "WLOP also stops when the mean move is below this * h and fell by less than --wlop-min-drop over "
		 "--wlop-window iterations",
		 NULL, NULL},
		{"--wlop-window", CLI_INT, &p->wlop.window, "iterations of WLOP's stall test", NULL, NULL},
		{"--wlop-min-drop", CLI_DOUBLE, &p->wlop.min_drop, "relative fall of the mean move that keeps WLOP going",
		 NULL, NULL},
		{"--wlop-mu", CLI_DOUBLE, &p->wlop.mu, "WLOP repulsion weight", NULL, NULL},
		{"--theta-k", CLI_DOUBLE, &p->wlop.theta_k, "WLOP theta(d) = exp(-k d^2/h^2)", NULL, NULL},
		{"--weight", CLI_CHOICE, &weight, "WLOP attraction: L1 median (Huang 2009) or Gaussian mean (CGAL)",
		 "l1|gaussian", NULL},
		{"--sqrt-density", CLI_FLAG, &p->wlop.sqrt_density, "WLOP: sample density sqrt(1 + sum theta)", NULL,
		 NULL},
		{"--seed", CLI_U64, &p->wlop.seed, "seed of the initial sample choice", NULL, NULL},
		{"--normal-k", CLI_INT, &p->normals.k, "PCA neighbours per normal", NULL, NULL},
		{"--graph-k", CLI_INT, &p->normals.k_graph, "neighbours in the orientation graph", NULL, NULL},
		{"--viewpoint", CLI_VEC3, p->normals.viewpoint,
		 "the scanner's position: normals are oriented towards it instead of by the MST, and (facing the scanner "
		 "on) the surface's points on the scan face it (README \"Facing the scanner\")", NULL,
		 &p->normals.use_viewpoint},
		{"--omega", CLI_DOUBLE, &p->sink.omega_deg, "settle angle omega, degrees (paper: 45)", NULL, NULL},
		{"--sigma-p", CLI_DOUBLE, &sigma_p, "static neighbourhood sigma_p, in r, of sinking and surface", NULL,
		 NULL},
		{"--settle-radius", CLI_DOUBLE, &p->sink.settle_radius_r, "settle test radius, in r (DESIGN 4.1)",
		 NULL, NULL},
		{"--front-factor", CLI_DOUBLE, &p->sink.front_factor,
		 "opposing front: surface points farther apart than this * settle radius", NULL, NULL},
		{"--first-step", CLI_DOUBLE, &p->sink.first_step_r, "first sinking step, in r", NULL, NULL},
		{"--slow-fraction", CLI_DOUBLE, &p->sink.slow_fraction,
		 "a point settles when its step falls below this * first step", NULL, NULL},
		{"--sink-iters", CLI_INT, &p->sink.max_iters, "sinking iteration cap", NULL, NULL},
		{"--medial-margin", CLI_DOUBLE, &p->sink.medial_margin_r,
		 "a sinking point past the medial axis by this much, in r, plus --medial-fraction of its depth, settles (0 = off)",
		 NULL, NULL},
		{"--medial-fraction", CLI_DOUBLE, &p->sink.medial_fraction,
		 "the medial test's margin grows by this fraction, in [0, 1), of the sinking point's depth", NULL, NULL},
		{"--medial-fraction-cap", CLI_DOUBLE, &p->sink.medial_fraction_cap_r,
		 "the depth's part of the medial test's margin is at most this, in r", NULL, NULL},
		{"--meet-shift", CLI_DOUBLE, &p->sink.meet_shift_r,
		 "a point settled on a front moves at most this far, in r, to where its partners place the medial axis (0 = off)",
		 NULL, NULL},
		{"--slow-margin", CLI_DOUBLE, &p->sink.slow_margin_r,
		 "a settled neighbour slows a sinking point only if it stopped no shallower than the point minus this, in r "
		 "(1e9: every settled neighbour, as in the paper)", NULL, NULL},
		{"--width-factor", CLI_DOUBLE, &p->sink.width_factor,
		 "a sinking point stops once as deep as half the scale at which the samples around its surface point "
		 "spread less than that scale / (2 * this): points leaving a thin part stop within a few of its widths "
		 "(0 = off)", NULL, NULL},
		{"--thin-wall", CLI_DOUBLE, &p->sink.wall_min_r,
		 "a sinking point also meets the far face of a wall however near it is, once the face's normal is over "
		 "135 degrees from its own and it lies at least this far behind that face's tangent plane, in r: a wall "
		 "thinner than the front test's far distance is otherwise passed through (0 = off)", NULL, NULL},
		{"--flat-angle", CLI_DOUBLE, &p->sink.flat_angle_deg,
		 "a point that stopped only by slow-down takes at most its flat face's depth: the median depth of the "
		 "evidence-settled points at the face's rim, passed on through samples whose normals stay within this "
		 "angle, degrees: a flat face scanned from one side is as thick as its rim shows (0 = off)", NULL, NULL},
		{"--sigma-q", CLI_DOUBLE, &p->skeleton.sigma_q, "skeleton PCA neighbourhood sigma_q, in r", NULL,
		 NULL},
		{"--eps", CLI_DOUBLE, &p->skeleton.eps, "semi-axis constant epsilon", NULL, NULL},
		{"--mu", CLI_DOUBLE, &p->skeleton.mu, "skeleton repulsion mu", NULL, NULL},
		{"--cutoff", CLI_DOUBLE, &p->skeleton.cutoff, "skeleton sums stop at this ellipsoid distance, in r",
		 NULL, NULL},
		{"--min-axis-weight", CLI_DOUBLE, &p->skeleton.min_axis_weight,
		 "skeleton repulsion ignores axes of smaller weight", NULL, NULL},
		{"--skeleton-along", CLI_FLAG, &along,
		 "the skeleton's median step moves points along curves and sheets too (the paper), not only across "
		 "them: sheets tear into spots and leave their rims", NULL, NULL},
		{"--skeleton-iters", CLI_INT, &p->skeleton.max_iters, "skeleton iteration cap", NULL, NULL},
		{"--skeleton-window", CLI_INT, &p->skeleton.window,
		 "skeleton stops when the mean move fell less than min-drop over this many iterations", NULL, NULL},
		{"--skeleton-min-drop", CLI_DOUBLE, &p->skeleton.min_drop, "required relative fall of the mean move",
		 NULL, NULL},
		{"--skeleton-min-move", CLI_DOUBLE, &p->skeleton.min_move_r,
		 "skeleton also stops when the mean move is below this, in r", NULL, NULL},
		{"--mu-hat", CLI_DOUBLE, &p->surface.mu_hat, "surface tangential repulsion mu-hat", NULL, NULL},
		{"--prior", CLI_CHOICE, &prior, "surface shape prior (Eq. 8 or Eq. 9)", "volume|minimal", NULL},
		{"--normal-radius", CLI_DOUBLE, &p->surface.normal_radius_r, "surface PCA normal radius, in r", NULL,
		 NULL},
		{"--no-reattach", CLI_FLAG, &no_reattach,
		 "keep inner ends on the skeleton points the skeleton stage gave them (end smoothing still moves them "
		 "across the normal unless --end-smoothing 0)", NULL, NULL},
		{"--reattach-radius", CLI_DOUBLE, &p->surface.reattach_radius_r, "re-attachment search radius, in r",
		 NULL, NULL},
		{"--end-smoothing", CLI_DOUBLE, &p->surface.end_smoothing_r,
		 "width, in r, over which inner ends are moved under their surface points across the normal, from the "
		 "skeleton points their neighbours hang on (0 = off)", NULL, NULL},
		{"--surface-iters", CLI_INT, &p->surface.max_iters, "surface iteration cap", NULL, NULL},
		{"--surface-window", CLI_INT, &p->surface.window,
		 "surface stops when over this many iterations the mean move, the mean spacing and its variation stalled",
		 NULL, NULL},
		{"--surface-min-drop", CLI_DOUBLE, &p->surface.min_drop, "required relative fall of the mean move",
		 NULL, NULL},
		{"--surface-min-growth", CLI_DOUBLE, &p->surface.min_growth,
		 "required relative growth of the mean spacing, or fall of its variation", NULL, NULL},
		{"--surface-min-move", CLI_DOUBLE, &p->surface.min_move_r,
		 "surface also stops when in each of the last --surface-window iterations at most one point in 1000 moved "
		 "more than this, in r (0 = off)", NULL, NULL},
		{"--tangent-floor", CLI_DOUBLE, &p->surface.tangent_floor_r,
		 "smallest tangential distance in the repulsion weight, in r", NULL, NULL},
		{"--slide-reach", CLI_DOUBLE, &p->surface.slide_reach_r,
		 "a surface point slides tangentially only while its nearest neighbour is within this, in r (0 = always): "
		 "fewer stray points, less completion", NULL, NULL},
		{"--escape-margin", CLI_DOUBLE, &p->surface.escape_margin_r,
		 "a surface point with no input near that lies deeper than this, in r, in a sinking ball whose centre it "
		 "faces moves out to the ball's sphere: no stray points inside the body (0 = off)", NULL, NULL},
		{"--no-same-side", CLI_FLAG, &any_side,
		 "surface sums over whole balls (the paper) instead of the point's own side", NULL, NULL},
		{"--no-dpoint-orient", CLI_FLAG, &old_orient,
		 "sign PCA normals by the old normal instead of the dpoint orientation", NULL, NULL},
		{"--no-sheet-points", CLI_FLAG, &no_sheet_points,
		 "leave completed points that came to rest in a skeletal sheet (a plate's middle, their normals along "
		 "it) where they are, instead of moving them across it to the plate's face", NULL, NULL},
		{"--no-silhouette", CLI_FLAG, &no_silhouette,
		 "let completed points leave the scan's outline seen along its view axis (README \"The scan's outline\")",
		 NULL, NULL},
		{"--view-axis", CLI_VEC3, p->surface.silhouette_axis,
		 "the scanner's view axis, whose outline holds the completed points and along which a one-sided scan's "
		 "normals face the scanner (default: found from the normals, if there is one)", NULL, NULL},
		{"--silhouette-margin", CLI_DOUBLE, &p->surface.silhouette_margin_r,
		 "growth of the scan's outline, in r, where the scan's surface turns away from the scanner at its edge",
		 NULL, NULL},
		{"--silhouette-edge-margin", CLI_DOUBLE, &p->surface.silhouette_edge_margin_r,
		 "growth of the scan's outline, in r, where the scan's surface faces the scanner up to its edge (normals "
		 "within 50 degrees of the view axis: a sharp edge, such as a flat base seen from the side)", NULL, NULL},
		{"--silhouette-grazing", CLI_DOUBLE, &p->surface.silhouette_grazing,
		 "a view axis is a direction to which at most this fraction of the normals lie within 10 degrees of "
		 "perpendicular", NULL, NULL},
		{"--no-face-scanner", CLI_FLAG, &no_face_scanner,
		 "leave normals that face away from the scanner of a one-sided scan (or from --viewpoint) as "
		 "orientation signed them, instead of turning those on the scan to face it (README \"Facing the "
		 "scanner\")", NULL, NULL},
		{"--face-scanner-cos", CLI_DOUBLE, &p->surface.face_scanner_cos,
		 "a normal on a one-sided scan is turned to face the scanner (or --viewpoint) when it points within "
		 "acos of this of straight away from it", NULL, NULL},
		{"--coarse-samples", CLI_COUNT, &p->refine.coarse_samples,
		 "deep points of the coarse level (0 = no coarse-to-fine)", NULL, NULL},
		{"--coarse-min", CLI_COUNT, &p->refine.coarse_min,
		 "a one-sided scan's coarse level may be as coarse as this (doubling up to --coarse-samples) where no "
		 "part is thinner than 16 r (0 = always --coarse-samples)", NULL, NULL},
		{"--fill-samples", CLI_COUNT, &p->refine.fill_samples,
		 "a one-sided scan's surface stage starts on an even subset of this many of the coarse level's deep "
		 "points, where its far side fills sooner (0 = off)", NULL, NULL},
		{"--level-factor", CLI_DOUBLE, &p->refine.level_factor, "deep-point growth per refined level", NULL,
		 NULL},
		{"--level-iters", CLI_INT, &p->refine.level_iters, "surface iterations per refined level", NULL, NULL},
		{"--even-rounds", CLI_INT, &p->refine.even_rounds,
		 "after the last level, rounds that move points from the densest places to the widest gaps (even "
		 "spacing; more flips where the completion is guessed, see README)", NULL, NULL},
		{"--even-iters", CLI_INT, &p->refine.even_iters, "surface iterations relaxing each even-spacing round",
		 NULL, NULL},
		{"--samples-floor", CLI_SIZE, &p->refine.samples_floor,
		 "default count: max(ratio * input, this), at most the distinct input points", NULL, NULL},
		{"--data-term", CLI_CHOICE, &data_term,
		 "surface data term along the normal (DESIGN 4.3) or as Eq. 6 is printed", "normal|full", NULL},
		{"--backend", CLI_CHOICE, &backend, "kernels on an OpenCL device, or the scalar reference", "cl|ref", NULL},
		{"--device", CLI_STRING, &device,
		 "OpenCL device: index or name substring from `dpoints devices` (env DPOINTS_DEVICE); a batch also takes "
		 "all, or a list such as 0,1: one worker per entry",
		 NULL, NULL},
		{"--threads", CLI_INT, &job.threads,
		 "host threads of each worker's loops over points (0 = the CPUs, shared among workers)", NULL, NULL},
		{"--save-stages", CLI_FLAG, &job.save_stages, "also write wlop.ply and anchors.ply", NULL, NULL},
		{"--render", CLI_FLAG, &job.render, "also render input, skeleton, surface and deep points to PNGs",
		 NULL, NULL},
		{"--up", CLI_CHOICE, &job.up_axis,
		 "vertical axis of the renders (default: z where the input is clearly taller in z than in y, else y)",
		 "x|y|z", &up_given},
		{"--ascii", CLI_FLAG, &job.ascii, "write ascii PLY", NULL, NULL},
		{"--quiet", CLI_FLAG, &quiet, "no progress on stderr", NULL, NULL},
		CLI_INPUT_OPTS(job.format, job.columns),
		{"--inputs", CLI_STRING, &list_file,
		 "file of input paths, one a line (# comments; - reads stdin), after those on the command line; "
		 "always one sub-folder per input",
		 NULL, NULL},
		{"--shard", CLI_STRING, &shard_text,
		 "I/N: run only inputs I, I+N, I+2N, ... (from 0) of the whole list "
		 "(default: SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT when set, else all)",
		 NULL, NULL},
		{"--skip-done", CLI_FLAG, &skip_done,
		 "skip an input whose folder holds its complete result (report.json and every file it lists)", NULL,
		 NULL},
		{"--json", CLI_FLAG, &job.json_stdout,
		 "print the run's summary as one JSON object on stdout (progress and errors stay on stderr)", NULL,
		 NULL},
	};
	static const char *positional[MAX_INPUTS];
	size_t npositional;
	int help;
	int rc = cli_parse(cmd, "INPUT [INPUT ...] | --inputs LIST  -o OUTDIR [options]", argc, argv, 2, opts,
			   sizeof opts / sizeof opts[0], positional, MAX_INPUTS, &npositional, &help);
	if (rc || help)
		return rc;
	if (samples && parse_samples(samples, &p->wlop.samples, &job.samples_factor)) {
		fprintf(stderr, "dpoints %s: --samples: '%s' is neither a positive count nor a factor like 4x (see dpoints %s --help)\n",
			cmd, samples, cmd);
		return DP_EXIT_INPUT;
	}
	if (job.threads < 0) {
		fprintf(stderr, "dpoints %s: --threads: %d is not a count >= 0 (0 = the CPUs)\n", cmd, job.threads);
		return DP_EXIT_INPUT;
	}
	if (!up_given)
		job.up_axis = -1; /* from each input's data */
	p->sink.sigma_p = p->surface.sigma_p = sigma_p;
	p->surface.prior = (dp_surface_prior)prior;
	p->surface.reattach = !no_reattach;
	p->surface.same_side = !any_side;
	p->skeleton.across_only = !along;
	p->surface.orient_by_dpoint = !old_orient;
	p->surface.sheet_points = !no_sheet_points;
	p->surface.silhouette = !no_silhouette;
	p->surface.face_scanner = !no_face_scanner;
	p->surface.data_along_normal = data_term == 0;
	p->wlop.weight = (dp_wlop_weight)weight;
	dp_cli_list all = {0}, devices = {0};
	for (size_t i = 0; i < npositional && !rc; i++)
		if (dp_cli_list_add(&all, positional[i])) {
			fprintf(stderr, "dpoints %s: out of memory\n", cmd);
			rc = DP_EXIT_NOMEM;
		}
	if (!rc && list_file)
		rc = dp_cli_read_input_list(cmd, list_file, &all);
	size_t shard, nshards;
	if (!rc)
		rc = dp_cli_shard(cmd, shard_text, &shard, &nshards);
	if (!rc)
		rc = dp_cli_device_list(cmd, device, &devices);
	if (!rc && (all.n == 0 || !outdir)) {
		fprintf(stderr, "dpoints %s: needs INPUT and -o OUTDIR (inputs on the command line or in --inputs LIST; "
				"see dpoints %s --help)\n",
			cmd, cmd);
		rc = DP_EXIT_INPUT;
	}
	if (!rc)
		rc = cli_check_folder(cmd, outdir, " (--json prints the summary there)");
	if (rc) {
		dp_cli_list_free(&all);
		dp_cli_list_free(&devices);
		return rc;
	}
	rc = run_batch(cmd, &job, backend, quiet, outdir, &all, list_file != NULL, shard, nshards, skip_done,
		       &devices);
	dp_cli_list_free(&all);
	dp_cli_list_free(&devices);
	return rc;
}

/* What the whole list (not only this shard) decides: folder names, and
 * whether each input gets a sub-folder, so every shard writes the same
 * folders a single run would. */
static int run_batch(const char *cmd, dp_consolidate_job *job, int backend, int quiet, const char *outdir,
		     const dp_cli_list *all, int listed, size_t shard, size_t nshards, int skip_done,
		     const dp_cli_list *devices)
{
	int batch = all->n > 1 || listed;
	int rc = 0;
	char **all_dirs = calloc(all->n, sizeof *all_dirs);
	size_t ninputs = 0;
	for (size_t i = shard; i < all->n; i += nshards)
		ninputs++;
	const char **inputs = calloc(ninputs ? ninputs : 1, sizeof *inputs);
	char **dirs = calloc(ninputs ? ninputs : 1, sizeof *dirs);
	dp_consolidate_summary *summary = calloc(ninputs ? ninputs : 1, sizeof *summary);
	if (!all_dirs || !inputs || !dirs || !summary) {
		fprintf(stderr, "dpoints %s: out of memory\n", cmd);
		rc = DP_EXIT_NOMEM;
	}
	for (size_t i = 0; i < all->n && !rc; i++) {
		all_dirs[i] = !batch ? strdup(outdir) : batch_dir(outdir, all->items[i], i, all_dirs);
		if (!all_dirs[i]) {
			fprintf(stderr, "dpoints %s: out of memory\n", cmd);
			rc = DP_EXIT_NOMEM;
		}
	}
	size_t nskipped = 0;
	/* every folder first: a later input may sit where an earlier one writes */
	for (size_t i = shard, k = 0; i < all->n && !rc; i += nshards, k++) {
		inputs[k] = all->items[i];
		dirs[k] = all_dirs[i];
		if (skip_done && dp_cli_result_done(dirs[k], inputs[k])) {
			summary[k].skipped = 1;
			nskipped++;
			continue;
		}
		rc = cli_check_folder_not_input(cmd, dirs[k], (const char *const *)all->items, all->n);
		if (!rc)
			rc = dp_cli_check_result_dir(cmd, dirs[k]);
	}
	struct stat sb;
	int outdir_existed = stat(outdir, &sb) == 0;
	dp_batch b = {cmd, inputs, dirs, summary, ninputs, 0, quiet, batch, 0, 0};
	job->backend_name = backend ? "ref" : "cl";
	if (!rc && !quiet && nskipped)
		fprintf(stderr, "dpoints %s: %zu of %zu inputs already done (--skip-done)\n", cmd, nskipped, ninputs);
	if (!rc && nskipped < ninputs && !(rc = dp_cli_mkdir(cmd, outdir)) &&
	    (rc = dp_cli_batch_run(&b, job, backend, devices)) && !outdir_existed)
		rmdir(outdir);
	if (!rc) {
		if (job->json_stdout)
			print_json(&b, batch, shard, nshards);
		else if (batch)
			dp_cli_print_batch_summary(stdout, inputs, summary, ninputs);
		if (b.failed && batch)
			fprintf(stderr, "dpoints %s: %zu of %zu inputs failed\n", cmd, b.failed, ninputs);
		/* a run that produced nothing leaves nothing (rmdir only removes it
		 * empty); not a shard, whose siblings may be writing there and whose
		 * failure records the summary needs */
		if (ninputs && b.failed == ninputs && !outdir_existed && nshards == 1) {
			for (size_t k = 0; k < ninputs; k++)
				dp_cli_clear_failure(dirs[k]);
			rmdir(outdir);
		}
		rc = b.first_failure;
	}
	for (size_t i = 0; all_dirs && i < all->n; i++)
		free(all_dirs[i]);
	free(all_dirs);
	free(inputs);
	free(dirs);
	free(summary);
	return rc;
}

/* One input: its report's summary and results (a single run), or every
 * input of this shard with the counts (a batch). */
static void print_json(const dp_batch *b, int batch, size_t shard, size_t nshards)
{
	size_t ok = 0, skipped = 0;
	if (batch)
		printf("{\"shard\":\"%zu/%zu\",\"inputs\":[", shard, nshards);
	for (size_t k = 0; k < b->n; k++) {
		const dp_consolidate_summary *s = &b->summary[k];
		char path[4096];
		snprintf(path, sizeof path, "%s/report.json", b->dirs[k]);
		dp_json *report = s->ok || s->skipped ? dp_json_read_file(path) : NULL;
		const char *status = s->skipped ? "skipped" : s->ok ? "ok" : "failed";
		ok += s->ok;
		skipped += s->skipped;
		if (k)
			putchar(',');
		dp_cli_summary_row_json(stdout, report, b->inputs[k], b->dirs[k],
					report ? dp_json_string(report, "device") : NULL, status,
					s->ok || s->skipped ? NULL : s->error, 1);
		dp_json_free(report);
	}
	if (batch)
		printf("],\"ok\":%zu,\"failed\":%zu,\"skipped\":%zu}", ok, b->n - ok - skipped, skipped);
	putchar('\n');
	fflush(stdout);
}
