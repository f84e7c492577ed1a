#ifndef DP_CL_DEVICE_H
#define DP_CL_DEVICE_H

#include "cl/runtime.h"

#define DP_CL_MAX_DEVICES 32

typedef struct dp_cl_device {
	cl_platform_id platform;
	cl_device_id device;
	char name[400];        /* "platform / device" */
	const char *type;      /* "CPU", "GPU", "other" */
	cl_uint compute_units;
	cl_ulong global_mem;
} dp_cl_device;

/* Every device of every platform, in the order `dpoints devices` prints. No
 * platform installed is not an error: *count is 0. */
dp_status dp_cl_devices(dp_cl_device *out, size_t cap, size_t *count, dp_error *err);
/* The device `spec` names: NULL/empty -> $DPOINTS_DEVICE, else index 0; a
 * decimal index; or a case-insensitive substring of the name. */
dp_status dp_cl_choose(const char *spec, dp_cl_device *chosen, dp_error *err);

#endif
