/* Pictures of a consolidate result: what went in and what came out. */
#include "cli/consolidate.h"

#include <stdio.h>

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

dp_status dp_cli_render_result(const dp_cloud *in, const dp_result *r, const float *x, const float *y,
			       const float *z, const uint32_t *edges, int up_axis, const char *dir, dp_error *err)
{
	size_t n = r->surface.n;
	dp_status st;
	dp_render_layer layer = {0};
	layer.cloud = in;
	for (int k = 0; k < 3; k++)
		layer.rgb[k] = INPUT_RGB[k];
	if ((st = render(dir, "input.png", &layer, 1, up_axis, err)) != DP_OK)
		return st;
	layer.cloud = &r->skeleton;
	for (int k = 0; k < 3; k++)
		layer.rgb[k] = SKELETON_RGB[k];
	if ((st = render(dir, "skeleton.png", &layer, 1, up_axis, err)) != DP_OK)
		return st;
	layer.cloud = &r->surface;
	for (int k = 0; k < 3; k++)
		layer.rgb[k] = SURFACE_RGB[k];
	if ((st = render(dir, "surface.png", &layer, 1, up_axis, err)) != DP_OK)
		return st;

	/* deep points: grey sticks with red surface ends and blue inner ends */
	dp_cloud ends = {0};
	ends.n = 2 * n;
	ends.x = (float *)x;
	ends.y = (float *)y;
	ends.z = (float *)z;
	dp_render_layer layers[3] = {{0}, {0}, {0}};
	layers[0].cloud = &ends;
	layers[0].edges = edges;
	layers[0].nedges = n;
	layers[0].segments_only = 1;
	layers[1].cloud = &r->surface;
	layers[2].cloud = &r->skeleton;
	for (int k = 0; k < 3; k++) {
		layers[0].rgb[k] = STICK_RGB[k];
		layers[1].rgb[k] = SURFACE_RGB[k];
		layers[2].rgb[k] = SKELETON_RGB[k];
	}
	return render(dir, "dpoints.png", layers, 3, up_axis, err);
}
