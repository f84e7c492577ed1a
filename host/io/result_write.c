/* A consolidate result as files: the three PLY files, report.json, and on
 * request the coarse level's stages and pictures. The tool's consolidate and
 * demo write through this, so a library user gets the same folder. */
#include "core/common.h"
#include "io/io.h"
#include "io/json.h"
#include "dpoints_tools.h"

#include <stdlib.h>
#include <string.h>

/* A 3-vector as an array member `name`. */
static void json_vec3(dp_json_writer *w, const char *name, const double v[3])
{
	dp_json_array(w, name);
	for (int c = 0; c < 3; c++)
		dp_json_num(w, NULL, v[c]);
	dp_json_end_array(w);
}

void dp_json_wlop_params(dp_json_writer *w, const dp_wlop_params *p)
{
	dp_json_object(w, "wlop");
	dp_json_int(w, "samples", (long long)p->samples);
	dp_json_num(w, "ratio", p->ratio);
	dp_json_num(w, "h", p->h);
	dp_json_num(w, "h_factor", p->h_factor);
	dp_json_num(w, "mu", p->mu);
	dp_json_int(w, "max_iters", p->max_iters);
	dp_json_num(w, "tol", p->tol);
	dp_json_num(w, "stall_tol", p->stall_tol);
	dp_json_int(w, "window", p->window);
	dp_json_num(w, "min_drop", p->min_drop);
	dp_json_num(w, "theta_k", p->theta_k);
	dp_json_str(w, "weight", p->weight == DP_WLOP_GAUSSIAN ? "gaussian" : "l1");
	dp_json_bool(w, "sqrt_density", p->sqrt_density);
	dp_json_int(w, "seed", (long long)p->seed);
	dp_json_end_object(w);
}

void dp_json_normal_params(dp_json_writer *w, const dp_normal_params *p)
{
	dp_json_object(w, "normals");
	dp_json_int(w, "k", p->k);
	dp_json_int(w, "k_graph", p->k_graph);
	dp_json_bool(w, "use_viewpoint", p->use_viewpoint);
	if (p->use_viewpoint) {
		json_vec3(w, "viewpoint", p->viewpoint);
	}
	dp_json_end_object(w);
}

static void json_sink_params(dp_json_writer *w, const dp_sink_params *p)
{
	dp_json_object(w, "sink");
	dp_json_num(w, "sigma_p", p->sigma_p);
	dp_json_num(w, "settle_radius_r", p->settle_radius_r);
	dp_json_num(w, "front_factor", p->front_factor);
	dp_json_num(w, "omega_deg", p->omega_deg);
	dp_json_num(w, "first_step_r", p->first_step_r);
	dp_json_num(w, "slow_fraction", p->slow_fraction);
	dp_json_int(w, "max_iters", p->max_iters);
	dp_json_num(w, "medial_margin_r", p->medial_margin_r);
	dp_json_num(w, "medial_fraction", p->medial_fraction);
	dp_json_num(w, "medial_fraction_cap_r", p->medial_fraction_cap_r);
	dp_json_num(w, "meet_shift_r", p->meet_shift_r);
	dp_json_num(w, "slow_margin_r", p->slow_margin_r);
	dp_json_num(w, "width_factor", p->width_factor);
	dp_json_num(w, "flat_angle_deg", p->flat_angle_deg);
	dp_json_num(w, "wall_min_r", p->wall_min_r);
	dp_json_end_object(w);
}

static void json_skeleton_params(dp_json_writer *w, const dp_skeleton_params *p)
{
	dp_json_object(w, "skeleton");
	dp_json_num(w, "sigma_q", p->sigma_q);
	dp_json_num(w, "eps", p->eps);
	dp_json_num(w, "mu", p->mu);
	dp_json_num(w, "cutoff", p->cutoff);
	dp_json_num(w, "min_axis_weight", p->min_axis_weight);
	dp_json_bool(w, "across_only", p->across_only);
	dp_json_int(w, "max_iters", p->max_iters);
	dp_json_int(w, "window", p->window);
	dp_json_num(w, "min_drop", p->min_drop);
	dp_json_num(w, "min_move_r", p->min_move_r);
	dp_json_end_object(w);
}

static void json_surface_params(dp_json_writer *w, const dp_surface_params *p)
{
	dp_json_object(w, "surface");
	dp_json_num(w, "sigma_p", p->sigma_p);
	dp_json_num(w, "mu_hat", p->mu_hat);
	dp_json_str(w, "prior", p->prior == DP_SURFACE_PRIOR_MINIMAL ? "minimal" : "volume");
	dp_json_num(w, "tangent_floor_r", p->tangent_floor_r);
	dp_json_num(w, "slide_reach_r", p->slide_reach_r);
	dp_json_num(w, "escape_margin_r", p->escape_margin_r);
	dp_json_str(w, "data_term", p->data_along_normal ? "normal" : "full");
	dp_json_num(w, "normal_radius_r", p->normal_radius_r);
	dp_json_bool(w, "reattach", p->reattach);
	dp_json_num(w, "reattach_radius_r", p->reattach_radius_r);
	dp_json_num(w, "end_smoothing_r", p->end_smoothing_r);
	dp_json_int(w, "max_iters", p->max_iters);
	dp_json_int(w, "window", p->window);
	dp_json_num(w, "min_drop", p->min_drop);
	dp_json_num(w, "min_growth", p->min_growth);
	dp_json_num(w, "min_move_r", p->min_move_r);
	dp_json_bool(w, "same_side", p->same_side);
	dp_json_bool(w, "orient_by_dpoint", p->orient_by_dpoint);
	dp_json_bool(w, "sheet_points", p->sheet_points);
	dp_json_bool(w, "silhouette", p->silhouette);
	json_vec3(w, "silhouette_axis", p->silhouette_axis);
	dp_json_num(w, "silhouette_grazing", p->silhouette_grazing);
	dp_json_num(w, "silhouette_margin_r", p->silhouette_margin_r);
	dp_json_num(w, "silhouette_edge_margin_r", p->silhouette_edge_margin_r);
	dp_json_bool(w, "face_scanner", p->face_scanner);
	dp_json_num(w, "face_scanner_cos", p->face_scanner_cos);
	dp_json_int(w, "scanner_side", p->scanner_side);
	dp_json_bool(w, "use_viewpoint", p->use_viewpoint);
	json_vec3(w, "viewpoint", p->viewpoint);
	dp_json_end_object(w);
}

static void json_refine_params(dp_json_writer *w, const dp_refine_params *p)
{
	dp_json_object(w, "refine");
	dp_json_int(w, "coarse_samples", (long long)p->coarse_samples);
	dp_json_int(w, "coarse_min", (long long)p->coarse_min);
	dp_json_num(w, "level_factor", p->level_factor);
	dp_json_int(w, "level_iters", p->level_iters);
	dp_json_int(w, "samples_floor", (long long)p->samples_floor);
	dp_json_int(w, "even_rounds", p->even_rounds);
	dp_json_int(w, "even_iters", p->even_iters);
	dp_json_int(w, "fill_samples", (long long)p->fill_samples);
	dp_json_end_object(w);
}

typedef struct report_arg {
	const char *input, *dir;
	const dp_result *res;
	const char *files[10]; /* the result files written, report.json aside */
	int nfiles;
} report_arg;

static void fill_report(dp_json_writer *w, const report_arg *a)
{
	const dp_result *r = a->res;
	const dp_params *p = &r->params;
	dp_json_object(w, NULL);
	dp_json_str(w, "command", "consolidate");
	dp_json_str(w, "input", a->input);
	dp_json_str(w, "output", a->dir);
	dp_json_str(w, "backend", r->backend == DP_BACKEND_REF ? "ref" : "cl");
	dp_json_str(w, "device", r->device);
	dp_json_object(w, "parameters");
	dp_json_wlop_params(w, &p->wlop);
	dp_json_normal_params(w, &p->normals);
	json_sink_params(w, &p->sink);
	json_skeleton_params(w, &p->skeleton);
	json_surface_params(w, &p->surface);
	json_refine_params(w, &p->refine);
	dp_json_end_object(w);
	dp_json_object(w, "results");
	dp_json_int(w, "points_in", (long long)r->points_in);
	dp_json_int(w, "deep_points", (long long)r->surface.n);
	dp_json_int(w, "deep_points_run", (long long)r->ran_with);
	dp_json_int(w, "filled_from", (long long)r->filled_from);
	dp_json_num(w, "r", r->r);
	dp_json_object(w, "wlop");
	dp_json_num(w, "h", r->wlop_stats.h);
	dp_json_int(w, "iterations", r->wlop_stats.iterations);
	dp_json_bool(w, "converged", r->wlop_stats.converged);
	dp_json_bool(w, "stalled", r->wlop_stats.stalled);
	dp_json_num(w, "last_mean_move_h", r->wlop_stats.last_mean_move);
	dp_json_num(w, "last_max_move_h", r->wlop_stats.last_max_move);
	dp_json_num(w, "seconds", r->wlop_stats.seconds_density + r->wlop_stats.seconds_iterations);
	dp_json_num(w, "pair_evaluations", r->wlop_stats.pair_evaluations);
	dp_json_end_object(w);
	dp_json_object(w, "normals");
	dp_json_num(w, "seconds", r->seconds_normals);
	dp_json_end_object(w);
	dp_json_object(w, "sink");
	dp_json_int(w, "iterations", r->sink_stats.iterations);
	dp_json_int(w, "settled_front", (long long)r->sink_stats.settled_front);
	dp_json_int(w, "settled_medial", (long long)r->sink_stats.settled_medial);
	dp_json_int(w, "settled_width", (long long)r->sink_stats.settled_width);
	dp_json_int(w, "settled_slow", (long long)r->sink_stats.settled_slow);
	dp_json_int(w, "settled_flat", (long long)r->sink_stats.settled_flat);
	dp_json_int(w, "unsettled", (long long)r->sink_stats.unsettled);
	dp_json_bool(w, "converged", r->sink_stats.converged);
	dp_json_num(w, "r", r->sink_r);
	dp_json_num(w, "seconds", r->sink_stats.seconds);
	dp_json_num(w, "pair_evaluations", r->sink_stats.pair_evaluations);
	dp_json_end_object(w);
	dp_json_object(w, "skeleton");
	dp_json_int(w, "iterations", r->skeleton_stats.iterations);
	dp_json_bool(w, "converged", r->skeleton_stats.converged);
	dp_json_num(w, "last_mean_move_r", r->skeleton_stats.last_mean_move);
	dp_json_num(w, "seconds", r->skeleton_stats.seconds);
	dp_json_num(w, "pair_evaluations", r->skeleton_stats.pair_evaluations);
	dp_json_end_object(w);
	dp_json_object(w, "surface");
	dp_json_int(w, "iterations", r->surface_stats.iterations);
	dp_json_bool(w, "converged", r->surface_stats.converged);
	dp_json_num(w, "last_mean_move_r", r->surface_stats.last_mean_move);
	dp_json_num(w, "spacing_growth", r->surface_stats.spacing_growth);
	dp_json_int(w, "reattached", (long long)r->surface_stats.reattached);
	dp_json_int(w, "escaped", (long long)r->surface_stats.escaped);
	dp_json_int(w, "sheet_points", (long long)r->surface_stats.sheet_points);
	json_vec3(w, "silhouette_axis", r->surface_stats.silhouette_axis);
	dp_json_num(w, "silhouette_grazing", r->surface_stats.silhouette_grazing);
	dp_json_int(w, "silhouette_held", (long long)r->surface_stats.silhouette_held);
	dp_json_int(w, "even_moved", (long long)r->even_moved);
	dp_json_int(w, "silhouette_capped", (long long)r->silhouette_capped);
	json_vec3(w, "scanner", r->surface_stats.scanner);
	dp_json_bool(w, "scanner_at_eye", r->surface_stats.scanner_at_eye);
	dp_json_int(w, "scanner_turned", (long long)r->surface_stats.scanner_turned);
	dp_json_int(w, "samples_turned", (long long)r->samples_turned);
	dp_json_int(w, "normals_disagreeing", (long long)r->surface_stats.normals_disagreeing);
	dp_json_num(w, "seconds", r->surface_stats.seconds);
	dp_json_num(w, "pair_evaluations", r->surface_stats.pair_evaluations);
	dp_json_array(w, "levels");
	for (int l = 0; l < r->levels; l++) {
		dp_json_object(w, NULL);
		dp_json_int(w, "points", (long long)r->level[l].points);
		dp_json_num(w, "r", r->level[l].r);
		dp_json_int(w, "iterations", r->level[l].iterations);
		dp_json_num(w, "seconds", r->level[l].seconds);
		dp_json_num(w, "pair_evaluations", r->level[l].pair_evaluations);
		dp_json_end_object(w);
	}
	dp_json_end_array(w);
	dp_json_end_object(w);
	dp_json_num(w, "seconds_total", r->seconds_total);
	dp_json_end_object(w);
	/* what --skip-done checks for: the folder is complete when all are there */
	dp_json_array(w, "files");
	for (int k = 0; k < a->nfiles; k++)
		dp_json_str(w, NULL, a->files[k]);
	dp_json_end_array(w);
	dp_json_end_object(w);
}


/* Colours people can tell apart on white: input grey, skeleton blue,
 * surface red (the paper's figures use red outer and blue inner ends). */
static const unsigned char INPUT_RGB[3] = {120, 120, 120}, SKELETON_RGB[3] = {30, 80, 200},
			   SURFACE_RGB[3] = {200, 50, 40}, STICK_RGB[3] = {150, 150, 150};

static dp_status render(const char *dir, const char *name, const dp_render_layer *layers, size_t n, int up_axis,
			dp_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	dp_render_params rp;
	dp_render_params_default(&rp);
	rp.up_axis = up_axis;
	return dp_render_png(path, layers, n, &rp, err);
}

static void set_rgb(unsigned char dst[3], const unsigned char src[3])
{
	memcpy(dst, src, 3);
}

/* xyz/edges are the deep points as dpoints.ply holds them (2n vertices, n edges). */
static dp_status render_result(report_arg *a, const dp_cloud *in, const dp_cloud *ends, const uint32_t *edges,
			       int up_axis, const char *dir, dp_error *err)
{
	const dp_result *r = a->res;
	dp_status st;
	dp_render_layer layer = {0};
	if (in) {
		layer.cloud = in;
		set_rgb(layer.rgb, INPUT_RGB);
		if ((st = render(dir, "input.png", &layer, 1, up_axis, err)) != DP_OK)
			return st;
		a->files[a->nfiles++] = "input.png";
	}
	layer.cloud = &r->skeleton;
	set_rgb(layer.rgb, SKELETON_RGB);
	if ((st = render(dir, "skeleton.png", &layer, 1, up_axis, err)) != DP_OK)
		return st;
	a->files[a->nfiles++] = "skeleton.png";
	layer.cloud = &r->surface;
	set_rgb(layer.rgb, SURFACE_RGB);
	if ((st = render(dir, "surface.png", &layer, 1, up_axis, err)) != DP_OK)
		return st;
	a->files[a->nfiles++] = "surface.png";

	/* deep points: grey sticks with red surface ends and blue inner ends */
	dp_render_layer layers[3] = {{0}, {0}, {0}};
	layers[0].cloud = ends;
	layers[0].edges = edges;
	layers[0].nedges = r->surface.n;
	layers[0].segments_only = 1;
	layers[1].cloud = &r->surface;
	layers[2].cloud = &r->skeleton;
	set_rgb(layers[0].rgb, STICK_RGB);
	set_rgb(layers[1].rgb, SURFACE_RGB);
	set_rgb(layers[2].rgb, SKELETON_RGB);
	if ((st = render(dir, "dpoints.png", layers, 3, up_axis, err)) != DP_OK)
		return st;
	a->files[a->nfiles++] = "dpoints.png";
	return DP_OK;
}

static dp_status write_ply(report_arg *a, const char *dir, const char *name, size_t n, const dp_ply_property *props,
			   size_t nprops, const uint32_t *edges, size_t nedges, int ascii, dp_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	/* colours of the input, when the caller carried them onto the surface */
	const unsigned char *rgb = strcmp(name, "surface.ply") == 0 ? a->res->surface.rgb : NULL;
	dp_status st = dp_io_ply_write_rgb(path, n, props, nprops, rgb, edges, nedges, NULL, 0, ascii, err);
	if (st == DP_OK)
		a->files[a->nfiles++] = name;
	return st;
}

static dp_status write_stage(report_arg *a, const char *dir, const char *name, const dp_cloud *cloud, int ascii,
			     dp_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	dp_status st = dp_cloud_write_ply(path, cloud, ascii, err);
	if (st == DP_OK)
		a->files[a->nfiles++] = name;
	return st;
}

/* anchors.ply: the anchors with how each stopped sinking, the dp_settle code
 * as a float property `settled`, which point-cloud viewers offer as a scalar
 * field to colour by (where a skeleton leaves the body, the way its anchors
 * settled there says which rule let them through). Anchors carry their
 * samples' normals and no colours; a result put together by hand may lack
 * the codes or the normals, and is written as the cloud it is. */
static dp_status write_anchors(report_arg *a, const char *dir, const dp_result *r, int ascii, dp_error *err)
{
	const dp_cloud *c = &r->anchors;
	if (!r->settled_by || c->n == 0 || !c->nx || c->rgb || c->intensity)
		return write_stage(a, dir, "anchors.ply", c, ascii, err);
	float *settled = dp_alloc_array(c->n, sizeof *settled);
	if (!settled)
		return dp_fail(err, DP_ERR_NOMEM, "anchors.ply: out of memory for %zu anchors", c->n);
	for (size_t i = 0; i < c->n; i++)
		settled[i] = (float)r->settled_by[i];
	const dp_ply_property props[] = {
		{"x", c->x},   {"y", c->y},   {"z", c->z}, {"nx", c->nx},
		{"ny", c->ny}, {"nz", c->nz}, {"settled", settled},
	};
	size_t nprops = sizeof props / sizeof *props;
	dp_status st = write_ply(a, dir, "anchors.ply", c->n, props, nprops, NULL, 0, ascii, err);
	free(settled);
	return st;
}

static dp_status write_report(const report_arg *a, const char *dir, dp_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/report.json", dir);
	dp_atomic_file af;
	dp_status st = dp_atomic_open(&af, path, err);
	if (st != DP_OK)
		return st;
	dp_json_writer w;
	dp_json_begin(&w, af.f);
	fill_report(&w, a);
	dp_json_finish(&w);
	return dp_atomic_commit(&af, err);
}

dp_status dp_result_report(const dp_result *r, const dp_write_options *options, char **json, dp_error *err)
{
	if (!json)
		return dp_fail(err, DP_ERR_ARG, "report: NULL output");
	*json = NULL;
	if (!r || r->surface.n == 0)
		return dp_fail(err, DP_ERR_ARG, "report: the result holds no deep points");
	report_arg a = {options && options->input_name ? options->input_name : "",
			options && options->output_name ? options->output_name : "", r, {0}, 0};
	size_t size = 0;
	FILE *f = open_memstream(json, &size);
	if (!f)
		return dp_fail(err, DP_ERR_NOMEM, "report: out of memory");
	dp_json_writer w;
	dp_json_begin(&w, f);
	fill_report(&w, &a);
	dp_json_finish(&w);
	if (fclose(f) != 0) {
		free(*json);
		*json = NULL;
		return dp_fail(err, DP_ERR_NOMEM, "report: out of memory");
	}
	return DP_OK;
}

void dp_write_options_default(dp_write_options *o)
{
	memset(o, 0, sizeof *o);
	o->up_axis = 1;
}

dp_status dp_result_write(const dp_result *r, const char *dir, const dp_write_options *options, dp_error *err)
{
	dp_write_options defaults;
	if (!options) {
		dp_write_options_default(&defaults);
		options = &defaults;
	}
	if (!r || !dir)
		return dp_fail(err, DP_ERR_ARG, "write: NULL result or folder");
	if (r->surface.n == 0 || !r->surface.nx || !r->skeleton.x || r->skeleton.n != r->surface.n || !r->length ||
	    !r->eta)
		return dp_fail(err, DP_ERR_ARG, "write: %s: the result holds no deep points", dir);
	if (options->up_axis < 0 || options->up_axis > 2)
		return dp_fail(err, DP_ERR_ARG, "write: up axis %d is not 0, 1 or 2", options->up_axis);
	int ascii = (options->flags & DP_WRITE_ASCII) != 0;
	report_arg a = {options->input_name ? options->input_name : "", options->output_name ? options->output_name : dir,
			r, {0}, 0};
	size_t n = r->surface.n;
	dp_status st;
	const dp_ply_property surface_props[] = {
		{"x", r->surface.x},   {"y", r->surface.y},   {"z", r->surface.z},
		{"nx", r->surface.nx}, {"ny", r->surface.ny}, {"nz", r->surface.nz},
		{"length", r->length}, {"eta", r->eta},	      {"intensity", r->surface.intensity},
	};
	/* the input's intensities, when the caller carried them onto the surface */
	size_t nsurface = r->surface.intensity ? 9 : 8;
	if ((st = write_ply(&a, dir, "surface.ply", n, surface_props, nsurface, NULL, 0, ascii, err)) != DP_OK)
		return st;
	const dp_ply_property skeleton_props[] = {{"x", r->skeleton.x}, {"y", r->skeleton.y}, {"z", r->skeleton.z}};
	if ((st = write_ply(&a, dir, "skeleton.ply", n, skeleton_props, 3, NULL, 0, ascii, err)) != DP_OK)
		return st;

	/* deep points: surface ends 0..n-1, inner ends n..2n-1, edge i joins i and n+i */
	float *xyz = dp_alloc_array(6 * n, sizeof(float));
	uint32_t *edges = dp_alloc_array(2 * n, sizeof(uint32_t));
	if (!xyz || !edges) {
		free(xyz);
		free(edges);
		return dp_fail(err, DP_ERR_NOMEM, "write: out of memory for %zu deep points", n);
	}
	dp_cloud ends = {0};
	ends.n = 2 * n;
	ends.x = xyz;
	ends.y = xyz + 2 * n;
	ends.z = xyz + 4 * n;
	for (size_t i = 0; i < n; i++) {
		ends.x[i] = r->surface.x[i];
		ends.y[i] = r->surface.y[i];
		ends.z[i] = r->surface.z[i];
		ends.x[n + i] = r->skeleton.x[i];
		ends.y[n + i] = r->skeleton.y[i];
		ends.z[n + i] = r->skeleton.z[i];
		edges[2 * i] = (uint32_t)i;
		edges[2 * i + 1] = (uint32_t)(n + i);
	}
	const dp_ply_property dp_props[] = {{"x", ends.x}, {"y", ends.y}, {"z", ends.z}};
	st = write_ply(&a, dir, "dpoints.ply", 2 * n, dp_props, 3, edges, n, ascii, err);
	if (st == DP_OK && (options->flags & DP_WRITE_STAGES)) {
		st = write_stage(&a, dir, "wlop.ply", &r->wlop, ascii, err);
		if (st == DP_OK)
			st = write_anchors(&a, dir, r, ascii, err);
	}
	if (st == DP_OK && (options->flags & DP_WRITE_RENDER))
		st = render_result(&a, options->input, &ends, edges, options->up_axis, dir, err);
	free(xyz);
	free(edges);
	if (st != DP_OK)
		return st;
	return write_report(&a, dir, err);
}
