#include "io/io.h"

#include "core/common.h"

#include <math.h>

static const char *const component_names[] = {"x", "y", "z", "nx", "ny", "nz"};

dp_status dp_io_check_finite(const char *path, size_t index, float x, float y, float z,
			     const float *normal, dp_error *err)
{
	float v[6] = {x, y, z, 0, 0, 0};
	int count = 3;
	if (normal) {
		v[3] = normal[0];
		v[4] = normal[1];
		v[5] = normal[2];
		count = 6;
	}
	for (int i = 0; i < count; i++)
		if (!isfinite(v[i]))
			return dp_fail(err, DP_ERR_FORMAT, "%s: point %zu (counting from 0) has a non-finite %s %s = %g",
				       path, index, i < 3 ? "coordinate" : "normal", component_names[i], (double)v[i]);
	return DP_OK;
}
