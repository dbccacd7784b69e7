/* The serving side of unix: and tcp: endpoints (the emulated board, test
 * peers): listen, then accept one connection after another, so a peer that
 * drops can come back. */
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "link/link_backend.h"

struct uwb_link_listener {
    int fd;
    int is_tcp;
    char endpoint[UWB_ENDPOINT_MAX];
    char unix_path[UWB_ENDPOINT_MAX]; /* removed on close; "" for tcp */
};

static int listen_unix(struct uwb_link_listener *l, const struct uwb_endpoint *ep, char *err, size_t errlen)
{
    struct sockaddr_un sun = {.sun_family = AF_UNIX};
    memcpy(sun.sun_path, ep->path, strlen(ep->path) + 1);
    /* A socket file left by a previous run would make bind fail; anything
     * else at that path is not ours to remove. */
    struct stat st;
    if (lstat(ep->path, &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            snprintf(err, errlen, "%s: %s exists and is not a socket", l->endpoint, ep->path);
            return UWB_LINK_ERR_OPEN;
        }
        unlink(ep->path);
    }
    l->fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (l->fd < 0 || bind(l->fd, (const struct sockaddr *)&sun, sizeof sun) < 0 || listen(l->fd, 4) < 0) {
        snprintf(err, errlen, "%s: cannot listen on %s: %s", l->endpoint, ep->path, strerror(errno));
        return UWB_LINK_ERR_OPEN;
    }
    snprintf(l->unix_path, sizeof l->unix_path, "%s", ep->path);
    return UWB_LINK_OK;
}

static int listen_tcp(struct uwb_link_listener *l, const struct uwb_endpoint *ep, char *err, size_t errlen)
{
    struct addrinfo hints = {.ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM, .ai_flags = AI_PASSIVE},
                    *res;
    int gai = getaddrinfo(ep->host, ep->port, &hints, &res);
    if (gai != 0) {
        snprintf(err, errlen, "%s: cannot resolve host '%s': %s", l->endpoint, ep->host, gai_strerror(gai));
        return UWB_LINK_ERR_OPEN;
    }
    int error = 0;
    for (struct addrinfo *ai = res; ai; ai = ai->ai_next) {
        int fd = socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC, ai->ai_protocol);
        if (fd < 0) {
            error = errno;
            continue;
        }
        int one = 1;
        setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        if (bind(fd, ai->ai_addr, ai->ai_addrlen) == 0 && listen(fd, 4) == 0) {
            l->fd = fd;
            l->is_tcp = 1;
            freeaddrinfo(res);
            return UWB_LINK_OK;
        }
        error = errno;
        close(fd);
    }
    freeaddrinfo(res);
    snprintf(err, errlen, "%s: cannot listen: %s", l->endpoint, strerror(error));
    return UWB_LINK_ERR_OPEN;
}

int uwb_link_listen(const char *endpoint, struct uwb_link_listener **listener, char *err, size_t errlen)
{
    *listener = NULL;
    struct uwb_endpoint ep;
    int rc = uwb_endpoint_parse(endpoint, &ep, err, errlen);
    if (rc != UWB_LINK_OK)
        return rc;
    if (ep.kind == UWB_ENDPOINT_SERIAL) {
        snprintf(err, errlen, "%s: only unix: and tcp: endpoints can be listened on", endpoint);
        return UWB_LINK_ERR_ENDPOINT;
    }
    struct uwb_link_listener *l = calloc(1, sizeof *l);
    if (!l) {
        snprintf(err, errlen, "%s: out of memory", endpoint);
        return UWB_LINK_ERR_OPEN;
    }
    l->fd = -1;
    snprintf(l->endpoint, sizeof l->endpoint, "%s", endpoint);
    rc = ep.kind == UWB_ENDPOINT_UNIX ? listen_unix(l, &ep, err, errlen) : listen_tcp(l, &ep, err, errlen);
    if (rc != UWB_LINK_OK) {
        if (l->fd >= 0)
            close(l->fd);
        free(l);
        return rc;
    }
    *listener = l;
    return UWB_LINK_OK;
}

int uwb_link_listener_fd(const struct uwb_link_listener *listener)
{
    return listener->fd;
}

int uwb_link_accept(struct uwb_link_listener *l, struct uwb_link **link, int timeout_ms, char *err,
                    size_t errlen)
{
    *link = NULL;
    int n = uwb_link_wait_fd(l->fd, POLLIN, timeout_ms);
    if (n == 0) {
        snprintf(err, errlen, "%s: nobody connected within %d ms", l->endpoint, timeout_ms);
        return UWB_LINK_ERR_TIMEOUT;
    }
    int fd = n > 0 ? accept(l->fd, NULL, NULL) : -1;
    if (fd >= 0)
        fcntl(fd, F_SETFD, FD_CLOEXEC);
    if (fd < 0) {
        snprintf(err, errlen, "%s: accept: %s", l->endpoint, strerror(errno));
        return UWB_LINK_ERR_IO;
    }
    if (l->is_tcp) {
        int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    }
    return uwb_link_from_fd(fd, l->endpoint, link, err, errlen);
}

void uwb_link_listener_close(struct uwb_link_listener *l)
{
    if (!l)
        return;
    if (l->fd >= 0)
        close(l->fd);
    if (l->unix_path[0])
        unlink(l->unix_path);
    free(l);
}
