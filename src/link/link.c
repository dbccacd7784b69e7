/* The link dispatcher: picks the backend from the endpoint's scheme; the
 * callers above never learn which one serves them. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "link/link_backend.h"
#include "uwb/monotonic.h"

static const struct uwb_link_ops *ops_for(enum uwb_endpoint_kind kind)
{
    switch (kind) {
    case UWB_ENDPOINT_SERIAL: return &uwb_link_serial_ops;
    case UWB_ENDPOINT_TCP: return &uwb_link_tcp_ops;
    case UWB_ENDPOINT_UNIX: return &uwb_link_unix_ops;
    }
    return NULL;
}

struct uwb_link *uwb_link_new(const struct uwb_link_ops *ops, const char *name, int fd, char *err,
                              size_t errlen)
{
    struct uwb_link *l = calloc(1, sizeof *l);
    if (!l) {
        snprintf(err, errlen, "%s: out of memory", name);
        return NULL;
    }
    l->ops = ops;
    l->fd = fd;
    snprintf(l->endpoint, sizeof l->endpoint, "%s", name);
    return l;
}

int uwb_link_time_left(long long deadline, int timeout_ms)
{
    if (timeout_ms < 0)
        return -1;
    long long left = deadline - uwb_monotonic_ms();
    return left < 0 ? 0 : (int)left;
}

int uwb_link_open(const char *endpoint, struct uwb_link **link, char *err, size_t errlen)
{
    *link = NULL;
    struct uwb_endpoint ep;
    int rc = uwb_endpoint_parse(endpoint, &ep, err, errlen);
    if (rc != UWB_LINK_OK)
        return rc;
    struct uwb_link *l = uwb_link_new(ops_for(ep.kind), endpoint, -1, err, errlen);
    if (!l)
        return UWB_LINK_ERR_OPEN;
    rc = l->ops->open(l, &ep, err, errlen);
    if (rc != UWB_LINK_OK) {
        free(l);
        return rc;
    }
    *link = l;
    return UWB_LINK_OK;
}

ssize_t uwb_link_read(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err, size_t errlen)
{
    return link->ops->read(link, buf, len, timeout_ms, err, errlen);
}

int uwb_link_read_exact(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err,
                        size_t errlen)
{
    /* One deadline for the whole read, not one per chunk. */
    long long deadline = uwb_monotonic_ms() + timeout_ms;
    size_t got = 0;
    while (got < len) {
        ssize_t n = link->ops->read(link, (char *)buf + got, len - got,
                                    uwb_link_time_left(deadline, timeout_ms), err, errlen);
        if (n < 0) {
            if (n == UWB_LINK_ERR_TIMEOUT)
                snprintf(err, errlen, "%s: timed out after %d ms with %zu of %zu bytes", link->endpoint,
                         timeout_ms, got, len);
            return (int)n;
        }
        got += (size_t)n;
    }
    return UWB_LINK_OK;
}

int uwb_link_write_all(struct uwb_link *link, const void *buf, size_t len, int timeout_ms, char *err,
                       size_t errlen)
{
    return link->ops->write_all(link, buf, len, timeout_ms, err, errlen);
}

int uwb_link_fd(struct uwb_link *link)
{
    return link->ops->fd(link);
}

const char *uwb_link_name(const struct uwb_link *link)
{
    return link->endpoint;
}

void uwb_link_close(struct uwb_link *link)
{
    if (!link)
        return;
    link->ops->close(link);
    free(link);
}
