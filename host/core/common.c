#include "core/common.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

dp_status dp_fail(dp_error *err, dp_status status, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(err->message, sizeof err->message, fmt, ap);
		va_end(ap);
		err->status = status;
	}
	return status;
}

double dp_seconds(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void dp_rng_seed(dp_rng *rng, uint64_t seed)
{
	rng->state = seed;
}

uint64_t dp_rng_next(dp_rng *rng)
{
	uint64_t z = (rng->state += 0x9e3779b97f4a7c15ULL);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
	return z ^ (z >> 31);
}

double dp_rng_uniform(dp_rng *rng)
{
	return (double)(dp_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
}

double dp_rng_normal(dp_rng *rng)
{
	double u1 = dp_rng_uniform(rng), u2 = dp_rng_uniform(rng);
	if (u1 < 1e-300)
		u1 = 1e-300;
	return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}

void *dp_alloc_array(size_t n, size_t size)
{
	if (n == 0)
		n = 1;
	if (size && n > SIZE_MAX / size)
		return NULL;
	return malloc(n * size);
}

const char *dp_status_string(dp_status status)
{
	switch (status) {
	case DP_OK: return "ok";
	case DP_ERR_ARG: return "invalid argument";
	case DP_ERR_IO: return "input/output error";
	case DP_ERR_FORMAT: return "file format error";
	case DP_ERR_EMPTY: return "no usable points";
	case DP_ERR_NOMEM: return "out of memory";
	case DP_ERR_NO_DEVICE: return "no OpenCL device";
	case DP_ERR_CL: return "OpenCL error";
	case DP_ERR_KERNEL_BUILD: return "OpenCL program build failed";
	case DP_ERR_INTERNAL: return "internal error";
	case DP_ERR_CANCELLED: return "cancelled";
	}
	return "unknown status";
}

const char *dp_version(void)
{
	return DP_VERSION_STRING;
}
