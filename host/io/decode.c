#include "io/io.h"

#include <string.h>

/* Assembles the integer byte by byte, so the host's own byte order never
 * matters. */
double dp_io_decode(const unsigned char *p, dp_io_kind kind, size_t size, int big_endian)
{
	uint64_t u = 0;
	for (size_t i = 0; i < size; i++) {
		size_t shift = 8 * (big_endian ? size - 1 - i : i);
		u |= (uint64_t)p[i] << shift;
	}
	switch (kind) {
	case DP_IO_FLOAT:
		if (size == sizeof(float)) {
			uint32_t bits = (uint32_t)u;
			float f;
			memcpy(&f, &bits, sizeof f);
			return f;
		} else {
			double d;
			memcpy(&d, &u, sizeof d);
			return d;
		}
	case DP_IO_INT:
		if (size < 8 && (u >> (8 * size - 1)) & 1)
			u |= ~(uint64_t)0 << (8 * size);
		return (double)(int64_t)u;
	case DP_IO_UINT:
		break;
	}
	return (double)u;
}
