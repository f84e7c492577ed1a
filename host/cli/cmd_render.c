/* dpoints render: point sets (and deep points as segments) to a PNG. */
#include "cli/caption.h"
#include "cli/session.h"
#include "core/common.h"
#include "tools/png_write.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_FILES 16
/* a deep-points file alone becomes three layers: two ends and the sticks */
#define MAX_LAYERS (MAX_FILES + 2)

#define COLOUR_NAMES "red, green, blue, orange, purple, yellow, cyan, magenta, pink, brown, grey, black, white"

static const unsigned char caption_ink[3] = {60, 60, 60}, stick_rgb[3] = {150, 150, 150};

static int is_file(const char *path)
{
	struct stat sb;
	return stat(path, &sb) == 0 && !S_ISDIR(sb.st_mode);
}

/* "file:colour" only when the suffix is a colour, since paths may hold ':';
 * a suffix that is not one, after a file that exists, is a misspelt colour. */
static int split_colour(const char *cmd, const char *arg, char *path, size_t size, unsigned char rgb[3],
			int *given)
{
	snprintf(path, size, "%s", arg);
	*given = 0;
	char *colon = strrchr(path, ':');
	if (!colon || is_file(path))
		return 0;
	dp_error err = {0};
	if (dp_parse_colour(colon + 1, rgb, &err) == DP_OK) {
		*colon = '\0';
		*given = 1;
		return 0;
	}
	*colon = '\0';
	if (!is_file(path)) {
		*colon = ':';
		return 0;
	}
	fprintf(stderr, "dpoints %s: %s: '%s' is not a colour: a name (" COLOUR_NAMES ") or #rgb / #rrggbb\n", cmd,
		arg, colon + 1);
	return DP_EXIT_INPUT;
}

/* The ends of `edges` into two clouds: first ends (the surface ends of a
 * dpoints.ply) and second ends (the inner ends), so each gets its colour. */
static dp_status split_ends(const dp_cloud *c, const uint32_t *edges, size_t nedges, dp_cloud *a, dp_cloud *b,
			    dp_error *err)
{
	dp_status st = dp_cloud_alloc(a, nedges, 0, err);
	if (st == DP_OK)
		st = dp_cloud_alloc(b, nedges, 0, err);
	for (size_t e = 0; st == DP_OK && e < nedges; e++) {
		uint32_t i = edges[2 * e], j = edges[2 * e + 1];
		a->x[e] = c->x[i];
		a->y[e] = c->y[i];
		a->z[e] = c->z[i];
		b->x[e] = c->x[j];
		b->y[e] = c->y[j];
		b->z[e] = c->z[j];
	}
	return st;
}

static const char *base_name(const char *path)
{
	const char *slash = strrchr(path, '/');
	return slash ? slash + 1 : path;
}

/* Under each view: the files and their point counts, then the view. */
static void draw_captions(unsigned char *rgb, int w, int h, const dp_render_params *rp, const char *const *files,
			  const dp_cloud *clouds, size_t nfiles)
{
	char what[1024] = "";
	size_t len = 0;
	for (size_t f = 0; f < nfiles && len < sizeof what; f++)
		len += (size_t)snprintf(what + len, sizeof what - len, "%s%s %zu points", f ? ", " : "",
					base_name(files[f]), clouds[f].n);
	int s = dp_cli_caption_scale(rp->width), line = 7 * s;
	for (int k = 0; k < rp->views; k++) {
		char view[128];
		double az = fmod(rp->azimuth_deg + 360.0 * k / rp->views, 360.0);
		snprintf(view, sizeof view, "view %d/%d azimuth %.0f elevation %.0f up %c", k + 1, rp->views, az,
			 rp->elevation_deg, "xyz"[rp->up_axis]);
		int x0 = k * rp->width + 2 * s, x1 = (k + 1) * rp->width - 2 * s;
		dp_cli_draw_text(rgb, w, h, x0, h - 2 * line, x1, what, s, caption_ink);
		dp_cli_draw_text(rgb, w, h, x0, h - line, x1, view, s, caption_ink);
	}
}

typedef struct png_job {
	const unsigned char *rgb;
	int w, h;
} png_job;

static dp_status write_png(const char *path, const void *varg, dp_error *err)
{
	const png_job *job = varg;
	return dp_png_write_rgb(path, job->rgb, job->w, job->h, err);
}

int dp_cmd_render(int argc, char **argv)
{
	const char *cmd = "render";
	dp_render_params rp;
	dp_render_params_default(&rp);
	const char *output = NULL;
	int up = rp.up_axis, up_given = 0, no_caption = 0;
	double point_size = 0.0;
	cli_opt opts[] = {
		{"--output", CLI_STRING, &output, "output PNG; - for standard output", NULL, NULL},
		{"--views", CLI_INT, &rp.views, "views side by side, orbiting the vertical axis", NULL, NULL},
		{"--size", CLI_INT, &rp.width, "pixels per (square) view", NULL, NULL},
		{"--up", CLI_CHOICE, &up, "vertical axis (default: z where the data is clearly taller in z than in y, else y)",
		 "x|y|z", &up_given},
		{"--elevation", CLI_DOUBLE, &rp.elevation_deg, "camera height above the horizon, degrees", NULL, NULL},
		{"--azimuth", CLI_DOUBLE, &rp.azimuth_deg, "azimuth of the first view, degrees", NULL, NULL},
		{"--point-size", CLI_DOUBLE, &point_size, "splat diameter in pixels (0 = automatic)", NULL, NULL},
		{"--no-caption", CLI_FLAG, &no_caption, "no caption (files, point counts, view) under each view", NULL,
		 NULL},
	};
	const char *pos[MAX_FILES];
	size_t npos;
	int help;
	int rc = cli_parse(cmd,
			   "A.ply[:COLOUR] [B.ply[:COLOUR] ...] -o OUT.png [options]\n"
			   "COLOUR is a name (" COLOUR_NAMES ") or #rgb / #rrggbb",
			   argc, argv, 2, opts, sizeof opts / sizeof opts[0], pos, MAX_FILES, &npos, &help);
	if (rc || help)
		return rc;
	if (npos == 0 || !output) {
		fprintf(stderr, "dpoints %s: needs at least one point file and -o OUT.png (see dpoints %s --help)\n",
			cmd, cmd);
		return DP_EXIT_INPUT;
	}
	int to_stdout = cli_is_stdout(output);
	if (!to_stdout && (rc = cli_check_output(cmd, output)))
		return rc;

	dp_error err = {0};
	dp_cloud clouds[MAX_LAYERS];
	dp_render_layer layers[MAX_LAYERS];
	uint32_t *edges[MAX_FILES] = {0};
	char paths[MAX_FILES][4096];
	const char *files[MAX_FILES];
	int given[MAX_FILES];
	unsigned char *rgb = NULL;
	memset(clouds, 0, sizeof clouds);
	memset(layers, 0, sizeof layers);
	size_t n = 0, nlayers = 0;
	for (; n < npos; n++) {
		dp_render_default_colour(n, layers[n].rgb);
		if ((rc = split_colour(cmd, pos[n], paths[n], sizeof paths[n], layers[n].rgb, &given[n])))
			goto done;
		files[n] = paths[n];
		if (dp_cloud_read(paths[n], &clouds[n], DP_READ_POINTS, &err) != DP_OK)
			goto fail;
		if (dp_ply_read_edges(paths[n], &edges[n], &layers[n].nedges, &err) != DP_OK)
			goto fail;
		layers[n].cloud = &clouds[n];
		layers[n].edges = edges[n];
		layers[n].point_size_px = (float)point_size;
	}
	nlayers = n;
	if (n == 1 && layers[0].nedges && !given[0]) {
		/* deep points alone: surface ends, inner ends, and grey sticks between */
		if (split_ends(&clouds[0], edges[0], layers[0].nedges, &clouds[1], &clouds[2], &err) != DP_OK)
			goto fail;
		layers[0].segments_only = 1;
		memcpy(layers[0].rgb, stick_rgb, 3);
		for (int l = 1; l <= 2; l++) {
			layers[l].cloud = &clouds[l];
			layers[l].point_size_px = (float)point_size;
			dp_render_default_colour((size_t)l - 1, layers[l].rgb);
		}
		nlayers = 3;
	}
	rp.up_axis = up_given ? up : dp_cli_detect_up(clouds, n);
	int w, h;
	if (dp_render_rgb(layers, nlayers, &rp, &rgb, &w, &h, &err) != DP_OK) {
		/* name the picture not made, as dp_render_png does */
		dp_cli_name_input(&err, output);
		goto fail;
	}
	if (!no_caption)
		draw_captions(rgb, w, h, &rp, files, clouds, n);
	png_job job = {rgb, w, h};
	if ((rc = cli_write_file(cmd, output, write_png, &job)))
		goto done;
	/* with -o - stdout is the picture */
	fprintf(to_stdout ? stderr : stdout, "render: %zu file%s, %d view%s of %d px, up %c%s -> %s\n", n, n == 1 ? "" : "s", rp.views,
	       rp.views == 1 ? "" : "s", rp.width, "xyz"[rp.up_axis], up_given ? "" : " (from the data; --up sets it)",
	       output);
	rc = DP_EXIT_OK;
	goto done;
fail:
	rc = dp_cli_fail(cmd, &err);
done:
	free(rgb);
	for (size_t i = 0; i < MAX_FILES; i++)
		free(edges[i]);
	for (size_t i = 0; i < MAX_LAYERS; i++)
		dp_cloud_free(&clouds[i]);
	return rc;
}
