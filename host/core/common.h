/* Internal helpers shared by every module: error reporting, timing, seeded
 * random numbers. Not part of the public API. */
#ifndef DP_CORE_COMMON_H
#define DP_CORE_COMMON_H

#include "dpoints.h"

#include <stdint.h>

/* Sets err (when not NULL) to `status` and a printf-formatted message; returns
 * `status` so callers can `return dp_fail(err, DP_ERR_IO, "%s: ...", path);`. */
dp_status dp_fail(dp_error *err, dp_status status, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/* Monotonic wall-clock seconds. */
double dp_seconds(void);

/* Seeded, reproducible random numbers (splitmix64); the same seed gives the
 * same sequence on every platform. */
typedef struct dp_rng {
	uint64_t state;
} dp_rng;

void dp_rng_seed(dp_rng *rng, uint64_t seed);
uint64_t dp_rng_next(dp_rng *rng);
/* Uniform in [0, 1). */
double dp_rng_uniform(dp_rng *rng);
/* Standard normal (Box–Muller). */
double dp_rng_normal(dp_rng *rng);

/* malloc of n elements of `size` bytes with overflow check; NULL on failure. */
void *dp_alloc_array(size_t n, size_t size);

#endif
