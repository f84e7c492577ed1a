/* dpoints scan: virtual range scan of a mesh file or a built-in shape. */
#include "cli/session.h"
#include "core/common.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

int dp_cmd_scan(int argc, char **argv)
{
	const char *cmd = "scan";
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	const char *output = NULL, *shape_name = NULL, *mesh_out = NULL;
	int ascii = 0, no_normals = 0, layout = (int)sp.layout, shape_res = 0;
	cli_opt opts[] = {
		{"--output", CLI_STRING, &output, "output PLY of the scanned points; - for standard output", NULL, NULL},
		{"--shape", CLI_STRING, &shape_name, "built-in shape: sphere, cylinder, slab, torus, knot, chair, rods",
		 NULL, NULL},
		{"--shape-res", CLI_INT, &shape_res, "triangulation resolution of the built-in shape (0 = its default)",
		 NULL, NULL},
		{"--mesh-out", CLI_STRING, &mesh_out, "also write the scanned mesh (the ground truth for eval); - for standard output", NULL,
		 NULL},
		{"--views", CLI_INT, &sp.views, "number of viewpoints", NULL, NULL},
		{"--res", CLI_INT, &sp.res, "rays per view: res x res", NULL, NULL},
		{"--noise", CLI_DOUBLE, &sp.noise, "Gaussian noise sigma, in bounding-box diagonals", NULL, NULL},
		{"--layout", CLI_CHOICE, &layout, "viewpoints on a ring around z, or spread over a sphere",
		 "ring|sphere", NULL},
		{"--elevation", CLI_DOUBLE, &sp.elevation_deg, "ring: eye height angle in degrees", NULL, NULL},
		{"--azimuth", CLI_DOUBLE, &sp.azimuth_deg, "ring: azimuth of the first view in degrees", NULL, NULL},
		{"--distance", CLI_DOUBLE, &sp.distance, "eye distance from the centre, in bbox diagonals", NULL, NULL},
		{"--seed", CLI_U64, &sp.seed, "noise seed", NULL, NULL},
		{"--no-normals", CLI_FLAG, &no_normals, "do not write the true normals of the hits", NULL, NULL},
		{"--ascii", CLI_FLAG, &ascii, "write ascii PLY", NULL, NULL},
	};
	const char *pos[1];
	size_t npos;
	int help;
	int rc = cli_parse(cmd, "MESH|--shape NAME -o OUT.ply [options]", argc, argv, 2, opts,
			   sizeof opts / sizeof opts[0], pos, 1, &npos, &help);
	if (rc || help)
		return rc;
	if ((npos == 1) == (shape_name != NULL) || !output) {
		fprintf(stderr, "dpoints %s: needs one of MESH or --shape NAME, and -o OUT.ply (see dpoints %s --help)\n",
			cmd, cmd);
		return DP_EXIT_INPUT;
	}
	sp.layout = (dp_scan_layout)layout;
	sp.normals = !no_normals;
	int to_stdout = cli_is_stdout(output), mesh_stdout = mesh_out && cli_is_stdout(mesh_out);
	if (to_stdout && mesh_stdout) {
		fprintf(stderr, "dpoints %s: -o - and --mesh-out -: only one output can go to standard output\n", cmd);
		return DP_EXIT_INPUT;
	}
	if ((!to_stdout && (rc = cli_check_output(cmd, output))) ||
	    (mesh_out && !mesh_stdout && (rc = cli_check_output(cmd, mesh_out))))
		return rc;
	if ((!to_stdout && (rc = cli_check_not_input(cmd, output, pos, npos))) ||
	    (mesh_out && !mesh_stdout && (rc = cli_check_not_input(cmd, mesh_out, pos, npos))) ||
	    (mesh_out && !to_stdout && !mesh_stdout && (rc = cli_check_distinct_outputs(cmd, mesh_out, output))))
		return rc;

	dp_error err = {0};
	dp_cloud mesh = {0}, points = {0};
	/* a bad option is no file's fault: said before reading, without a name */
	if (dp_scan_params_check(&sp, &err) != DP_OK)
		goto fail;
	if (shape_name) {
		dp_shape shape;
		if (dp_shape_default(shape_name, &shape, &err) != DP_OK)
			goto fail;
		if (shape_res)
			shape.resolution = shape_res;
		if (dp_shape_mesh(&shape, &mesh, &err) != DP_OK)
			goto fail;
	} else if (dp_cloud_read(pos[0], &mesh, DP_READ_MESH, &err) != DP_OK) {
		goto fail;
	} else if (mesh.nfaces == 0) {
		dp_fail(&err, DP_ERR_FORMAT, "%s: has no faces; scan needs a triangle mesh", pos[0]);
		goto fail;
	}
	if (dp_scan(&mesh, &sp, &points, NULL, &err) != DP_OK) {
		if (!shape_name)
			dp_cli_name_input(&err, pos[0]);
		goto fail;
	}
	/* The mesh goes under a temporary name until the scan is written, so a
	 * run that fails leaves both files as they were; only the last rename
	 * can fail after the scan is in place, and its error says so. A mesh
	 * for stdout is written last instead. */
	char mesh_tmp[4096] = "";
	if (mesh_out && !mesh_stdout) {
		int len = snprintf(mesh_tmp, sizeof mesh_tmp, "%s.tmp.%ld", mesh_out, (long)getpid());
		if (len < 0 || (size_t)len >= sizeof mesh_tmp) {
			dp_fail(&err, DP_ERR_IO, "%s: the path is too long", mesh_out);
			goto fail;
		}
		if (dp_cloud_write_ply(mesh_tmp, &mesh, ascii, &err) != DP_OK)
			goto fail;
	}
	if ((rc = cli_write_ply(cmd, output, &points, ascii))) {
		if (*mesh_tmp)
			remove(mesh_tmp);
		goto done;
	}
	if (*mesh_tmp && rename(mesh_tmp, mesh_out) != 0) {
		dp_fail(&err, DP_ERR_IO, "%s: cannot move the mesh into place: %s (the scan is in %s)", mesh_out,
			strerror(errno), to_stdout ? "standard output" : output);
		remove(mesh_tmp);
		goto fail;
	}
	if (mesh_stdout && (rc = cli_write_ply(cmd, mesh_out, &mesh, ascii)))
		goto done;
	/* with -o - or --mesh-out - stdout is that file */
	fprintf(to_stdout || mesh_stdout ? stderr : stdout,
		"scan: %s (%zu triangles), %d view%s of %dx%d rays, noise %g diagonals -> %zu points in %s\n",
		shape_name ? shape_name : pos[0], mesh.nfaces, sp.views, sp.views == 1 ? "" : "s", sp.res, sp.res,
		sp.noise, points.n, output);
	rc = DP_EXIT_OK;
	goto done;
fail:
	rc = dp_cli_fail(cmd, &err);
done:
	dp_cloud_free(&mesh);
	dp_cloud_free(&points);
	return rc;
}
