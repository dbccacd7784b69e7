/* What a link backend (src/link/link_socket.c, src/hw/link_serial.c) sees
 * of a link; nothing above the backends includes this. */
#ifndef UWB_LINK_BACKEND_H
#define UWB_LINK_BACKEND_H

#include "uwb/link.h"

struct uwb_link_ops {
    /* ep: the endpoint uwb_link_open parsed; link->endpoint holds its text. */
    int (*open)(struct uwb_link *link, const struct uwb_endpoint *ep, char *err, size_t errlen);
    /* As uwb_link_read. */
    ssize_t (*read)(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err, size_t errlen);
    int (*write_all)(struct uwb_link *link, const void *buf, size_t len, int timeout_ms, char *err,
                     size_t errlen);
    int (*fd)(struct uwb_link *link); /* for poll(); -1 if none */
    void (*close)(struct uwb_link *link);
};

struct uwb_link {
    const struct uwb_link_ops *ops;
    char endpoint[UWB_ENDPOINT_MAX];
    int fd;     /* socket backends: the connected socket, else -1 */
    void *port; /* serial backend: its struct sp_port */
};

extern const struct uwb_link_ops uwb_link_tcp_ops;
extern const struct uwb_link_ops uwb_link_unix_ops;
extern const struct uwb_link_ops uwb_link_serial_ops;

/* A link served by ops, named name, over fd (-1 until a backend's open
 * sets it); NULL with err set when out of memory. */
struct uwb_link *uwb_link_new(const struct uwb_link_ops *ops, const char *name, int fd, char *err,
                              size_t errlen);

/* What is left of timeout_ms at deadline (uwb_monotonic_ms() + timeout_ms
 * when it started): -1 (wait for ever) stays -1, a passed deadline is 0. */
int uwb_link_time_left(long long deadline, int timeout_ms);

/* Waits for `events` on fd; 1 ready, 0 timed out, -1 error (errno).
 * Shared by the socket backend and the listener (src/link/). */
int uwb_link_wait_fd(int fd, short events, int timeout_ms);

#endif
