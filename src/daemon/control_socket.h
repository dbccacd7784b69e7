/* The local control socket: a unix stream socket that appears at its path
 * already listening with its final mode and group (bound under a temporary
 * name, then renamed into place), so no client ever sees it half set up. */
#ifndef UWB_DAEMON_CONTROL_SOCKET_H
#define UWB_DAEMON_CONTROL_SOCKET_H

#include <stddef.h>
#include <sys/types.h>

enum uwbd_control_error {
    UWBD_CONTROL_OK = 0,
    UWBD_CONTROL_ERR_CONFIG = -1, /* the group does not exist or the daemon is not in it */
    UWBD_CONTROL_ERR_CREATE = -2, /* path unusable, in use by another uwbd, bind/listen failed */
};

struct uwbd_control_socket {
    int fd;
    char path[108];
    dev_t dev;
    ino_t ino; /* to remove only our own socket at exit */
};

/* group: name or "" for the daemon's own group. Returns an enum
 * uwbd_control_error with err naming the path or group and the problem. */
int uwbd_control_listen(struct uwbd_control_socket *cs, const char *path, unsigned mode, const char *group,
                        char *err, size_t errlen);
/* Close and remove the socket file if it is still ours. */
void uwbd_control_close(struct uwbd_control_socket *cs);

/* Client side: connect to the daemon's socket. Returns the fd or -1. */
int uwbd_control_connect(const char *path, char *err, size_t errlen);

#endif
