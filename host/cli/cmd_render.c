/* dpoints render: point sets (and deep points as segments) to a PNG. */
#include "cli/session.h"
#include "core/common.h"

#include <stdlib.h>
#include <string.h>

#define MAX_LAYERS 16

int dp_cmd_render(int argc, char **argv)
{
	const char *cmd = "render";
	dp_render_params rp;
	dp_render_params_default(&rp);
	const char *output = NULL;
	int up = rp.up_axis;
	double point_size = 0.0;
	cli_opt opts[] = {
		{"--output", CLI_STRING, &output, "output PNG", NULL, NULL},
		{"--views", CLI_INT, &rp.views, "views side by side, orbiting the vertical axis", NULL, NULL},
		{"--size", CLI_INT, &rp.width, "pixels per (square) view", NULL, NULL},
		{"--up", CLI_CHOICE, &up, "vertical axis", "x|y|z", NULL},
		{"--elevation", CLI_DOUBLE, &rp.elevation_deg, "camera height above the horizon, degrees", NULL, NULL},
		{"--azimuth", CLI_DOUBLE, &rp.azimuth_deg, "azimuth of the first view, degrees", NULL, NULL},
		{"--point-size", CLI_DOUBLE, &point_size, "splat diameter in pixels (0 = automatic)", NULL, NULL},
	};
	const char *pos[MAX_LAYERS];
	size_t npos;
	int help;
	int rc = cli_parse(cmd, "A.ply[:COLOUR] [B.ply[:COLOUR] ...] -o OUT.png [options]", argc, argv, 2, opts,
			   sizeof opts / sizeof opts[0], pos, MAX_LAYERS, &npos, &help);
	if (rc || help)
		return rc;
	if (npos == 0 || !output) {
		fprintf(stderr, "dpoints %s: needs at least one point file and -o OUT.png (see dpoints %s --help)\n",
			cmd, cmd);
		return DP_EXIT_INPUT;
	}
	rp.up_axis = up;
	if ((rc = cli_check_output(cmd, output)))
		return rc;

	dp_error err = {0};
	dp_cloud clouds[MAX_LAYERS];
	dp_render_layer layers[MAX_LAYERS];
	uint32_t *edges[MAX_LAYERS] = {0};
	memset(clouds, 0, sizeof clouds);
	memset(layers, 0, sizeof layers);
	size_t n = 0;
	for (; n < npos; n++) {
		char path[4096];
		snprintf(path, sizeof path, "%s", pos[n]);
		dp_render_default_colour(n, layers[n].rgb);
		/* "file:colour" only when the suffix is a colour: paths may hold ':' */
		char *colon = strrchr(path, ':');
		dp_error not_colour = {0};
		if (colon && dp_parse_colour(colon + 1, layers[n].rgb, &not_colour) == DP_OK)
			*colon = '\0';
		if (dp_cloud_read(path, &clouds[n], DP_READ_POINTS, &err) != DP_OK)
			goto fail;
		if (dp_ply_read_edges(path, &edges[n], &layers[n].nedges, &err) != DP_OK)
			goto fail;
		layers[n].cloud = &clouds[n];
		layers[n].edges = edges[n];
		layers[n].point_size_px = (float)point_size;
	}
	if (dp_render_png(output, layers, n, &rp, &err) != DP_OK)
		goto fail;
	printf("render: %zu layer%s, %d view%s of %d px -> %s\n", n, n == 1 ? "" : "s", rp.views,
	       rp.views == 1 ? "" : "s", rp.width, output);
	rc = DP_EXIT_OK;
	goto done;
fail:
	rc = dp_cli_fail(cmd, &err);
done:
	for (size_t i = 0; i < MAX_LAYERS; i++) {
		free(edges[i]);
		dp_cloud_free(&clouds[i]);
	}
	return rc;
}
