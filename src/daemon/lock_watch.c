/* The state directory's lock is a flock on STATE_DIR/uwbd.lock. Deleting
 * the tree (rm -rf) takes the lock file with it, and a second uwbd would
 * then lock a new one and share the directory with us. So the lock file is
 * watched (inotify): once the path no longer names the file we hold, this
 * daemon stops with a clear message rather than keep writing into a tree
 * that another may own. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include "daemon_internal.h"
#include "control/exit_codes.h"
#include "util/log.h"

static void lock_path(const struct daemon *d, char *path, size_t n)
{
    uwbd_path_join(path, n, d->store.root, "uwbd.lock");
}

int uwbd_lock_watch_open(struct daemon *d)
{
    char path[UWBD_PATH_MAX + 16];
    lock_path(d, path, sizeof path);
    d->lock_watch_fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (d->lock_watch_fd < 0 ||
        inotify_add_watch(d->lock_watch_fd, path, IN_ATTRIB | IN_DELETE_SELF | IN_MOVE_SELF) < 0 ||
        inotify_add_watch(d->lock_watch_fd, d->store.root, IN_DELETE_SELF | IN_MOVE_SELF) < 0) {
        uwbd_log(UWBD_LOG_WARNING, "%s: cannot watch the lock file (%s); it is checked before each scan",
                 path, strerror(errno));
        if (d->lock_watch_fd >= 0)
            close(d->lock_watch_fd);
        d->lock_watch_fd = -1;
        return -1;
    }
    return 0;
}

void uwbd_lock_watch_check(struct daemon *d)
{
    char events[4096];
    while (d->lock_watch_fd >= 0 && read(d->lock_watch_fd, events, sizeof events) > 0) {
        /* what happened is read below from the file system itself */
    }
    if (d->exit_code || d->lock_fd < 0)
        return;
    char path[UWBD_PATH_MAX + 16];
    lock_path(d, path, sizeof path);
    struct stat held, named;
    if (fstat(d->lock_fd, &held) != 0)
        return;
    int ours = stat(path, &named) == 0 && named.st_dev == held.st_dev && named.st_ino == held.st_ino;
    if (ours)
        return;
    uwbd_log(UWBD_LOG_ERR,
             "state directory %s: its lock file %s was deleted or replaced (the state directory "
             "removed?); stopping, so that no other uwbd shares it with this one. Restore the state "
             "directory (or accept a fresh one) and start uwbd again",
             d->store.root, path);
    d->exit_code = UWBD_EXIT_CANT_CREATE;
    if (!d->stopping) {
        d->stopping = 1;
        uwbd_worker_request_stop(d);
    }
}
