/* A byte stream to a peer named by an endpoint string:
 *   serial:/dev/ttyUSB0?baud=921600   through libserialport (src/hw/)
 *   tcp:HOST:PORT                     a digitiser behind ser2net or on Ethernet
 *   unix:PATH                         a local socket (the emulated board)
 * Every read has a timeout; nothing above this layer knows which it is. */
#ifndef UWB_LINK_H
#define UWB_LINK_H

#include <stddef.h>
#include <sys/types.h>

#define UWB_ENDPOINT_MAX 256

enum uwb_link_error {
    UWB_LINK_OK = 0,
    UWB_LINK_ERR_ENDPOINT = -1, /* malformed endpoint string */
    UWB_LINK_ERR_OPEN = -2,     /* port missing, connection refused, ... */
    UWB_LINK_ERR_IO = -3,       /* read/write failed, peer closed */
    UWB_LINK_ERR_TIMEOUT = -4,
};

enum uwb_endpoint_kind { UWB_ENDPOINT_SERIAL, UWB_ENDPOINT_TCP, UWB_ENDPOINT_UNIX };

#define UWB_SERIAL_DEFAULT_BAUD 115200

/* An endpoint string taken apart. */
struct uwb_endpoint {
    enum uwb_endpoint_kind kind;
    char path[UWB_ENDPOINT_MAX]; /* serial device or unix socket path */
    char host[UWB_ENDPOINT_MAX]; /* tcp: name or address, IPv6 without its [] */
    char port[8];                /* tcp: 1..65535 as text */
    int baud;                    /* serial: ?baud=N, else UWB_SERIAL_DEFAULT_BAUD */
    char parity;                 /* serial: ?parity=none|even|odd as 'N', 'E', 'O'; else 'N' */
    int stop_bits;               /* serial: ?stopbits=1|2, else 1 */
};

/* Pure parsing, no I/O. Returns UWB_LINK_OK or UWB_LINK_ERR_ENDPOINT with
 * err quoting the endpoint and saying what is wrong with it. */
int uwb_endpoint_parse(const char *text, struct uwb_endpoint *ep, char *err, size_t errlen);

struct uwb_link;

int uwb_link_open(const char *endpoint, struct uwb_link **link, char *err, size_t errlen);
/* Up to len bytes, waiting at most timeout_ms (-1: for ever) for the first;
 * returns the count (> 0) or an enum uwb_link_error. */
ssize_t uwb_link_read(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err, size_t errlen);
/* Exactly len bytes or an error. */
int uwb_link_read_exact(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err,
                        size_t errlen);
int uwb_link_write_all(struct uwb_link *link, const void *buf, size_t len, int timeout_ms, char *err,
                       size_t errlen);
int uwb_link_fd(struct uwb_link *link);
/* The endpoint string the link was opened with (for messages). */
const char *uwb_link_name(const struct uwb_link *link);
void uwb_link_close(struct uwb_link *link);

/* A link over an already connected socket (socketpair, accepted
 * connection); the link owns fd from now on, also on failure. */
int uwb_link_from_fd(int fd, const char *name, struct uwb_link **link, char *err, size_t errlen);

/* The serving side, for the emulated board and for tests: listen on
 * unix:PATH (a stale socket file is replaced) or tcp:HOST:PORT, and accept
 * one peer after another. */
struct uwb_link_listener;
int uwb_link_listen(const char *endpoint, struct uwb_link_listener **listener, char *err, size_t errlen);
int uwb_link_listener_fd(const struct uwb_link_listener *listener);
/* Accept one pending connection (call when listener_fd polls readable;
 * waits at most timeout_ms otherwise). */
int uwb_link_accept(struct uwb_link_listener *listener, struct uwb_link **link, int timeout_ms, char *err,
                    size_t errlen);
/* Closes the socket and removes a unix socket's file. NULL is a no-op. */
void uwb_link_listener_close(struct uwb_link_listener *listener);

#endif
