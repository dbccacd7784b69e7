/* Opening only regular files, never blocking (see uwb/regular_file.h). */
#include "uwb/regular_file.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* What mode is, in words, when it is not a regular file; NULL when it is. */
static const char *not_regular(mode_t mode)
{
    if (S_ISREG(mode))
        return NULL;
    if (S_ISFIFO(mode))
        return "is a FIFO, not a regular file";
    if (S_ISSOCK(mode))
        return "is a socket, not a regular file";
    if (S_ISCHR(mode))
        return "is a character device, not a regular file";
    if (S_ISBLK(mode))
        return "is a block device, not a regular file";
    return "is not a regular file";
}

/* Why the open failed: a FIFO opened for writing with no reader fails
 * with ENXIO, a socket with ENXIO too, so look at what is there. */
static int explain_failure(const char *path, int flags, int e, const char **problem)
{
    if (e == ELOOP && (flags & O_NOFOLLOW)) {
        *problem = "is a symbolic link, which uwbd does not follow in its state directory";
        errno = ELOOP;
        return -1;
    }
    struct stat st;
    int follow = !(flags & O_NOFOLLOW);
    int looked = follow ? stat(path, &st) : lstat(path, &st);
    if (e == EISDIR || (looked == 0 && S_ISDIR(st.st_mode))) {
        *problem = strerror(EISDIR);
        errno = EISDIR;
        return -1;
    }
    if (looked == 0 && not_regular(st.st_mode) && e != ENOENT && e != EACCES) {
        *problem = not_regular(st.st_mode);
        errno = EINVAL;
        return -1;
    }
    *problem = strerror(e);
    errno = e;
    return -1;
}

int uwb_open_regular(const char *path, int flags, mode_t mode, const char **problem)
{
    *problem = NULL;
    int fd = open(path, flags | O_NONBLOCK | O_CLOEXEC, mode);
    if (fd < 0)
        return explain_failure(path, flags, errno, problem);
    struct stat st;
    int e;                  /* errno to leave */
    const char *why = NULL; /* NULL: strerror(e) */
    if (fstat(fd, &st) != 0) {
        e = errno;
        goto fail;
    }
    if (!S_ISREG(st.st_mode)) {
        e = S_ISDIR(st.st_mode) ? EISDIR : EINVAL;
        why = S_ISDIR(st.st_mode) ? strerror(EISDIR) : not_regular(st.st_mode);
        goto fail;
    }
    /* Regular files never block anyway; cleared so the caller sees the
     * flags it asked for. */
    int fl = fcntl(fd, F_GETFL);
    if (!(flags & O_NONBLOCK) && (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0)) {
        e = errno;
        goto fail;
    }
    return fd;
fail:
    close(fd);
    *problem = why ? why : strerror(e);
    errno = e;
    return -1;
}
