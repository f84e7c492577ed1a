#include "io/io.h"

#include "core/common.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

dp_status dp_atomic_open(dp_atomic_file *af, const char *path, dp_error *err)
{
	memset(af, 0, sizeof *af);
	af->path = path;
	/* Same folder as the target, so the rename stays on one file system. */
	int len = snprintf(NULL, 0, "%s.tmp.%ld", path, (long)getpid());
	af->tmp_path = malloc((size_t)len + 1);
	if (!af->tmp_path)
		return dp_fail(err, DP_ERR_NOMEM, "%s: out of memory", path);
	snprintf(af->tmp_path, (size_t)len + 1, "%s.tmp.%ld", path, (long)getpid());
	int fd = open(af->tmp_path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	if (fd < 0) {
		int e = errno;
		free(af->tmp_path);
		af->tmp_path = NULL;
		return dp_fail(err, DP_ERR_IO, "%s: cannot create a temporary file beside it: %s", path, strerror(e));
	}
	af->f = fdopen(fd, "wb");
	if (!af->f) {
		int e = errno;
		close(fd);
		dp_atomic_abort(af);
		return dp_fail(err, DP_ERR_IO, "%s: cannot open a stream: %s", path, strerror(e));
	}
	return DP_OK;
}

dp_status dp_atomic_commit(dp_atomic_file *af, dp_error *err)
{
	int e = 0;
	errno = 0;
	if (fflush(af->f) != 0 || ferror(af->f))
		e = errno ? errno : EIO;
	/* Sync before the rename so a crash cannot leave a renamed but empty
	 * file; EINVAL means the file system has nothing to sync. */
	if (!e && fsync(fileno(af->f)) != 0 && errno != EINVAL)
		e = errno;
	if (fclose(af->f) != 0 && !e)
		e = errno;
	af->f = NULL;
	if (!e && rename(af->tmp_path, af->path) != 0)
		e = errno;
	if (e) {
		dp_atomic_abort(af);
		return dp_fail(err, DP_ERR_IO, "%s: write failed: %s", af->path, strerror(e));
	}
	free(af->tmp_path);
	af->tmp_path = NULL;
	return DP_OK;
}

void dp_atomic_abort(dp_atomic_file *af)
{
	if (af->f)
		fclose(af->f);
	af->f = NULL;
	if (af->tmp_path)
		unlink(af->tmp_path);
	free(af->tmp_path);
	af->tmp_path = NULL;
}
