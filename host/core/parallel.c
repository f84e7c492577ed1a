#include "core/parallel.h"

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

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

int dp_parallel_for(int threads, size_t n, size_t min_items, dp_range_fn fn, void *arg)
{
	int parts = dp_parallel_parts(threads, n, min_items);
	if (parts == 1) {
		fn(arg, 0, n, 0);
		return 1;
	}
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
