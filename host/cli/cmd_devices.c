#include "cli/cli.h"

int dp_cmd_devices(int argc, char **argv)
{
	static const char *const type_names[] = {"CPU", "GPU", "other"};
	const char *pos[1];
	size_t npos;
	int help;
	int rc = cli_parse("devices", "", argc, argv, 2, NULL, 0, pos, 0, &npos, &help);
	if (rc || help)
		return rc;
	dp_error err = {0};
	dp_device_info *list;
	size_t n;
	if (dp_devices(&list, &n, &err) != DP_OK)
		return dp_cli_fail("devices", &err);
	if (n == 0) {
		err.status = DP_ERR_NO_DEVICE;
		snprintf(err.message, sizeof err.message,
			 "OpenCL: no platform or device found (install pocl-opencl-icd for the CPU)");
		return dp_cli_fail("devices", &err);
	}
	for (size_t i = 0; i < n; i++)
		printf("%zu: %s [%s, %u compute units, %.1f GiB]\n", list[i].index, list[i].name,
		       type_names[list[i].type], list[i].compute_units,
		       (double)list[i].global_mem_bytes / (1024.0 * 1024.0 * 1024.0));
	dp_devices_free(list);
	return DP_EXIT_OK;
}
