/* Enumerating OpenCL devices and choosing one by index or name. */
#include "cl/device.h"

#include "core/common.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static int contains_nocase(const char *hay, const char *needle)
{
	size_t n = strlen(needle);
	for (; *hay; hay++) {
		size_t i = 0;
		while (i < n && hay[i] && tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
			i++;
		if (i == n)
			return 1;
	}
	return n == 0;
}

/* A platform's (device NULL) or a device's name, cut to `size`; "?" when the
 * query fails. A name that cannot be read, or one longer than any buffer
 * (clGet*Info refuses a buffer too small for it), must not keep the other
 * devices from being listed and chosen. */
static void info_name(cl_platform_id platform, cl_device_id device, char *buf, size_t size)
{
	size_t need = 0;
	cl_int rc = device ? clGetDeviceInfo(device, CL_DEVICE_NAME, 0, NULL, &need)
			   : clGetPlatformInfo(platform, CL_PLATFORM_NAME, 0, NULL, &need);
	char *full = rc == CL_SUCCESS && need > 0 ? malloc(need) : NULL;
	if (full)
		rc = device ? clGetDeviceInfo(device, CL_DEVICE_NAME, need, full, NULL)
			    : clGetPlatformInfo(platform, CL_PLATFORM_NAME, need, full, NULL);
	if (full && rc == CL_SUCCESS)
		snprintf(buf, size, "%.*s", (int)strnlen(full, need), full);
	else
		snprintf(buf, size, "?");
	free(full);
}

static int is_index(const char *s)
{
	if (!*s)
		return 0;
	for (; *s; s++)
		if (!isdigit((unsigned char)*s))
			return 0;
	return 1;
}

dp_status dp_cl_devices(dp_cl_device *out, size_t cap, size_t *count, dp_error *err)
{
	cl_platform_id platforms[DP_CL_MAX_DEVICES];
	cl_uint nplat = 0;
	*count = 0;
	cl_int rc = clGetPlatformIDs(DP_CL_MAX_DEVICES, platforms, &nplat);
	if (rc == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (rc == CL_SUCCESS && nplat == 0))
		return DP_OK;
	if (rc != CL_SUCCESS)
		return dp_fail(err, DP_ERR_CL, "OpenCL: clGetPlatformIDs failed: %s", dp_cl_error_name(rc));
	if (nplat > DP_CL_MAX_DEVICES)
		nplat = DP_CL_MAX_DEVICES;
	for (cl_uint p = 0; p < nplat; p++) {
		char pname[128];
		info_name(platforms[p], NULL, pname, sizeof pname);
		cl_device_id devices[DP_CL_MAX_DEVICES];
		cl_uint ndev = 0;
		rc = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, DP_CL_MAX_DEVICES, devices, &ndev);
		if (rc == CL_DEVICE_NOT_FOUND)
			continue;
		if (rc != CL_SUCCESS)
			return dp_fail(err, DP_ERR_CL, "OpenCL: clGetDeviceIDs on platform '%s' failed: %s", pname,
				       dp_cl_error_name(rc));
		if (ndev > DP_CL_MAX_DEVICES)
			ndev = DP_CL_MAX_DEVICES;
		for (cl_uint d = 0; d < ndev && *count < cap; d++) {
			dp_cl_device *o = &out[(*count)++];
			char dname[256];
			cl_device_id dev = devices[d];
			info_name(NULL, dev, dname, sizeof dname);
			/* a figure the device does not give reads 0, a type "other" */
			cl_device_type type = 0;
			if (clGetDeviceInfo(dev, CL_DEVICE_TYPE, sizeof type, &type, NULL) != CL_SUCCESS)
				type = 0;
			if (clGetDeviceInfo(dev, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof o->compute_units, &o->compute_units,
					    NULL) != CL_SUCCESS)
				o->compute_units = 0;
			if (clGetDeviceInfo(dev, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof o->global_mem, &o->global_mem, NULL) !=
			    CL_SUCCESS)
				o->global_mem = 0;
			o->platform = platforms[p];
			o->device = devices[d];
			snprintf(o->name, sizeof o->name, "%s / %s", pname, dname);
			o->type = (type & CL_DEVICE_TYPE_GPU) ? "GPU" : (type & CL_DEVICE_TYPE_CPU) ? "CPU" : "other";
		}
	}
	return DP_OK;
}

dp_status dp_cl_choose(const char *spec, dp_cl_device *chosen, dp_error *err)
{
	dp_cl_device list[DP_CL_MAX_DEVICES];
	size_t n = 0;
	dp_status st = dp_cl_devices(list, DP_CL_MAX_DEVICES, &n, err);
	if (st != DP_OK)
		return st;
	if (!spec || !*spec)
		spec = getenv("DPOINTS_DEVICE");
	if (n == 0)
		return dp_fail(err, DP_ERR_NO_DEVICE,
			       "OpenCL: no platform or device found (install pocl-opencl-icd for the CPU, "
			       "or use --backend ref)");
	if (!spec || !*spec) {
		*chosen = list[0];
		return DP_OK;
	}
	if (is_index(spec)) {
		unsigned long i = strtoul(spec, NULL, 10);
		if (i >= n)
			return dp_fail(err, DP_ERR_NO_DEVICE,
				       "OpenCL: device index %s is out of range (%zu device%s; see `dpoints devices`)",
				       spec, n, n == 1 ? "" : "s");
		*chosen = list[i];
		return DP_OK;
	}
	for (size_t i = 0; i < n; i++)
		if (contains_nocase(list[i].name, spec)) {
			*chosen = list[i];
			return DP_OK;
		}
	return dp_fail(err, DP_ERR_NO_DEVICE, "OpenCL: no device name contains '%s' (see `dpoints devices`)", spec);
}

dp_status dp_devices(dp_device_info **list, size_t *count, dp_error *err)
{
	if (!list || !count)
		return dp_fail(err, DP_ERR_ARG, "devices: NULL list or count");
	*list = NULL;
	*count = 0;
	dp_cl_device found[DP_CL_MAX_DEVICES];
	size_t n = 0;
	dp_status st = dp_cl_devices(found, DP_CL_MAX_DEVICES, &n, err);
	if (st != DP_OK || n == 0)
		return st;
	dp_device_info *out = calloc(n, sizeof *out);
	if (!out)
		return dp_fail(err, DP_ERR_NOMEM, "devices: out of memory");
	for (size_t i = 0; i < n; i++) {
		out[i].index = i;
		snprintf(out[i].name, sizeof out[i].name, "%s", found[i].name);
		out[i].type = strcmp(found[i].type, "CPU") == 0   ? DP_DEVICE_CPU
			      : strcmp(found[i].type, "GPU") == 0 ? DP_DEVICE_GPU
								  : DP_DEVICE_OTHER;
		out[i].compute_units = (unsigned)found[i].compute_units;
		out[i].global_mem_bytes = (uint64_t)found[i].global_mem;
	}
	*list = out;
	*count = n;
	return DP_OK;
}

void dp_devices_free(dp_device_info *list)
{
	free(list);
}

dp_status dp_list_devices(FILE *out, dp_error *err)
{
	static const char *const type_names[] = {"CPU", "GPU", "other"};
	dp_device_info *list;
	size_t n;
	dp_status st = dp_devices(&list, &n, err);
	if (st != DP_OK)
		return st;
	if (n == 0)
		return dp_fail(err, DP_ERR_NO_DEVICE,
			       "OpenCL: no platform or device found (install pocl-opencl-icd for the CPU)");
	for (size_t i = 0; i < n; i++)
		fprintf(out, "%zu: %s [%s, %u compute units, %.1f GiB]\n", i, list[i].name, type_names[list[i].type],
			list[i].compute_units, (double)list[i].global_mem_bytes / (1024.0 * 1024.0 * 1024.0));
	dp_devices_free(list);
	return DP_OK;
}
