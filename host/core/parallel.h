/* Host loops over points split across threads. The kernels run on the
 * OpenCL device; what stays on the host (the sinking's medial test, width
 * bound and flat faces, the skeleton's PCA frames, the surface stage's
 * normals, the pair accounting) is one thread's work per point, and on a GPU
 * machine that work, not the kernels, set each stage's time (H100, 67K deep
 * points: sinking 8.1 s with 0.26 s in kernels).
 *
 * Each thread gets one contiguous range and writes only the outputs of its
 * own items, so the result does not depend on the thread count; reductions
 * are per range and added in range order by the caller. The threads are a
 * pool kept for the life of the process (parallel.c has why). */
#ifndef DP_CORE_PARALLEL_H
#define DP_CORE_PARALLEL_H

#include <stddef.h>

/* The most threads one loop uses; more cores than this stay idle. */
#define DP_PARALLEL_MAX 64

/* Items [begin, end) of the loop, as range number `part`. */
typedef void (*dp_range_fn)(void *arg, size_t begin, size_t end, int part);

/* How many ranges dp_parallel_for will cut n items into with `threads`
 * threads and at least `min_items` items a range, between 1 and
 * DP_PARALLEL_MAX (per-range results need that many slots at most). */
int dp_parallel_parts(int threads, size_t n, size_t min_items);

/* Runs fn over [0, n) in dp_parallel_parts(threads, n, min_items) ranges,
 * range 0 on the calling thread, and returns how many ranges ran once all
 * have finished: per-range results are in slots 0 .. that - 1. A thread that
 * cannot be started runs its range on the caller instead: this never fails. */
int dp_parallel_for(int threads, size_t n, size_t min_items, dp_range_fn fn, void *arg);

/* The CPUs this process may run on (its affinity mask; the online CPUs where
 * that cannot be read), at most DP_PARALLEL_MAX, at least 1. */
int dp_parallel_cpus(void);

#endif
