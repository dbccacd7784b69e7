/* Socket links: tcp:HOST:PORT (a digitiser behind ser2net or on Ethernet)
 * and unix:PATH (the emulated board). Reads and writes wait with poll()
 * so every call has a timeout; MSG_NOSIGNAL turns a vanished peer into an
 * error instead of SIGPIPE. */
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "link/link_backend.h"
#include "uwb/monotonic.h"

#define CONNECT_TIMEOUT_MS 5000

int uwb_link_wait_fd(int fd, short events, int timeout_ms)
{
    long long deadline = uwb_monotonic_ms() + timeout_ms;
    for (;;) {
        struct pollfd p = {.fd = fd, .events = events};
        int n = poll(&p, 1, uwb_link_time_left(deadline, timeout_ms));
        if (n > 0)
            return 1;
        if (n == 0)
            return 0;
        if (errno != EINTR)
            return -1;
    }
}

static ssize_t socket_read(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err,
                           size_t errlen)
{
    if (link->fd < 0) {
        snprintf(err, errlen, "%s: link is closed", link->endpoint);
        return UWB_LINK_ERR_IO;
    }
    for (;;) {
        int ready = uwb_link_wait_fd(link->fd, POLLIN, timeout_ms);
        if (ready == 0) {
            snprintf(err, errlen, "%s: no data within %d ms", link->endpoint, timeout_ms);
            return UWB_LINK_ERR_TIMEOUT;
        }
        if (ready < 0) {
            snprintf(err, errlen, "%s: poll: %s", link->endpoint, strerror(errno));
            return UWB_LINK_ERR_IO;
        }
        ssize_t n = recv(link->fd, buf, len, 0);
        if (n > 0)
            return n;
        if (n == 0) {
            snprintf(err, errlen, "%s: peer closed the connection", link->endpoint);
            return UWB_LINK_ERR_IO;
        }
        if (errno == EINTR || errno == EAGAIN)
            continue;
        snprintf(err, errlen, "%s: read: %s", link->endpoint, strerror(errno));
        return UWB_LINK_ERR_IO;
    }
}

static int socket_write_all(struct uwb_link *link, const void *buf, size_t len, int timeout_ms, char *err,
                            size_t errlen)
{
    if (link->fd < 0) {
        snprintf(err, errlen, "%s: link is closed", link->endpoint);
        return UWB_LINK_ERR_IO;
    }
    long long deadline = uwb_monotonic_ms() + timeout_ms;
    size_t done = 0;
    while (done < len) {
        ssize_t n = send(link->fd, (const char *)buf + done, len - done, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            done += (size_t)n;
            continue;
        }
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
            snprintf(err, errlen, "%s: write: %s", link->endpoint, strerror(errno));
            return UWB_LINK_ERR_IO;
        }
        int ready = uwb_link_wait_fd(link->fd, POLLOUT, uwb_link_time_left(deadline, timeout_ms));
        if (ready == 0) {
            snprintf(err, errlen, "%s: peer not reading: %zu of %zu bytes sent within %d ms", link->endpoint,
                     done, len, timeout_ms);
            return UWB_LINK_ERR_TIMEOUT;
        }
        if (ready < 0) {
            snprintf(err, errlen, "%s: poll: %s", link->endpoint, strerror(errno));
            return UWB_LINK_ERR_IO;
        }
    }
    return UWB_LINK_OK;
}

static int socket_fd(struct uwb_link *link)
{
    return link->fd;
}

static void socket_close(struct uwb_link *link)
{
    if (link->fd >= 0)
        close(link->fd);
    link->fd = -1;
}

/* Non-blocking connect bounded by CONNECT_TIMEOUT_MS; returns 0 or errno. */
static int connect_bounded(int fd, const struct sockaddr *addr, socklen_t addrlen)
{
    int flags = fcntl(fd, F_GETFL);
    if (flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0)
        return errno;
    int rc = connect(fd, addr, addrlen);
    int error = 0;
    if (rc < 0 && errno != EINPROGRESS) {
        error = errno;
    } else if (rc < 0) {
        int ready = uwb_link_wait_fd(fd, POLLOUT, CONNECT_TIMEOUT_MS);
        socklen_t elen = sizeof error;
        if (ready == 0)
            error = ETIMEDOUT;
        else if (ready < 0 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &elen) < 0)
            error = errno;
    }
    if (!error && fcntl(fd, F_SETFL, flags) < 0)
        error = errno;
    return error;
}

static int tcp_open(struct uwb_link *link, const struct uwb_endpoint *ep, char *err, size_t errlen)
{
    struct addrinfo hints = {.ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM}, *res;
    int gai = getaddrinfo(ep->host, ep->port, &hints, &res);
    if (gai != 0) {
        snprintf(err, errlen, "%s: cannot resolve host '%s': %s", link->endpoint, ep->host,
                 gai_strerror(gai));
        return UWB_LINK_ERR_OPEN;
    }
    int error = 0;
    for (struct addrinfo *ai = res; ai; ai = ai->ai_next) {
        int fd = socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC, ai->ai_protocol);
        if (fd < 0) {
            error = errno;
            continue;
        }
        error = connect_bounded(fd, ai->ai_addr, ai->ai_addrlen);
        if (error == 0) {
            /* GPIO messages are a few bytes each: send them at once. */
            int one = 1;
            setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            link->fd = fd;
            freeaddrinfo(res);
            return UWB_LINK_OK;
        }
        close(fd);
    }
    freeaddrinfo(res);
    snprintf(err, errlen, "%s: cannot connect: %s", link->endpoint, strerror(error ? error : ECONNREFUSED));
    return UWB_LINK_ERR_OPEN;
}

static int unix_open(struct uwb_link *link, const struct uwb_endpoint *ep, char *err, size_t errlen)
{
    struct sockaddr_un sun = {.sun_family = AF_UNIX};
    memcpy(sun.sun_path, ep->path, strlen(ep->path) + 1); /* length checked by the parser */
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        snprintf(err, errlen, "%s: socket: %s", link->endpoint, strerror(errno));
        return UWB_LINK_ERR_OPEN;
    }
    int error = connect_bounded(fd, (const struct sockaddr *)&sun, sizeof sun);
    if (error) {
        close(fd);
        snprintf(err, errlen, "%s: cannot connect to socket %s: %s", link->endpoint, ep->path,
                 strerror(error));
        return UWB_LINK_ERR_OPEN;
    }
    link->fd = fd;
    return UWB_LINK_OK;
}

const struct uwb_link_ops uwb_link_tcp_ops = {
    .open = tcp_open,
    .read = socket_read,
    .write_all = socket_write_all,
    .fd = socket_fd,
    .close = socket_close,
};

const struct uwb_link_ops uwb_link_unix_ops = {
    .open = unix_open,
    .read = socket_read,
    .write_all = socket_write_all,
    .fd = socket_fd,
    .close = socket_close,
};

/* A link over a socket someone else connected: socketpair or accept. */
static const struct uwb_link_ops fd_ops = {
    .open = NULL,
    .read = socket_read,
    .write_all = socket_write_all,
    .fd = socket_fd,
    .close = socket_close,
};

int uwb_link_from_fd(int fd, const char *name, struct uwb_link **link, char *err, size_t errlen)
{
    *link = uwb_link_new(&fd_ops, name, fd, err, errlen);
    if (!*link) {
        close(fd);
        return UWB_LINK_ERR_OPEN;
    }
    return UWB_LINK_OK;
}
