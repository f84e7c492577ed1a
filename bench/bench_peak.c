/* The peak microbenchmark (issue 8): the bare pair loop of every kernel
 * (kernels/peak.cl: a count and Σ exp(-d²/radius²) over the grid candidates
 * within the radius) on real scans, OpenCL and the scalar reference on the
 * same input in one run, as JSON lines. Each point of the input queries all
 * of them, at radii of a few times the mean spacing r (the operators' radii:
 * WLOP's h, sinking's and the surface's sigma_p r = 5 r, the normals' 3 r)
 * and on grids of 1, 2 or 3 cells per radius, scanning 3, 5 or 7 cells per
 * axis: a finer grid scans fewer candidates for the same neighbours, at more,
 * shorter rows. "cell_r" and "cells_reach" give the grid actually built (the
 * cap on cells per point can make the cell larger than radius / reach).
 *
 *   bench_peak [--radii R,...] [--reaches K,...] [--input FILE] [--no-ref] [--device D] [--data DIR]
 */
#include "peak_timing.h"

#include "dpoints_tools.h"
#include "knn/knn.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_RADII "2,3,5"
#define DEFAULT_REACHES "1,2,3"
#define MAX_LIST 8
/* the scans of the paper's Table 1 in the shared data folder */
static const char *const data_inputs[] = {"paper/statue-fig12b-raw.xyz", "paper/loops-fig10t-raw.ply"};

typedef struct options {
	double radii[MAX_LIST];
	int nradii;
	int reaches[MAX_LIST];
	int nreaches;
	const char *input, *device, *data;
	int ref;
} options;

static int parse_list(const char *text, double *out, int *n)
{
	*n = 0;
	while (*text) {
		char *end;
		double v = strtod(text, &end);
		if (end == text || !(v > 0.0) || *n == MAX_LIST || (*end && *end != ','))
			return -1;
		out[(*n)++] = v;
		text = *end ? end + 1 : end;
	}
	return *n ? 0 : -1;
}

static int parse_options(int argc, char **argv, options *o)
{
	memset(o, 0, sizeof *o);
	o->ref = 1;
	o->data = getenv("DP_DATA_DIR") ? getenv("DP_DATA_DIR") : "../shared/data";
	double reaches[MAX_LIST];
	parse_list(DEFAULT_RADII, o->radii, &o->nradii);
	parse_list(DEFAULT_REACHES, reaches, &o->nreaches);
	for (int a = 1; a < argc; a++) {
		const char *arg = argv[a], *val = a + 1 < argc ? argv[a + 1] : NULL;
		if (!strcmp(arg, "--no-ref")) {
			o->ref = 0;
			continue;
		}
		if (!val)
			return -1;
		if (!strcmp(arg, "--radii") && parse_list(val, o->radii, &o->nradii) == 0) {
		} else if (!strcmp(arg, "--reaches") && parse_list(val, reaches, &o->nreaches) == 0) {
		} else if (!strcmp(arg, "--input")) {
			o->input = val;
		} else if (!strcmp(arg, "--device")) {
			o->device = val;
		} else if (!strcmp(arg, "--data")) {
			o->data = val;
		} else {
			return -1;
		}
		a++;
	}
	for (int i = 0; i < o->nreaches; i++) {
		if (reaches[i] != floor(reaches[i]) || reaches[i] > DP_GRID_MAX_MARGIN)
			return -1;
		o->reaches[i] = (int)reaches[i];
	}
	return 0;
}

static void print_line(const char *input, const dp_cloud *c, double r, double radius_r, int reach,
		       dp_context *ctx, const peak_result *p)
{
	printf("{\"what\":\"peak\",\"input\":\"%s\",\"size\":%zu,\"queries\":%zu,\"radius_r\":%g,\"r\":%.6g,"
	       "\"reach_asked\":%d,\"cells_reach\":%d,\"cell_r\":%.4g,\"backend\":\"%s\",\"device\":\"%s\","
	       "\"seconds\":%.6f,\"iterations\":%.0f,\"pair_evaluations\":%.6g,\"pair_evals_per_s\":%.4g,"
	       "\"neighbour_pairs\":%.6g,\"neighbour_pairs_per_s\":%.4g,\"neighbours_per_candidate\":%.4f}\n",
	       input, c->n, c->n, radius_r, r, reach, p->cells_reach, p->cell / r,
	       dp_context_backend(ctx) == DP_BACKEND_CL ? "cl" : "ref", dp_context_device_name(ctx), p->seconds,
	       p->launches, p->candidates, p->candidates / p->seconds, p->neighbours, p->neighbours / p->seconds,
	       p->candidates > 0 ? p->neighbours / p->candidates : 0.0);
	fflush(stdout);
}

/* Every radius and reach on one input, each on OpenCL then the reference. */
static int run_input(const options *o, dp_context *cl, dp_context *ref, const char *name, const dp_cloud *c)
{
	dp_error err = {0};
	double r = 0.0;
	float *count = dp_alloc_array(c->n, sizeof(float)), *sum = dp_alloc_array(c->n, sizeof(float));
	int rc = -1;
	if (!count || !sum) {
		dp_fail(&err, DP_ERR_NOMEM, "bench_peak: out of memory");
		goto done;
	}
	if (dp_mean_spacing(c->n, c->x, c->y, c->z, &r, &err) != DP_OK)
		goto done;
	for (int i = 0; i < o->nradii; i++)
		for (int k = 0; k < o->nreaches; k++)
			for (int b = 0; b < 1 + o->ref; b++) {
				dp_context *ctx = b ? ref : cl;
				peak_result p;
				if (peak_measure(ctx, c, c, (float)(o->radii[i] * r), o->reaches[k], count, sum, &p,
						 &err) != DP_OK)
					goto done;
				print_line(name, c, r, o->radii[i], o->reaches[k], ctx, &p);
			}
	rc = 0;
done:
	if (rc)
		fprintf(stderr, "bench_peak: %s: %s\n", name, err.message);
	free(count);
	free(sum);
	return rc;
}

int main(int argc, char **argv)
{
	options o;
	if (parse_options(argc, argv, &o)) {
		fprintf(stderr, "usage: bench_peak [--radii R,...] [--reaches K,...] [--input FILE] [--no-ref] "
				"[--device D] [--data DIR]\n");
		return 2;
	}
	dp_error err = {0};
	dp_context *cl = NULL, *ref = NULL;
	if (dp_context_create(&cl, DP_BACKEND_CL, o.device, &err) != DP_OK ||
	    dp_context_create(&ref, DP_BACKEND_REF, NULL, &err) != DP_OK) {
		fprintf(stderr, "bench_peak: %s\n", err.message);
		dp_context_free(cl);
		return 1;
	}
	int rc = 0, ran = 0;
	size_t ninputs = o.input ? 1 : sizeof data_inputs / sizeof data_inputs[0];
	for (size_t i = 0; i < ninputs && !rc; i++) {
		char path[4096];
		if (o.input)
			snprintf(path, sizeof path, "%s", o.input);
		else
			snprintf(path, sizeof path, "%s/%s", o.data, data_inputs[i]);
		dp_cloud c;
		if (dp_cloud_read(path, &c, DP_READ_POINTS, &err) != DP_OK) {
			if (o.input) {
				fprintf(stderr, "bench_peak: %s\n", err.message);
				rc = 1;
			} else {
				printf("{\"what\":\"peak\",\"input\":\"%s\",\"skipped\":\"data absent or unreadable\"}\n",
				       data_inputs[i]);
				fprintf(stderr, "bench_peak: skipping %s: %s\n", path, err.message);
			}
			continue;
		}
		const char *base = strrchr(path, '/');
		rc = run_input(&o, cl, ref, base ? base + 1 : path, &c) ? 1 : 0;
		ran++;
		dp_cloud_free(&c);
	}
	if (!rc && !ran)
		fprintf(stderr, "bench_peak: no input (the shared data folder is absent): nothing measured\n");
	dp_context_free(cl);
	dp_context_free(ref);
	return rc;
}
