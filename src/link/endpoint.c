/* Endpoint strings taken apart, without any I/O, so that a typo in the
 * config is reported before anything is opened. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/un.h>

#include "uwb/link.h"

/* Baud rates above this are not UARTs any more; a typo more likely. */
#define MAX_BAUD 20000000L

static int bad(const char *text, char *err, size_t errlen, const char *problem)
{
    snprintf(err, errlen,
             "endpoint '%s': %s (expected serial:/dev/ttyX[?baud=N&parity=none|even|odd&stopbits=1|2], "
             "tcp:HOST:PORT or unix:PATH)",
             text, problem);
    return UWB_LINK_ERR_ENDPOINT;
}

static int copy_text(char *dst, size_t dstlen, const char *src, size_t len)
{
    if (len >= dstlen)
        return -1;
    memcpy(dst, src, len);
    dst[len] = '\0';
    return 0;
}

static int parse_unix(const char *text, const char *rest, struct uwb_endpoint *ep, char *err, size_t errlen)
{
    struct sockaddr_un sun;
    size_t len = strlen(rest);
    if (len == 0)
        return bad(text, err, errlen, "unix: needs a socket path");
    if (len >= sizeof sun.sun_path) {
        char problem[96];
        snprintf(problem, sizeof problem, "socket path longer than %zu bytes", sizeof sun.sun_path - 1);
        return bad(text, err, errlen, problem);
    }
    ep->kind = UWB_ENDPOINT_UNIX;
    return copy_text(ep->path, sizeof ep->path, rest, len) == 0 ? UWB_LINK_OK
                                                                : bad(text, err, errlen, "path too long");
}

static int parse_tcp(const char *text, const char *rest, struct uwb_endpoint *ep, char *err, size_t errlen)
{
    const char *host = rest, *colon;
    size_t hostlen;
    if (rest[0] == '[') { /* [IPv6]:PORT */
        const char *close = strchr(rest, ']');
        if (!close)
            return bad(text, err, errlen, "IPv6 address without its closing ']'");
        if (close[1] != ':')
            return bad(text, err, errlen, "tcp: needs ':PORT' after the host");
        host = rest + 1;
        hostlen = (size_t)(close - host);
        colon = close + 1;
    } else {
        colon = strrchr(rest, ':');
        if (!colon)
            return bad(text, err, errlen, "tcp: needs HOST:PORT");
        hostlen = (size_t)(colon - rest);
        if (memchr(rest, ':', hostlen))
            return bad(text, err, errlen, "an IPv6 host must be written in [brackets]");
    }
    if (hostlen == 0)
        return bad(text, err, errlen, "tcp: host is empty");
    const char *port = colon + 1;
    if (!*port)
        return bad(text, err, errlen, "tcp: port is empty");
    char *end;
    errno = 0;
    long number = strtol(port, &end, 10);
    if (*end || errno || port[0] == '-' || port[0] == '+' || number < 1 || number > 65535)
        return bad(text, err, errlen, "tcp: port must be a number from 1 to 65535");
    ep->kind = UWB_ENDPOINT_TCP;
    if (copy_text(ep->host, sizeof ep->host, host, hostlen) != 0)
        return bad(text, err, errlen, "host too long");
    snprintf(ep->port, sizeof ep->port, "%ld", number);
    return UWB_LINK_OK;
}

#define SERIAL_OPTIONS "baud=N, parity=none|even|odd, stopbits=1|2"

/* One serial option, NAME=VALUE, len bytes at opt; `seen` has a bit per
 * option already given. */
static int parse_serial_option(const char *text, const char *opt, size_t len, unsigned *seen,
                               struct uwb_endpoint *ep, char *err, size_t errlen)
{
    static const char *const names[] = {"baud", "parity", "stopbits"};
    char option[64], problem[160];
    if (len == 0)
        return bad(text, err, errlen, "empty serial option (separate them with one '&')");
    if (len >= sizeof option) {
        snprintf(problem, sizeof problem, "unknown serial option '%.40s...' (" SERIAL_OPTIONS ")", opt);
        return bad(text, err, errlen, problem);
    }
    memcpy(option, opt, len);
    option[len] = '\0';
    char *value = strchr(option, '=');
    size_t which = sizeof names / sizeof names[0];
    if (value) {
        *value++ = '\0';
        for (which = 0; which < sizeof names / sizeof names[0]; which++)
            if (strcmp(option, names[which]) == 0)
                break;
    }
    if (which == sizeof names / sizeof names[0]) {
        snprintf(problem, sizeof problem, "unknown serial option '%.*s' (" SERIAL_OPTIONS ")", (int)len, opt);
        return bad(text, err, errlen, problem);
    }
    if (*seen & (1u << which)) {
        snprintf(problem, sizeof problem, "%s given twice", names[which]);
        return bad(text, err, errlen, problem);
    }
    *seen |= 1u << which;
    if (which == 0) {
        char *end;
        errno = 0;
        long baud = strtol(value, &end, 10);
        if (!*value || *end || errno || value[0] == '-' || value[0] == '+' || baud < 1 || baud > MAX_BAUD)
            return bad(text, err, errlen, "baud must be a positive number of bits per second");
        ep->baud = (int)baud;
    } else if (which == 1) {
        if (strcmp(value, "none") == 0)
            ep->parity = 'N';
        else if (strcmp(value, "even") == 0)
            ep->parity = 'E';
        else if (strcmp(value, "odd") == 0)
            ep->parity = 'O';
        else
            return bad(text, err, errlen, "parity must be none, even or odd");
    } else {
        if (strcmp(value, "1") != 0 && strcmp(value, "2") != 0)
            return bad(text, err, errlen, "stopbits must be 1 or 2");
        ep->stop_bits = value[0] - '0';
    }
    return UWB_LINK_OK;
}

/* serial:PATH[?OPTION&...]: baud=N, parity=none|even|odd, stopbits=1|2;
 * 8 data bits always. Without them, UWB_SERIAL_DEFAULT_BAUD 8N1. */
static int parse_serial(const char *text, const char *rest, struct uwb_endpoint *ep, char *err, size_t errlen)
{
    const char *query = strchr(rest, '?');
    size_t pathlen = query ? (size_t)(query - rest) : strlen(rest);
    if (pathlen == 0)
        return bad(text, err, errlen, "serial: needs a device path");
    ep->kind = UWB_ENDPOINT_SERIAL;
    ep->baud = UWB_SERIAL_DEFAULT_BAUD;
    ep->parity = 'N';
    ep->stop_bits = 1;
    if (copy_text(ep->path, sizeof ep->path, rest, pathlen) != 0)
        return bad(text, err, errlen, "device path too long");
    if (!query)
        return UWB_LINK_OK;
    unsigned seen = 0;
    for (const char *opt = query + 1;;) {
        size_t len = strcspn(opt, "&");
        int rc = parse_serial_option(text, opt, len, &seen, ep, err, errlen);
        if (rc != UWB_LINK_OK)
            return rc;
        if (!opt[len])
            return UWB_LINK_OK;
        opt += len + 1;
    }
}

int uwb_endpoint_parse(const char *text, struct uwb_endpoint *ep, char *err, size_t errlen)
{
    memset(ep, 0, sizeof *ep);
    if (!text || !*text)
        return bad(text ? text : "", err, errlen, "empty");
    if (strncmp(text, "unix:", 5) == 0)
        return parse_unix(text, text + 5, ep, err, errlen);
    if (strncmp(text, "tcp:", 4) == 0)
        return parse_tcp(text, text + 4, ep, err, errlen);
    if (strncmp(text, "serial:", 7) == 0)
        return parse_serial(text, text + 7, ep, err, errlen);
    const char *colon = strchr(text, ':');
    char problem[96];
    if (colon)
        snprintf(problem, sizeof problem, "unknown scheme '%.*s'",
                 (int)(colon - text > 32 ? 32 : colon - text), text);
    else
        snprintf(problem, sizeof problem, "no scheme");
    return bad(text, err, errlen, problem);
}
