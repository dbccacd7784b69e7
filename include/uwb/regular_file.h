/* Opening a file that must be a regular file, without ever blocking: a
 * FIFO put where a state or config file belongs would otherwise hold
 * open() (or the first write) for ever. */
#ifndef UWB_REGULAR_FILE_H
#define UWB_REGULAR_FILE_H

#include <sys/types.h>

/* open(path, flags | O_NONBLOCK | O_CLOEXEC, mode), kept only if fstat says
 * it is a regular file; O_NONBLOCK is cleared again before returning, so
 * reads and writes behave as usual. Pass O_NOFOLLOW in flags for files
 * in the state directory. Returns the fd, or -1 with errno set and
 * *problem (never NULL then) saying why in words to follow "PATH: ":
 * strerror(errno) (ENOENT, EACCES, EISDIR for a directory...), "is a
 * symbolic link, which uwbd does not follow in its state directory"
 * (O_NOFOLLOW: meant for state files), or "is a FIFO, not a regular
 * file" (likewise a socket or a device; errno EINVAL). */
int uwb_open_regular(const char *path, int flags, mode_t mode, const char **problem);

#endif
