/* The dp_context behind the public opaque handle: which backend runs the
 * operators, and for OpenCL the opened device with its built program. */
#ifndef DP_BACKEND_CONTEXT_H
#define DP_BACKEND_CONTEXT_H

#include "cl/runtime.h"

struct dp_context {
	dp_backend_kind kind;
	dp_cl cl;              /* opened only for DP_BACKEND_CL */
	double pair_evaluations; /* neighbour pairs visited by operators, for reports */
	struct dp_neighbour_counts *neighbours; /* benchmarks: true neighbours counted when set */
	dp_progress_fn progress;
	void *progress_user;
	double started;          /* dp_seconds() at creation, for progress reports */
	int threads;             /* host loops' threads (core/parallel.h), >= 1 */
};

/* Reports one iteration of a stage to the progress callback, if any.
 * DP_ERR_CANCELLED (err says which stage and iteration) when the callback
 * asked to stop: the stage then ends as on any error. */
dp_status dp_progress(dp_context *ctx, const char *stage, int iteration, double value, dp_error *err);

/* Pairs closer than DP_PAIR_EPS times the operator's radius are skipped by
 * every neighbour sum: they are a point and itself, or exact duplicates, and
 * the 1/d weights of WLOP and the L1 terms would be infinite there. */
#define DP_PAIR_EPS 1e-5f

#endif
