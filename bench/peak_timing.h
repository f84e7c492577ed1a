/* Timing of the peak operator (kernels/peak.cl, its row in ops/operators.h) on given
 * points, radius and reach: the ceiling bench_peak prints and bench_stages
 * prints beside every operator. */
#ifndef DP_BENCH_PEAK_TIMING_H
#define DP_BENCH_PEAK_TIMING_H

#include "backend/context.h"
#include "backend/ops.h"
#include "core/common.h"

#include <string.h>

/* Launches are repeated until they have run this long (and at least
 * PEAK_MIN_LAUNCHES times), after one untimed launch that uploads the data
 * (and compiles the kernel, the first time). */
#define PEAK_MIN_SECONDS 0.3
#define PEAK_MIN_LAUNCHES 3

typedef struct peak_result {
	double seconds;    /* per launch */
	double launches;
	double candidates; /* per launch */
	double neighbours; /* per launch: pairs within the radius */
	float cell;        /* the grid's actual cell */
	int cells_reach;   /* cells scanned per side */
} peak_result;

/* The kernel seconds dp_cl_launch measured for peak_pairs so far. */
static inline double peak_kernel_seconds(const dp_context *ctx)
{
	for (size_t i = 0; i < ctx->cl.nkernels; i++)
		if (!strcmp(ctx->cl.kernels[i].name, "peak_pairs"))
			return ctx->cl.kernels[i].stats.seconds;
	return 0.0;
}

/* Queries q over a grid of data, both from the caller; count and sum hold
 * q->n floats. On the OpenCL backend the time is dp_cl_launch's (as for every
 * operator line), on the reference the wall time of dp_ref_peak; neither
 * includes the grid build or the host's candidate count. The candidates are
 * the ones the dispatcher counts; the operators' true-neighbour counts are
 * left alone (the peak counts its own, in count). */
static inline dp_status peak_measure(dp_context *ctx, const dp_cloud *data, const dp_cloud *q, float radius,
				     int reach, float *count, float *sum, peak_result *out, dp_error *err)
{
	dp_grid g = {0};
	struct dp_neighbour_counts *counting = ctx->neighbours;
	ctx->neighbours = NULL;
	memset(out, 0, sizeof *out);
	dp_status st = dp_peak_grid(&g, data->n, data->x, data->y, data->z, radius, reach, &out->cells_reach, err);
	if (st != DP_OK)
		goto done;
	out->cell = g.cell;
	dp_peak_args a = {.data = &g, .nq = q->n, .qx = q->x, .qy = q->y, .qz = q->z, .radius = radius,
			  .reach = out->cells_reach, .count = count, .sum = sum};
	double before = ctx->pair_evaluations;
	if ((st = dp_op_peak(ctx, &a, err)) != DP_OK)
		goto done;
	out->candidates = ctx->pair_evaluations - before;
	for (size_t i = 0; i < q->n; i++)
		out->neighbours += count[i];
	int cl = dp_context_backend(ctx) == DP_BACKEND_CL;
	double spent = 0.0;
	while (spent < PEAK_MIN_SECONDS || out->launches < PEAK_MIN_LAUNCHES) {
		double t0 = cl ? peak_kernel_seconds(ctx) : dp_seconds();
		if (cl)
			st = dp_op_peak(ctx, &a, err);
		else
			dp_ref_peak(&a);
		if (st != DP_OK)
			goto done;
		spent += (cl ? peak_kernel_seconds(ctx) : dp_seconds()) - t0;
		out->launches += 1.0;
	}
	out->seconds = spent / out->launches;
done:
	ctx->neighbours = counting;
	dp_grid_free(&g);
	return st;
}

#endif
