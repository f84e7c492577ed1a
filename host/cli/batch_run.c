/* A batch spread over devices: one worker thread per --device entry, each
 * with its own context (a dp_context is for one thread at a time), taking
 * the next input from a shared counter so a slow input does not hold back
 * the others. */
#include "cli/batch_run.h"
#include "cli/batch.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

typedef struct worker {
	dp_batch *b;
	dp_consolidate_job job;
	dp_context *ctx;
	const char *label; /* the --device entry */
	dp_cli_progress_state progress;
} worker;

typedef struct shared {
	pthread_mutex_t lock;
	size_t next, started;
} shared;

static shared queue = {PTHREAD_MUTEX_INITIALIZER, 0, 0};

static void *work(void *arg)
{
	worker *w = arg;
	dp_batch *b = w->b;
	for (;;) {
		pthread_mutex_lock(&queue.lock);
		size_t i = queue.next;
		while (i < b->n && b->summary[i].skipped)
			i++;
		queue.next = i + 1;
		size_t k = i < b->n ? ++queue.started : 0;
		pthread_mutex_unlock(&queue.lock);
		if (i >= b->n)
			return NULL;
		if (!b->quiet && b->n > 1)
			fprintf(stderr, "%s[%zu/%zu] %s\n", w->progress.prefix, k, b->todo, b->inputs[i]);
		dp_consolidate_summary *s = &b->summary[i];
		snprintf(s->device, sizeof s->device, "%s", w->label);
		int r = dp_cli_consolidate_one(b->cmd, w->ctx, &w->job, b->inputs[i], b->dirs[i], s);
		if (b->records) {
			if (r)
				dp_cli_write_failure(b->cmd, b->dirs[i], b->inputs[i], w->job.device_name, s->error);
			else
				dp_cli_clear_failure(b->dirs[i]);
		}
		pthread_mutex_lock(&queue.lock);
		if (r) {
			b->failed++;
			if (!b->first_failure)
				b->first_failure = r;
		}
		pthread_mutex_unlock(&queue.lock);
	}
}

int dp_cli_batch_run(dp_batch *b, const dp_consolidate_job *job, int backend, const dp_cli_list *devices)
{
	size_t nw = devices->n;
	worker *ws = calloc(nw, sizeof *ws);
	pthread_t *threads = calloc(nw, sizeof *threads);
	int rc = 0;
	if (!ws || !threads) {
		fprintf(stderr, "dpoints %s: out of memory\n", b->cmd);
		rc = DP_EXIT_NOMEM;
	}
	/* every context before any work: a bad --device entry fails the run
	 * up front rather than after hours on the other devices */
	for (size_t d = 0; d < nw && !rc; d++) {
		const char *spec = devices->items[d];
		rc = cli_open_context(b->cmd, backend, *spec ? spec : NULL, &ws[d].ctx);
		if (rc)
			break;
		/* workers share the CPUs: each one's host loops get a share */
		int cpus = dp_context_threads(ws[d].ctx), share = cpus / (int)nw;
		dp_context_set_threads(ws[d].ctx, job->threads > 0 ? job->threads : share > 1 ? share : 1);
		ws[d].b = b;
		ws[d].job = *job;
		ws[d].job.device_name = dp_context_device_name(ws[d].ctx);
		ws[d].label = spec;
		if (nw > 1)
			snprintf(ws[d].progress.prefix, sizeof ws[d].progress.prefix, "worker %zu (device %s): ", d + 1,
				 spec);
		if (!b->quiet) {
			dp_context_set_progress(ws[d].ctx, dp_cli_progress, &ws[d].progress);
			ws[d].job.progress = &ws[d].progress;
		}
		if (!b->quiet && nw > 1)
			fprintf(stderr, "%s%s\n", ws[d].progress.prefix, ws[d].job.device_name);
	}
	b->todo = 0;
	for (size_t i = 0; i < b->n; i++)
		b->todo += !b->summary[i].skipped;
	queue.next = queue.started = 0;
	if (!rc && nw == 1) {
		work(&ws[0]);
	} else if (!rc) {
		size_t started = 0;
		for (; started < nw; started++)
			if (pthread_create(&threads[started], NULL, work, &ws[started]) != 0)
				break;
		if (started == 0)
			work(&ws[0]);
		for (size_t d = 0; d < started; d++)
			pthread_join(threads[d], NULL);
	}
	for (size_t d = 0; ws && d < nw; d++)
		dp_context_free(ws[d].ctx);
	free(ws);
	free(threads);
	return rc;
}
