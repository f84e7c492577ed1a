/* Host loops split across threads (core/parallel.h): every item runs once,
 * in its own range, and a whole consolidation gives the same bytes whatever
 * dp_context_set_threads says. */
#include "testkit.h"

#include "core/parallel.h"

#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

typedef struct visits {
	unsigned char *count;
	size_t begin[DP_PARALLEL_MAX], end[DP_PARALLEL_MAX];
	int seen[DP_PARALLEL_MAX];
} visits;

static void visit(void *arg, size_t begin, size_t end, int part)
{
	visits *v = arg;
	v->begin[part] = begin;
	v->end[part] = end;
	v->seen[part]++;
	for (size_t i = begin; i < end; i++)
		v->count[i]++;
}

static void test_ranges(void **state)
{
	(void)state;
	const int threads[] = {0, 1, 2, 3, 7, 64, 1000};
	const size_t sizes[] = {0, 1, 5, 255, 256, 1000, 4097};
	const size_t mins[] = {0, 1, 256};
	unsigned char *count = calloc(4097, 1);
	assert_non_null(count);
	for (size_t t = 0; t < sizeof threads / sizeof *threads; t++)
		for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++)
			for (size_t m = 0; m < sizeof mins / sizeof *mins; m++) {
				size_t n = sizes[s];
				int parts = dp_parallel_parts(threads[t], n, mins[m]);
				assert_true(parts >= 1 && parts <= DP_PARALLEL_MAX);
				assert_true(parts <= (threads[t] > 1 ? threads[t] : 1));
				if (parts > 1)
					assert_true(n / (size_t)parts >= (mins[m] ? mins[m] : 1));
				visits v = {.count = count};
				memset(count, 0, 4097);
				dp_parallel_for(threads[t], n, mins[m], visit, &v);
				for (size_t i = 0; i < n; i++)
					assert_int_equal(count[i], 1);
				/* contiguous ranges in part order, each run once */
				size_t next = 0;
				for (int k = 0; k < parts; k++) {
					assert_int_equal(v.seen[k], 1);
					assert_int_equal(v.begin[k], next);
					next = v.end[k];
				}
				assert_int_equal(next, n);
				for (int k = parts; k < DP_PARALLEL_MAX; k++)
					assert_int_equal(v.seen[k], 0);
			}
	/* enough work for two threads on a 64-thread request */
	assert_int_equal(dp_parallel_parts(64, 512, 256), 2);
	assert_int_equal(dp_parallel_parts(2, 100000, 256), 2);
	free(count);
}

/* The pool runs one loop at a time: a loop started from inside a range, or by
 * a second program thread while one runs, must still run every item once and
 * never wait on the pool. */
#define BUSY_N 3000
#define BUSY_ROUNDS 200

typedef struct busy_loop {
	unsigned short count[BUSY_N];
	int nested; /* ranges start a loop of their own */
} busy_loop;

static void count_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	unsigned short *count = arg;
	for (size_t i = begin; i < end; i++)
		count[i]++;
}

static void nesting_range(void *arg, size_t begin, size_t end, int part)
{
	(void)part;
	busy_loop *b = arg;
	for (size_t i = begin; i < end; i++)
		b->count[i]++;
	if (b->nested) {
		/* every one of this range's items once more, split again */
		unsigned short *mine = b->count + begin;
		dp_parallel_for(3, end - begin, 16, count_range, mine);
	}
}

static void *busy_rounds(void *arg)
{
	busy_loop *b = arg;
	for (int round = 0; round < BUSY_ROUNDS; round++)
		dp_parallel_for(4, BUSY_N, 16, nesting_range, b);
	return NULL;
}

static void test_pool_busy(void **state)
{
	(void)state;
	static busy_loop loops[2];
	memset(loops, 0, sizeof loops);
	loops[1].nested = 1;
	pthread_t other;
	assert_int_equal(pthread_create(&other, NULL, busy_rounds, &loops[1]), 0);
	busy_rounds(&loops[0]);
	assert_int_equal(pthread_join(other, NULL), 0);
	for (size_t i = 0; i < BUSY_N; i++) {
		assert_int_equal(loops[0].count[i], BUSY_ROUNDS);
		assert_int_equal(loops[1].count[i], 2 * BUSY_ROUNDS);
	}
}

/* A program that forks while another of its threads runs loops on the pool
 * (a Python caller's multiprocessing, say): the child inherits the pool's
 * state but none of its workers, and must finish loops of its own. Without
 * the pool's fork handlers a child that caught the pool's lock held waited
 * for ever: 1 in 1000 on a loaded 2-core machine, 1 in 40 once in CI. */
#define FORK_CHILDREN 300
#define FORK_N 4096
#define FORK_WAIT_MS 10000

static atomic_int forking_done;

static void *loop_until_done(void *arg)
{
	unsigned short *count = arg;
	while (!forking_done)
		dp_parallel_for(4, FORK_N, 16, count_range, count);
	return NULL;
}

/* in the child: no allocation, which a fork may have caught mid-way */
static int child_loops(void)
{
	static unsigned short count[FORK_N];
	for (int round = 0; round < 3; round++)
		dp_parallel_for(4, FORK_N, 16, count_range, count);
	for (size_t i = 0; i < FORK_N; i++)
		if (count[i] != 3)
			return 1;
	return 0;
}

static void test_fork_while_busy(void **state)
{
	(void)state;
	static unsigned short count[FORK_N];
	forking_done = 0;
	pthread_t busy;
	assert_int_equal(pthread_create(&busy, NULL, loop_until_done, count), 0);
	int hung = 0, failed = 0;
	for (int k = 0; k < FORK_CHILDREN; k++) {
		pid_t pid = fork();
		assert_true(pid >= 0);
		if (pid == 0)
			_exit(child_loops());
		int status = 0, waited = 0;
		pid_t got;
		while ((got = waitpid(pid, &status, WNOHANG)) == 0 && waited < FORK_WAIT_MS) {
			usleep(1000);
			waited++;
		}
		if (got == 0) {
			kill(pid, SIGKILL);
			waitpid(pid, &status, 0);
			hung++;
		} else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
			failed++;
		}
	}
	forking_done = 1;
	assert_int_equal(pthread_join(busy, NULL), 0);
	printf("  %d children: %d hung, %d failed\n", FORK_CHILDREN, hung, failed);
	assert_int_equal(hung, 0);
	assert_int_equal(failed, 0);
}

static void test_context_threads(void **state)
{
	(void)state;
	dp_context *ctx = tk_ref_context();
	dp_context_set_threads(ctx, 3);
	assert_int_equal(dp_context_threads(ctx), 3);
	dp_context_set_threads(ctx, 1000);
	assert_int_equal(dp_context_threads(ctx), DP_PARALLEL_MAX);
	dp_context_set_threads(ctx, 0);
	assert_int_equal(dp_context_threads(ctx), dp_parallel_cpus());
	assert_true(dp_context_threads(ctx) >= 1);
	dp_context_set_threads(ctx, -3);
	assert_int_equal(dp_context_threads(ctx), dp_parallel_cpus());
}

static void assert_same_cloud(const dp_cloud *a, const dp_cloud *b, const char *what)
{
	print_message("%s: %zu points\n", what, a->n);
	assert_int_equal(a->n, b->n);
	assert_true(a->n > 0);
	const float *fa[6] = {a->x, a->y, a->z, a->nx, a->ny, a->nz}, *fb[6] = {b->x, b->y, b->z, b->nx, b->ny, b->nz};
	for (int c = 0; c < 6; c++) {
		assert_true((fa[c] == NULL) == (fb[c] == NULL));
		if (fa[c])
			assert_memory_equal(fa[c], fb[c], a->n * sizeof(float));
	}
}

/* Large enough that every threaded loop (medial test, width bound, flat
 * faces, PCA frames, normal update, pair counts) really splits: the demo
 * chair (flat faces, thin legs) at 9000 deep points, no coarse level. */
static void test_same_result(void **state)
{
	(void)state;
	dp_cloud scan = {0};
	tk_scan_shape("chair", 2, 256, 0.003, 5, NULL, NULL, &scan);
	dp_params params;
	dp_params_default(&params);
	params.wlop.samples = 9000;
	params.refine.coarse_samples = 0;
	params.surface.max_iters = 25;
	dp_context *ctx = tk_cl_context();
	dp_result res[2];
	const int threads[2] = {1, 3};
	for (int k = 0; k < 2; k++) {
		dp_error err = {0};
		dp_context_set_threads(ctx, threads[k]);
		if (dp_consolidate(ctx, &scan, &params, &res[k], &err) != DP_OK)
			fail_msg("%s", err.message);
	}
	dp_context_set_threads(ctx, 0);
	assert_int_equal(res[0].surface.n, 9000);
	assert_same_cloud(&res[0].wlop, &res[1].wlop, "wlop");
	assert_same_cloud(&res[0].anchors, &res[1].anchors, "anchors");
	assert_memory_equal(res[0].settled_by, res[1].settled_by, res[0].anchors.n);
	assert_same_cloud(&res[0].skeleton, &res[1].skeleton, "skeleton");
	assert_same_cloud(&res[0].surface, &res[1].surface, "surface");
	assert_memory_equal(res[0].eta, res[1].eta, res[0].surface.n * sizeof(float));
	assert_memory_equal(res[0].length, res[1].length, res[0].surface.n * sizeof(float));
	/* the medial test, the width bound and the flat faces settled some;
	 * their counts, the normals' and the pair counts agree */
	assert_true(res[0].sink_stats.settled_medial > 0);
	assert_true(res[0].sink_stats.settled_width > 0);
	assert_true(res[0].sink_stats.settled_flat > 0);
	assert_int_equal(res[0].sink_stats.settled_width, res[1].sink_stats.settled_width);
	assert_int_equal(res[0].sink_stats.settled_flat, res[1].sink_stats.settled_flat);
	assert_int_equal(res[0].sink_stats.settled_medial, res[1].sink_stats.settled_medial);
	assert_int_equal(res[0].surface_stats.normals_disagreeing, res[1].surface_stats.normals_disagreeing);
	assert_true(res[0].surface_stats.reattached > 0);
	assert_int_equal(res[0].surface_stats.reattached, res[1].surface_stats.reattached);
	assert_int_equal(res[0].surface_stats.escaped, res[1].surface_stats.escaped);
	assert_true(res[0].surface_stats.iterations == res[1].surface_stats.iterations);
	assert_true(res[0].surface_stats.pair_evaluations > 0.0);
	assert_true(res[0].surface_stats.pair_evaluations == res[1].surface_stats.pair_evaluations);
	assert_true(res[0].skeleton_stats.pair_evaluations == res[1].skeleton_stats.pair_evaluations);
	assert_true(res[0].sink_stats.pair_evaluations == res[1].sink_stats.pair_evaluations);
	for (int k = 0; k < 2; k++)
		dp_result_free(&res[k]);
	dp_cloud_free(&scan);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_ranges),
		cmocka_unit_test(test_pool_busy),
		cmocka_unit_test(test_fork_while_busy),
		cmocka_unit_test(test_context_threads),
		cmocka_unit_test(test_same_result),
	};
	return tk_exit_status(cmocka_run_group_tests(tests, NULL, tk_teardown_contexts));
}
