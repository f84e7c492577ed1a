/* Progress lines of long stages. The library reports iterations only, so the
 * caps come from the parameters the CLI passed, and a stage's end is seen
 * when the next stage (or a new run of the same one) reports, or when the
 * pipeline returns. */
#include "cli/consolidate.h"

#include <string.h>

/* WLOP under any of its progress names (dp_progress_fn). */
static int wlop_run(const char *stage)
{
	return strcmp(stage, "wlop") == 0 || strcmp(stage, "coarser") == 0 || strcmp(stage, "denser") == 0;
}

static int cap_of(const dp_cli_progress_state *st, const char *stage)
{
	const dp_params *p = st->params;
	if (!p)
		return 0;
	if (wlop_run(stage))
		return p->wlop.max_iters;
	if (strcmp(stage, "sink") == 0)
		return p->sink.max_iters;
	if (strcmp(stage, "skeleton") == 0)
		return p->skeleton.max_iters;
	if (strcmp(stage, "surface") == 0)
		return st->runs > 1 ? p->refine.level_iters : p->surface.max_iters;
	if (strcmp(stage, "even") == 0)
		return p->refine.even_iters;
	return 0;
}

/* The running stage's name as printed: refined levels are runs of the
 * surface stage after the first; even-spacing rounds and the coarser levels
 * tried are numbered. */
static const char *label(const dp_cli_progress_state *st, char *buf, size_t size)
{
	if (strcmp(st->stage, "surface") == 0 && st->runs > 1) {
		snprintf(buf, size, "level %d", st->runs - 1);
		return buf;
	}
	if (strcmp(st->stage, "even") == 0 || strcmp(st->stage, "coarser") == 0) {
		snprintf(buf, size, "%s %d", st->stage, st->runs);
		return buf;
	}
	return st->stage;
}

static void end_line(const dp_cli_progress_state *st)
{
	char name[32];
	int cap = cap_of(st, st->stage);
	const char *why;
	/* a stage that ran to its cap may have met its test in the last
	 * iteration too; report.json's converged flags settle that */
	if ((strcmp(st->stage, "surface") == 0 && st->runs > 1) || strcmp(st->stage, "even") == 0)
		why = "fixed iteration count";
	else if (!cap)
		why = "done";
	else if (st->iteration < cap)
		why = strcmp(st->stage, "sink") == 0 ? "all settled" : "converged";
	else
		why = "stopped at the iteration cap";
	if (cap)
		fprintf(stderr, "%s  [%7.1f s] %-9s ended after %d/%d iterations: %s\n", st->prefix, st->elapsed,
			label(st, name, sizeof name), st->iteration, cap, why);
	else
		fprintf(stderr, "%s  [%7.1f s] %-9s ended after %d iterations\n", st->prefix, st->elapsed,
			label(st, name, sizeof name), st->iteration);
}

int dp_cli_progress(void *user, const char *stage, int iteration, double value, double elapsed)
{
	dp_cli_progress_state *st = user;
	/* iterations rise within a run: one that does not starts a new run
	 * (a run may end at its first iteration) */
	int fresh = stage != st->stage || iteration <= st->iteration;
	if (fresh && st->stage)
		end_line(st);
	if (fresh) {
		st->runs = stage == st->stage ? st->runs + 1 : 1;
		st->stage = stage;
	}
	st->iteration = iteration;
	st->value = value;
	st->elapsed = elapsed;
	/* one line a second, and the first iteration of every stage */
	if (!fresh && elapsed - st->last_print < 1.0)
		return 0;
	st->last_print = elapsed;
	char it[32], name[32];
	int cap = cap_of(st, stage);
	if (cap)
		snprintf(it, sizeof it, "%3d/%d", iteration, cap);
	else
		snprintf(it, sizeof it, "%3d", iteration);
	const char *pre = st->prefix, *shown = label(st, name, sizeof name);
	if (strcmp(stage, "sink") == 0)
		fprintf(stderr, "%s  [%7.1f s] %-9s iteration %s, %.0f settled\n", pre, elapsed, shown, it, value);
	else if (wlop_run(stage))
		fprintf(stderr, "%s  [%7.1f s] %-9s iteration %s, mean move %.4f h\n", pre, elapsed, shown, it, value);
	else
		fprintf(stderr, "%s  [%7.1f s] %-9s iteration %s, mean move %.4f r\n", pre, elapsed, shown, it, value);
	return 0;
}

void dp_cli_progress_end(dp_cli_progress_state *st, int ok)
{
	if (ok && st->stage)
		end_line(st);
	st->stage = NULL;
	st->iteration = 0;
	st->runs = 0;
}
