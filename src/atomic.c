/* atomic.c: write-to-temporary-then-rename, so that a failed writer never
 * leaves a half-written file and never touches an existing target. */
#include "imageio.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* Open "<path>.tmp.<pid>" for writing (and reading, so libtiff may use the
 * descriptor too).  tmp receives the temporary name.  Returns the stream, or
 * NULL with TD_EINVAL (bad arguments) or TD_EIO (cannot create, message
 * naming path) in cx. */
FILE *td_atomic_open(const char *path, char *tmp, size_t tmpsize, td_ctx *cx)
{
    FILE *f;
    int n;
    if (!path || !*path || !tmp) {
        td_seterr(cx, TD_EINVAL, "no output file name given");
        return NULL;
    }
    n = snprintf(tmp, tmpsize, "%s.tmp.%ld", path, (long)getpid());
    if (n < 0 || (size_t)n >= tmpsize) {
        td_seterr(cx, TD_EINVAL, "%s: file name too long", path);
        return NULL;
    }
    f = fopen(tmp, "w+b");
    if (!f) {
        td_seterr(cx, TD_EIO, "%s: cannot create: %s", path, strerror(errno));
        return NULL;
    }
    return f;
}

/* Flush, fsync and close f, then rename tmp over path.  On any failure the
 * temporary is removed, an existing path is left as it was, and TD_EIO is
 * returned with a message naming path. */
int td_atomic_commit(FILE *f, const char *tmp, const char *path, td_ctx *cx)
{
    int err = 0;
    if (!f)
        return td_seterr(cx, TD_EINVAL, "%s: no open file to commit", path);
    errno = 0;
    if (fflush(f) != 0 || ferror(f))
        err = errno ? errno : EIO;
    if (!err && fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS)
        err = errno;
    if (fclose(f) != 0 && !err)
        err = errno ? errno : EIO;
    if (!err && rename(tmp, path) != 0)
        err = errno;
    if (!err)
        return 0;
    remove(tmp);
    return td_seterr(cx, TD_EIO, "%s: write failed: %s", path, strerror(err));
}

/* Close f (may be NULL) and remove tmp (may be NULL); never fails. */
void td_atomic_abort(FILE *f, const char *tmp)
{
    if (f)
        fclose(f);
    if (tmp && *tmp)
        remove(tmp);
}
