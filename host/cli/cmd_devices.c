#include "cli/cli.h"

int dp_cmd_devices(int argc, char **argv)
{
	const char *pos[1];
	size_t npos;
	int help;
	int rc = cli_parse("devices", "", argc, argv, 2, NULL, 0, pos, 0, &npos, &help);
	if (rc || help)
		return rc;
	dp_error err = {0};
	if (dp_list_devices(stdout, &err) != DP_OK)
		return dp_cli_fail("devices", &err);
	return DP_EXIT_OK;
}
