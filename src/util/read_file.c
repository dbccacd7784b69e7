/* The one bounded whole-file reader (see uwb/read_file.h). */
#include "uwb/read_file.h"
#include "uwb/regular_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* First buffer when the size is not known beforehand (pipes, sockets, /proc). */
#define UNKNOWN_SIZE_FIRST_BUFFER 65536

enum uwb_read_result uwb_read_fd(int fd, const char *name, size_t max_bytes, char **out, size_t *out_len,
                                 char *err, size_t errlen)
{
    *out = NULL;
    *out_len = 0;
    struct stat st;
    if (fstat(fd, &st) != 0) {
        snprintf(err, errlen, "%s: cannot stat: %s", name, strerror(errno));
        return UWB_READ_FAILED;
    }
    if (S_ISDIR(st.st_mode)) {
        snprintf(err, errlen, "%s: cannot read: %s", name, strerror(EISDIR));
        return UWB_READ_FAILED;
    }
    /* A regular file tells its size: refuse it before allocating anything. */
    int size_known = S_ISREG(st.st_mode) && st.st_size > 0;
    if (size_known && (uintmax_t)st.st_size > max_bytes) {
        snprintf(err, errlen, "%s: too big: %jd bytes, over the limit of %zu", name, (intmax_t)st.st_size,
                 max_bytes);
        return UWB_READ_TOO_BIG;
    }
    /* So that max_bytes + 2 below cannot wrap (no such buffer could be allocated anyway). */
    if (max_bytes > SIZE_MAX - 2)
        max_bytes = SIZE_MAX - 2;
    /* max_bytes, one byte more to see the input go past the limit, and the NUL. */
    size_t room_limit = max_bytes + 2;
    /* The +2 leaves room for the read that finds EOF, so a file of the size
     * fstat gave is never copied into a doubled buffer just to learn it ended. */
    size_t room = size_known ? (size_t)st.st_size + 2 : UNKNOWN_SIZE_FIRST_BUFFER;
    if (room > room_limit)
        room = room_limit;

    char *buf = malloc(room);
    if (buf == NULL) {
        snprintf(err, errlen, "%s: cannot read: out of memory (%zu bytes)", name, room);
        return UWB_READ_FAILED;
    }
    size_t len = 0;
    enum uwb_read_result rc = UWB_READ_FAILED;
    for (;;) {
        if (len + 1 == room) {
            room = room > room_limit / 2 ? room_limit : room * 2;
            char *grown = realloc(buf, room);
            if (grown == NULL) {
                snprintf(err, errlen, "%s: cannot read: out of memory (%zu bytes)", name, room);
                goto fail;
            }
            buf = grown;
        }
        ssize_t got = read(fd, buf + len, room - 1 - len);
        if (got < 0) {
            if (errno == EINTR)
                continue;
            snprintf(err, errlen, "%s: cannot read: %s", name, strerror(errno));
            goto fail;
        }
        if (got == 0)
            break;
        len += (size_t)got;
        if (len > max_bytes) {
            snprintf(err, errlen, "%s: too big: over the limit of %zu bytes", name, max_bytes);
            rc = UWB_READ_TOO_BIG;
            goto fail;
        }
    }
    buf[len] = '\0';
    *out = buf;
    *out_len = len;
    return UWB_READ_OK;
fail:
    free(buf);
    return rc;
}

static enum uwb_read_result read_regular(const char *path, int flags, size_t max_bytes, char **out,
                                         size_t *out_len, char *err, size_t errlen)
{
    *out = NULL;
    *out_len = 0;
    const char *problem = NULL;
    int fd = uwb_open_regular(path, O_RDONLY | flags, 0, &problem);
    if (fd < 0) {
        snprintf(err, errlen, "%s: cannot open: %s", path, problem);
        return UWB_READ_FAILED;
    }
    enum uwb_read_result rc = uwb_read_fd(fd, path, max_bytes, out, out_len, err, errlen);
    close(fd);
    return rc;
}

enum uwb_read_result uwb_read_file(const char *path, size_t max_bytes, char **out, size_t *out_len, char *err,
                                   size_t errlen)
{
    return read_regular(path, 0, max_bytes, out, out_len, err, errlen);
}

enum uwb_read_result uwb_read_file_nofollow(const char *path, size_t max_bytes, char **out, size_t *out_len,
                                            char *err, size_t errlen)
{
    return read_regular(path, O_NOFOLLOW, max_bytes, out, out_len, err, errlen);
}
