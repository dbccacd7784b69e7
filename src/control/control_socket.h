/* The local control socket: a unix stream socket that appears at its path
 * already listening with its final mode and group (bound under a temporary
 * name, then renamed into place), so no client ever sees it half set up. */
#ifndef UWB_CONTROL_CONTROL_SOCKET_H
#define UWB_CONTROL_CONTROL_SOCKET_H

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

enum {
    UWBD_CONTROL_CONNECT_FAILED = -1,  /* no such socket, refused, ...: err says why */
    UWBD_CONTROL_CONNECT_TIMEOUT = -2, /* the daemon did not accept within the timeout */
    UWBD_CONTROL_CONNECT_DENIED = -3,  /* this user may not open the socket (EACCES, EPERM) */
};
/* Client side: connect to the daemon's socket, waiting at most timeout_s
 * for a daemon whose backlog is full. Returns the fd (blocking), or one of
 * the codes above with err naming the path and the problem. */
int uwbd_control_connect(const char *path, double timeout_s, char *err, size_t errlen);
/* Why connect() on path failed with error (EACCES, EPERM), in err: the
 * directory or the socket that shuts this user out, its mode, owner and
 * group, and what to do (join the group, log in again, ...). */
void uwbd_control_explain_denied(const char *path, int error, char *err, size_t errlen);
/* Client side: send n bytes of text. 0, or -1 with errno; when the daemon
 * had closed the connection (EPIPE, ECONNRESET), reason holds the line it
 * wrote before closing (its refusal), "" when none. */
int uwbd_control_send(int fd, const char *text, size_t n, char *reason, size_t reason_len);

#endif
