/* outfile.c: write-to-temporary-then-rename, so that a failed writer never
 * leaves a half-written file and never touches an existing target. */
#include "src/io/io.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Refuse a target that exists and is no regular file (a directory, a
 * device, a FIFO): renaming over it would replace a device node with a
 * file, or fail only after all the work.  0 or TD_EINVAL naming path. */
int td_atomic_check_target(const char *path, td_ctx *cx)
{
    struct stat st;
    if (!path || !*path)
        return td_seterr(cx, TD_EINVAL, "no output file name given");
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return td_seterr(cx, TD_EINVAL,
                         "%s: is %s, not a regular file: give a file name",
                         path,
                         S_ISDIR(st.st_mode)                          ? "a folder"
                         : S_ISFIFO(st.st_mode)                       ? "a FIFO"
                         : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                                      : "special");
    return 0;
}

/* An input must be a file (or a FIFO or device a user pipes in): a
 * folder is named as such, not read as an empty file.  0 or TD_EINVAL. */
int td_check_input(const char *path, td_ctx *cx)
{
    struct stat st;
    if (!path || !*path)
        return td_seterr(cx, TD_EINVAL, "no input file name given");
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return td_seterr(cx, TD_EINVAL, "%s: is a folder, not a file", path);
    return 0;
}

/* Create "<path>.tmp.<pid>.<n>" for writing (and reading, so libtiff may
 * use the descriptor too): O_CREAT | O_EXCL | O_NOFOLLOW, so a file or a
 * symbolic link planted under that name is never opened nor followed (the
 * next n is tried), mode 0666 less the umask as any new file.  tmp
 * receives the name.  Returns the stream, or NULL with TD_EINVAL (bad
 * arguments, a target that is no regular file) or TD_EIO (cannot create,
 * message naming path) in cx. */
FILE *td_atomic_open(const char *path, char *tmp, size_t tmpsize, td_ctx *cx)
{
    FILE *f;
    int n, fd = -1, k;
    if (!path || !*path || !tmp) {
        td_seterr(cx, TD_EINVAL, "no output file name given");
        return NULL;
    }
    if (td_atomic_check_target(path, cx) != 0)
        return NULL;
    for (k = 0; k < 100 && fd < 0; k++) {
        n = snprintf(tmp, tmpsize, "%s.tmp.%ld.%d", path, (long)getpid(), k);
        if (n < 0 || (size_t)n >= tmpsize) {
            td_seterr(cx, TD_EINVAL, "%s: file name too long", path);
            return NULL;
        }
        fd = open(tmp, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
                  0666);
        if (fd < 0 && errno != EEXIST)
            break;
    }
    if (fd < 0 || !(f = fdopen(fd, "w+b"))) {
        int e = errno;
        if (fd >= 0) {
            close(fd);
            remove(tmp);
        }
        td_seterr(cx, TD_EIO, "%s: cannot create: %s", path, strerror(e));
        tmp[0] = '\0';
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
    if (!err && td_atomic_check_target(path, NULL) != 0)
        err = EISDIR; /* it became one while we worked */
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
