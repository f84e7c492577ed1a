#include "core/parallel.h"

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

/* One pool of workers for the whole process, started on first use and kept:
 * a stage calls dp_parallel_for a few times per iteration, for hundreds of
 * iterations, and starting and joining 15 threads for each call cost more
 * than the loops it split (H200, 16 threads, the surface stage's per-point
 * loops: 3.3 s -> 3.5-3.7 s). Workers sleep on a condition variable between
 * loops and are never joined; they hold no resource but their stacks.
 *
 * One loop at a time runs on the pool. A loop started while it is busy (by
 * another thread of the program, or from inside a range) starts threads of
 * its own as before, so the pool never waits on itself. Which thread runs a
 * range does not change what the range computes: range k always covers the
 * same items and is passed part k.
 *
 * A fork copies the pool's state but none of its workers. Caught at the
 * wrong instant it also copied the lock held by a worker, and the child's
 * first pooled loop waited for ever (1 child in 1000 forked while another
 * thread ran loops, on a loaded machine; once in CI). So the fork handlers
 * below take the lock across the fork, and the child starts from an idle,
 * empty pool with fresh synchronisation objects. */
typedef struct pool {
	pthread_mutex_t lock; /* guards every field below */
	pthread_cond_t posted, finished;
	int workers;          /* started, never stopped */
	int busy;             /* a loop is running on the pool */
	unsigned long loop;   /* counts the loops posted, so a worker sees each once */
	dp_range_fn fn;
	void *arg;
	size_t n;
	int parts, next, unfinished;
} pool;

static pool the_pool = {.lock = PTHREAD_MUTEX_INITIALIZER, .posted = PTHREAD_COND_INITIALIZER, .finished = PTHREAD_COND_INITIALIZER};
static pthread_once_t fork_handlers_once = PTHREAD_ONCE_INIT;

static void before_fork(void)
{
	pthread_mutex_lock(&the_pool.lock);
}

static void after_fork_parent(void)
{
	pthread_mutex_unlock(&the_pool.lock);
}

/* The child is one thread: a loop the parent was running belongs to threads
 * it does not have, and waiters the condition variables remember are gone. */
static void after_fork_child(void)
{
	pool *p = &the_pool;
	pthread_mutex_init(&p->lock, NULL);
	pthread_cond_init(&p->posted, NULL);
	pthread_cond_init(&p->finished, NULL);
	p->workers = 0;
	p->busy = 0;
	p->parts = p->next = p->unfinished = 0;
}

static void register_fork_handlers(void)
{
	pthread_atfork(before_fork, after_fork_parent, after_fork_child);
}

int dp_parallel_parts(int threads, size_t n, size_t min_items)
{
	if (threads > DP_PARALLEL_MAX)
		threads = DP_PARALLEL_MAX;
	if (min_items < 1)
		min_items = 1;
	size_t most = n / min_items;
	if (threads < 1 || most < 2)
		return 1;
	return most < (size_t)threads ? (int)most : threads;
}

/* Where range k of `parts` over n items begins: the first n % parts ranges
 * hold one item more (no n * k, which overflows a 32-bit size_t). */
static size_t range_begin(size_t n, int parts, int k)
{
	size_t each = n / (size_t)parts, extra = n % (size_t)parts, kk = (size_t)k;
	return kk * each + (kk < extra ? kk : extra);
}

/* Claims and runs the posted loop's ranges until none is left. Called and
 * returns with the lock held. */
static void run_claimed(pool *p)
{
	while (p->next < p->parts) {
		int k = p->next++;
		dp_range_fn fn = p->fn;
		void *arg = p->arg;
		size_t n = p->n;
		int parts = p->parts;
		pthread_mutex_unlock(&p->lock);
		fn(arg, range_begin(n, parts, k), range_begin(n, parts, k + 1), k);
		pthread_mutex_lock(&p->lock);
		if (--p->unfinished == 0)
			pthread_cond_signal(&p->finished);
	}
}

static void *worker(void *arg)
{
	pool *p = arg;
	pthread_mutex_lock(&p->lock);
	unsigned long seen = p->loop;
	for (;;) {
		while (p->loop == seen)
			pthread_cond_wait(&p->posted, &p->lock);
		seen = p->loop;
		run_claimed(p);
	}
	return NULL;
}

/* Starts workers until there are `want`, as far as the system lets it: the
 * calling thread runs whatever ranges no worker claims. */
static void grow(pool *p, int want)
{
	while (p->workers < want) {
		pthread_t tid;
		pthread_attr_t attr;
		if (pthread_attr_init(&attr) != 0)
			return;
		int ok = pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED) == 0 &&
			 pthread_create(&tid, &attr, worker, p) == 0;
		pthread_attr_destroy(&attr);
		if (!ok)
			return;
		p->workers++;
	}
}

typedef struct range_job {
	dp_range_fn fn;
	void *arg;
	size_t begin, end;
	int part;
} range_job;

static void *run_range(void *p)
{
	range_job *j = p;
	j->fn(j->arg, j->begin, j->end, j->part);
	return NULL;
}

/* The pool is busy: threads of this loop's own, joined before it returns. */
static void run_unpooled(int parts, size_t n, dp_range_fn fn, void *arg)
{
	range_job jobs[DP_PARALLEL_MAX];
	pthread_t tid[DP_PARALLEL_MAX];
	int started[DP_PARALLEL_MAX] = {0};
	for (int k = 0; k < parts; k++)
		jobs[k] = (range_job){fn, arg, range_begin(n, parts, k), range_begin(n, parts, k + 1), k};
	for (int k = 1; k < parts; k++)
		started[k] = pthread_create(&tid[k], NULL, run_range, &jobs[k]) == 0;
	run_range(&jobs[0]);
	for (int k = 1; k < parts; k++) {
		if (started[k])
			pthread_join(tid[k], NULL);
		else
			run_range(&jobs[k]);
	}
}

int dp_parallel_for(int threads, size_t n, size_t min_items, dp_range_fn fn, void *arg)
{
	int parts = dp_parallel_parts(threads, n, min_items);
	if (parts == 1) {
		fn(arg, 0, n, 0);
		return 1;
	}
	pthread_once(&fork_handlers_once, register_fork_handlers);
	pool *p = &the_pool;
	pthread_mutex_lock(&p->lock);
	if (p->busy) {
		pthread_mutex_unlock(&p->lock);
		run_unpooled(parts, n, fn, arg);
		return parts;
	}
	p->busy = 1;
	grow(p, parts - 1);
	p->fn = fn;
	p->arg = arg;
	p->n = n;
	p->parts = parts;
	p->next = 1; /* range 0 is the caller's, as documented */
	p->unfinished = parts - 1;
	p->loop++;
	/* wake only as many as there are ranges for: a loop of few ranges on a
	 * pool of many would otherwise wake them all for nothing */
	for (int k = 1; k < parts; k++)
		pthread_cond_signal(&p->posted);
	pthread_mutex_unlock(&p->lock);
	fn(arg, 0, range_begin(n, parts, 1), 0);
	pthread_mutex_lock(&p->lock);
	run_claimed(p);
	while (p->unfinished > 0)
		pthread_cond_wait(&p->finished, &p->lock);
	p->busy = 0;
	pthread_mutex_unlock(&p->lock);
	return parts;
}

int dp_parallel_cpus(void)
{
	/* the CPUs this process may run on: a Slurm job or a container is given
	 * a few of a large machine's */
	cpu_set_t set;
	long n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : sysconf(_SC_NPROCESSORS_ONLN);
	if (n < 1)
		return 1;
	return n > DP_PARALLEL_MAX ? DP_PARALLEL_MAX : (int)n;
}
