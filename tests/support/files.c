#include "files.h"

#include "testkit.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
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

unsigned char *tk_read_file(const char *path, size_t *size)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		fail_msg("cannot open %s", path);
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	long n = ftell(f);
	assert_true(n >= 0);
	rewind(f);
	unsigned char *data = malloc((size_t)n + 1);
	assert_non_null(data);
	assert_int_equal(fread(data, 1, (size_t)n, f), (size_t)n);
	fclose(f);
	*size = (size_t)n;
	return data;
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
