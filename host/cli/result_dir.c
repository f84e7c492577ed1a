/* A consolidate result folder replaced as a whole (issue 9, defect 4).
 *
 * Renaming each file atomically is not enough: killed between two renames, a
 * folder held a new surface.ply beside an old skeleton.ply whose rows no
 * longer matched, and files of an earlier --save-stages run stayed forever.
 * So every output of one input goes into the sibling "<dir>.tmp.<pid>", and
 * only a complete set is swapped in. Siblings (not sub-folders) keep the
 * swap a rename within one file system. */
#include "cli/consolidate.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *const dp_cli_result_files[] = {"surface.ply",  "skeleton.ply", "dpoints.ply", "report.json",
					   "wlop.ply",     "anchors.ply",  "input.png",   "skeleton.png",
					   "surface.png",  "dpoints.png",  NULL};

/* The pid of "<prefix><pid>", or 0 when `name` is not of that form. */
static long pid_suffix(const char *name, const char *prefix)
{
	size_t len = strlen(prefix);
	if (strncmp(name, prefix, len) != 0)
		return 0;
	const char *s = name + len;
	if (*s < '0' || *s > '9' || strlen(s) > 9)
		return 0;
	for (const char *p = s; *p; p++)
		if (*p < '0' || *p > '9')
			return 0;
	return strtol(s, NULL, 10);
}

/* Only ESRCH proves a run dead: EPERM is a live process of another user, and
 * the temporaries of a live run are its own to finish or remove. */
static int pid_dead(long pid)
{
	return pid > 0 && pid != (long)getpid() && (pid > INT_MAX || (kill((pid_t)pid, 0) != 0 && errno == ESRCH));
}

/* 1 for a file consolidate writes, 2 for the per-file temporary of one (the
 * pid in *pid), 0 for anything else. */
static int result_name(const char *name, long *pid)
{
	for (int k = 0; dp_cli_result_files[k]; k++) {
		size_t len = strlen(dp_cli_result_files[k]);
		if (strcmp(name, dp_cli_result_files[k]) == 0)
			return 1;
		char prefix[64];
		snprintf(prefix, sizeof prefix, "%.*s.tmp.", (int)len, dp_cli_result_files[k]);
		if ((*pid = pid_suffix(name, prefix)) > 0)
			return 2;
	}
	return 0;
}

/* Removes a result folder. Only result files are unlinked, so whatever else
 * got in there since it was checked survives (and keeps the folder). */
static void remove_result_folder(const char *path)
{
	DIR *d = opendir(path);
	if (!d)
		return;
	struct dirent *e;
	while ((e = readdir(d))) {
		long pid;
		if (result_name(e->d_name, &pid)) {
			char file[4096];
			snprintf(file, sizeof file, "%s/%s", path, e->d_name);
			unlink(file);
		}
	}
	closedir(d);
	rmdir(path);
}

/* `dir` without trailing slashes, split at its last slash: "a/b/" gives
 * parent "a", base "b"; "b" gives ".", "b". */
static void split_path(const char *dir, char *parent, char *base, size_t size)
{
	char path[4096];
	snprintf(path, sizeof path, "%s", dir);
	size_t len = strlen(path);
	while (len > 1 && path[len - 1] == '/')
		path[--len] = '\0';
	char *slash = strrchr(path, '/');
	if (!slash) {
		snprintf(parent, size, ".");
		snprintf(base, size, "%s", path);
	} else {
		snprintf(base, size, "%s", slash + 1);
		if (slash == path)
			slash++;
		*slash = '\0';
		snprintf(parent, size, "%s", path);
	}
}

/* The absolute path the swap renames: through symbolic links, ".", "..", so
 * the siblings sit beside the real folder. "" when that cannot be known. */
static void target_path(const char *dir, char *out, size_t size)
{
	char parent[4096], base[4096], real[PATH_MAX];
	struct stat sb;
	out[0] = '\0';
	if (lstat(dir, &sb) == 0) {
		if (realpath(dir, real))
			snprintf(out, size, "%s", real);
		return;
	}
	split_path(dir, parent, base, sizeof parent);
	if (realpath(parent, real) &&
	    (size_t)snprintf(out, size, "%s%s%s", real, strcmp(real, "/") ? "/" : "", base) >= size)
		out[0] = '\0';
}

/* Removes "<target>.tmp.<pid>" and "<target>.old.<pid>" of dead runs beside
 * the folder, and per-file temporaries of dead runs inside it. */
static void remove_stale(const char *target)
{
	char parent[4096], base[4096], tmp_prefix[4200], old_prefix[4200];
	split_path(target, parent, base, sizeof parent);
	snprintf(tmp_prefix, sizeof tmp_prefix, "%s.tmp.", base);
	snprintf(old_prefix, sizeof old_prefix, "%s.old.", base);
	DIR *d = opendir(parent);
	if (d) {
		struct dirent *e;
		while ((e = readdir(d))) {
			long pid = pid_suffix(e->d_name, tmp_prefix);
			if (!pid)
				pid = pid_suffix(e->d_name, old_prefix);
			if (pid_dead(pid)) {
				char path[8400];
				snprintf(path, sizeof path, "%s/%s", parent, e->d_name);
				remove_result_folder(path);
			}
		}
		closedir(d);
	}
	if ((d = opendir(target))) {
		struct dirent *e;
		while ((e = readdir(d))) {
			long pid;
			if (result_name(e->d_name, &pid) == 2 && pid_dead(pid)) {
				char path[8400];
				snprintf(path, sizeof path, "%s/%s", target, e->d_name);
				unlink(path);
			}
		}
		closedir(d);
	}
}

int dp_cli_check_result_dir(const char *cmd, const char *dir)
{
	char target[4096];
	target_path(dir, target, sizeof target);
	if (!target[0])
		return 0; /* nothing there to replace; creating it reports what is wrong */
	if (strcmp(target, "/") == 0) {
		fprintf(stderr, "dpoints %s: %s: cannot replace the root folder; choose another output\n", cmd, dir);
		return DP_EXIT_INPUT;
	}
	remove_stale(target);
	struct stat sb;
	if (stat(target, &sb) != 0)
		return 0;
	if (!S_ISDIR(sb.st_mode)) {
		fprintf(stderr, "dpoints %s: %s: cannot create output folder: a file of that name exists\n", cmd,
			dir);
		return DP_EXIT_INPUT;
	}
	DIR *d = opendir(target);
	if (!d) {
		fprintf(stderr, "dpoints %s: %s: cannot read output folder: %s\n", cmd, dir, strerror(errno));
		return DP_EXIT_INPUT;
	}
	/* the swap deletes the old folder: anything in it but our own files
	 * would go with it, so such a folder is not ours to replace */
	struct dirent *e;
	const char *other = NULL;
	while ((e = readdir(d)) && !other) {
		long pid;
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && !result_name(e->d_name, &pid))
			other = e->d_name;
	}
	if (other)
		fprintf(stderr,
			"dpoints %s: %s: output folder holds '%s', which is not a dpoints result file; choose an "
			"empty or new folder, or one with an earlier result (report.json, surface.ply, ...) only\n",
			cmd, dir, other);
	closedir(d);
	return other ? DP_EXIT_INPUT : 0;
}

int dp_cli_stage_begin(const char *cmd, const char *dir, char *staging, size_t size)
{
	char parent[4096], base[4096], target[4096];
	split_path(dir, parent, base, sizeof parent);
	int rc = dp_cli_mkdir(cmd, parent);
	if (rc)
		return rc;
	target_path(dir, target, sizeof target);
	if (!target[0]) {
		fprintf(stderr, "dpoints %s: %s: cannot create output folder: %s\n", cmd, dir, strerror(errno));
		return DP_EXIT_INPUT;
	}
	/* again: a run of its own may have been killed since the check */
	if ((rc = dp_cli_check_result_dir(cmd, dir)))
		return rc;
	/* room left for the longest file name, which write_outputs cuts off */
	if ((size_t)snprintf(staging, size, "%s.tmp.%ld", target, (long)getpid()) + 32 >= size) {
		fprintf(stderr, "dpoints %s: %s: cannot create output folder: path too long\n", cmd, dir);
		return DP_EXIT_INPUT;
	}
	remove_result_folder(staging);
	if (mkdir(staging, 0777) != 0) {
		fprintf(stderr, "dpoints %s: %s: cannot create output folder %s: %s\n", cmd, dir, staging,
			strerror(errno));
		return DP_EXIT_INPUT;
	}
	return 0;
}

void dp_cli_stage_abort(const char *staging)
{
	remove_result_folder(staging);
}

int dp_cli_stage_commit(const char *cmd, const char *dir, const char *staging)
{
	char target[4096], old[4200];
	snprintf(target, sizeof target, "%.*s", (int)(strrchr(staging, '.') - staging - 4), staging);
	snprintf(old, sizeof old, "%s.old.%ld", target, (long)getpid());
	struct stat sb;
	int e = 0;
	if (lstat(target, &sb) != 0) {
		if (rename(staging, target) != 0)
			e = errno;
		goto done;
	}
#ifdef RENAME_EXCHANGE
	/* one step: no moment without the folder */
	if (renameat2(AT_FDCWD, staging, AT_FDCWD, target, RENAME_EXCHANGE) == 0) {
		remove_result_folder(staging);
		return 0;
	}
	if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) {
		e = errno;
		goto done;
	}
#endif
	/* two steps: killed between them, the folder is missing, never mixed */
	if (rename(target, old) != 0) {
		e = errno;
		goto done;
	}
	if (rename(staging, target) != 0) {
		e = errno;
		rename(old, target);
		goto done;
	}
	remove_result_folder(old);
done:
	if (!e)
		return 0;
	dp_cli_stage_abort(staging);
	fprintf(stderr, "dpoints %s: %s: cannot replace output folder: %s\n", cmd, dir, strerror(e));
	return DP_EXIT_INPUT;
}
