/* dpoints eval: metrics of a point set against a ground-truth mesh. */
#include "cli/session.h"
#include "core/common.h"

int dp_cmd_eval(int argc, char **argv)
{
	const char *cmd = "eval";
	dp_eval_params ep;
	dp_eval_params_default(&ep);
	int json = 0;
	cli_opt opts[] = {
		{"--json", CLI_FLAG, &json, "print one JSON object instead of text", NULL, NULL},
		{"--samples", CLI_SIZE, &ep.samples, "surface samples for completeness and coverage", NULL, NULL},
		{"--coverage-factor", CLI_DOUBLE, &ep.coverage_factor,
		 "a sample is covered within this many mean point spacings", NULL, NULL},
		{"--seed", CLI_U64, &ep.seed, "surface sampling seed", NULL, NULL},
	};
	const char *pos[2];
	size_t npos;
	int help;
	int rc = cli_parse(cmd, "GROUND_TRUTH_MESH POINTS [options]", argc, argv, 2, opts,
			   sizeof opts / sizeof opts[0], pos, 2, &npos, &help);
	if (rc || help)
		return rc;
	if (npos != 2) {
		fprintf(stderr, "dpoints %s: needs GROUND_TRUTH_MESH and POINTS (see dpoints %s --help)\n", cmd, cmd);
		return DP_EXIT_INPUT;
	}
	dp_error err = {0};
	dp_cloud mesh = {0}, points = {0};
	dp_eval_result r;
	/* a bad option is no file's fault: said before reading, without a name */
	if (dp_eval_params_check(&ep, &err) != DP_OK)
		goto fail;
	if (dp_cloud_read(pos[0], &mesh, DP_READ_MESH, &err) != DP_OK)
		goto fail;
	if (mesh.nfaces == 0) {
		dp_fail(&err, DP_ERR_FORMAT, "%s: has no faces; the ground truth must be a triangle mesh", pos[0]);
		goto fail;
	}
	if (dp_cloud_read(pos[1], &points, DP_READ_POINTS, &err) != DP_OK)
		goto fail;
	if (dp_eval(&mesh, &points, &ep, &r, &err) != DP_OK) {
		/* the library's message says whether the mesh or the points */
		char both[4096];
		snprintf(both, sizeof both, "%s, %s", pos[0], pos[1]);
		dp_cli_name_input(&err, both);
		goto fail;
	}
	if (json) {
		dp_eval_json(&r, stdout);
	} else {
		printf("points                 %zu (against %zu surface samples; lengths in bbox diagonals = %g)\n",
		       r.points, r.samples, r.diagonal);
		printf("accuracy mean / p95    %.6f / %.6f\n", r.accuracy_mean, r.accuracy_p95);
		printf("completeness mean      %.6f\n", r.completeness_mean);
		printf("coverage               %.4f (within %.6f)\n", r.coverage, r.coverage_radius);
		printf("spacing mean / CV      %.6f / %.4f\n", r.spacing_mean, r.spacing_cv);
		printf("scatter (median)       %.4f\n", r.scatter_median);
		if (r.has_normals)
			printf("normal error / flipped %.2f deg / %.4f (clear %.4f)\n", r.normal_angle_deg, r.normal_flipped,
			       r.normal_flipped_clear);
		else
			printf("normals                none in %s\n", pos[1]);
	}
	dp_cloud_free(&mesh);
	dp_cloud_free(&points);
	return DP_EXIT_OK;
fail:
	dp_cloud_free(&mesh);
	dp_cloud_free(&points);
	return dp_cli_fail(cmd, &err);
}
