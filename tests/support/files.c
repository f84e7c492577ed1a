#include "files.h"

#include "testkit.h"

#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

const char *tk_write_file(const char *dir, const char *name, const void *data, size_t len)
{
	static char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	FILE *f = fopen(path, "wb");
	if (!f)
		fail_msg("cannot create %s", path);
	if (len && fwrite(data, 1, len, f) != len)
		fail_msg("cannot write %s", path);
	if (fclose(f) != 0)
		fail_msg("cannot close %s", path);
	return path;
}

const char *tk_write_text(const char *dir, const char *name, const char *text)
{
	return tk_write_file(dir, name, text, strlen(text));
}

size_t tk_count_files(const char *dir, const char *containing)
{
	DIR *d = opendir(dir);
	size_t n = 0;
	if (!d)
		fail_msg("cannot list %s", dir);
	for (struct dirent *e; (e = readdir(d));)
		if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
		    (!containing || strstr(e->d_name, containing)))
			n++;
	closedir(d);
	return n;
}

void tk_remove_dir(const char *dir)
{
	DIR *d = opendir(dir);
	char path[4096];
	if (!d)
		return;
	for (struct dirent *e; (e = readdir(d));) {
		if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
			continue;
		snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
		if (unlink(path) != 0)
			tk_remove_dir(path);
	}
	closedir(d);
	rmdir(dir);
}
