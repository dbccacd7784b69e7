/* What a link backend (src/link/link_socket.c, src/hw/link_serial.c) sees
 * of a link; nothing above the backends includes this. */
#ifndef UWB_LINK_BACKEND_H
#define UWB_LINK_BACKEND_H

#include "uwb/link.h"

struct uwb_link {
    const struct uwb_link_ops *ops;
    char endpoint[UWB_ENDPOINT_MAX];
    int fd;            /* socket backends: the connected socket, else -1 */
    void *port;        /* serial backend: its struct sp_port */
};

extern const struct uwb_link_ops uwb_link_tcp_ops;
extern const struct uwb_link_ops uwb_link_unix_ops;
extern const struct uwb_link_ops uwb_link_serial_ops;

/* Socket helpers the socket backend shares with the listener. */
ssize_t uwb_link_socket_read(struct uwb_link *link, void *buf, size_t len, int timeout_ms,
                             char *err, size_t errlen);
int uwb_link_socket_write_all(struct uwb_link *link, const void *buf, size_t len, int timeout_ms,
                              char *err, size_t errlen);
int uwb_link_socket_fd(struct uwb_link *link);
void uwb_link_socket_close(struct uwb_link *link);

#endif
