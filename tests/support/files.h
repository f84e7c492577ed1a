/* Temporary files for the I/O tests. */
#ifndef DP_TEST_FILES_H
#define DP_TEST_FILES_H

#include <stddef.h>

/* Writes `len` bytes to dir/name (failing the test on error) and returns the
 * path in a static buffer, valid until the next call. */
const char *tk_write_file(const char *dir, const char *name, const void *data, size_t len);
/* Same for a NUL-terminated text. */
const char *tk_write_text(const char *dir, const char *name, const char *text);
/* The whole file at `path` (failing the test on error), malloc'd with one
 * spare byte; the caller frees it. */
unsigned char *tk_read_file(const char *path, size_t *size);
/* Number of entries in dir (besides . and ..) whose name contains
 * `containing`, or all of them when it is NULL. */
size_t tk_count_files(const char *dir, const char *containing);
/* Removes the files and folders in dir, then dir itself. */
void tk_remove_dir(const char *dir);

#endif
