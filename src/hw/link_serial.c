/* serial:/dev/ttyX?baud=N&parity=P&stopbits=S through libserialport: 8
 * data bits, the endpoint's parity (none unless given) and stop bits (1
 * unless given), no flow control (a digitiser's UART, a USB bridge, an
 * RS-485 Modbus line). */
#include <errno.h>
#include <libserialport.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "link/link_backend.h"

/* libserialport's message for the last SP_ERR_FAIL, else a fixed text. */
static void describe(enum sp_return rc, char *buf, size_t buflen)
{
    if (rc == SP_ERR_FAIL) {
        char *msg = sp_last_error_message();
        snprintf(buf, buflen, "%s", msg ? msg : "system error");
        sp_free_error_message(msg);
    } else if (rc == SP_ERR_ARG) {
        snprintf(buf, buflen, "not a serial port libserialport can use");
    } else if (rc == SP_ERR_MEM) {
        snprintf(buf, buflen, "out of memory");
    } else if (rc == SP_ERR_SUPP) {
        snprintf(buf, buflen, "not supported on this port");
    } else {
        snprintf(buf, buflen, "error %d", (int)rc);
    }
}

static int serial_open(struct uwb_link *link, const struct uwb_endpoint *ep, char *err, size_t errlen)
{
    /* libserialport says only "invalid argument" for a missing device;
     * the engineer needs to hear that the device is not there. */
    struct stat st;
    if (stat(ep->path, &st) != 0) {
        snprintf(err, errlen, "%s: serial port %s: %s", link->endpoint, ep->path, strerror(errno));
        return UWB_LINK_ERR_OPEN;
    }
    struct sp_port *port = NULL;
    char why[256];
    enum sp_return sp = sp_get_port_by_name(ep->path, &port);
    if (sp != SP_OK) {
        describe(sp, why, sizeof why);
        snprintf(err, errlen, "%s: serial port %s: %s", link->endpoint, ep->path, why);
        return UWB_LINK_ERR_OPEN;
    }
    const char *step = "open";
    enum sp_parity parity = ep->parity == 'E'   ? SP_PARITY_EVEN
                            : ep->parity == 'O' ? SP_PARITY_ODD
                                                : SP_PARITY_NONE;
    const char *set_parity = parity == SP_PARITY_EVEN  ? "set even parity"
                             : parity == SP_PARITY_ODD ? "set odd parity"
                                                       : "set no parity";
    int stop_bits = ep->stop_bits == 2 ? 2 : 1;
    sp = sp_open(port, SP_MODE_READ_WRITE);
    if (sp == SP_OK && (step = "set baud rate", sp = sp_set_baudrate(port, ep->baud)) == SP_OK &&
        (step = "set 8 data bits", sp = sp_set_bits(port, 8)) == SP_OK &&
        (step = set_parity, sp = sp_set_parity(port, parity)) == SP_OK &&
        (step = stop_bits == 2 ? "set 2 stop bits" : "set 1 stop bit",
         sp = sp_set_stopbits(port, stop_bits)) == SP_OK &&
        (step = "turn off flow control", sp = sp_set_flowcontrol(port, SP_FLOWCONTROL_NONE)) == SP_OK) {
        link->port = port;
        return UWB_LINK_OK;
    }
    describe(sp, why, sizeof why);
    snprintf(err, errlen, "%s: serial port %s: cannot %s: %s", link->endpoint, ep->path, step, why);
    sp_close(port);
    sp_free_port(port);
    return UWB_LINK_ERR_OPEN;
}

static ssize_t serial_read(struct uwb_link *link, void *buf, size_t len, int timeout_ms, char *err,
                           size_t errlen)
{
    /* libserialport's timeout 0 means "wait for ever". */
    int n;
    if (timeout_ms == 0)
        n = sp_nonblocking_read(link->port, buf, len);
    else
        n = sp_blocking_read_next(link->port, buf, len, timeout_ms < 0 ? 0 : (unsigned)timeout_ms);
    if (n > 0)
        return n;
    if (n == 0) {
        snprintf(err, errlen, "%s: no data within %d ms", link->endpoint, timeout_ms);
        return UWB_LINK_ERR_TIMEOUT;
    }
    char why[256];
    describe(n, why, sizeof why);
    snprintf(err, errlen, "%s: read: %s", link->endpoint, why);
    return UWB_LINK_ERR_IO;
}

static int serial_write_all(struct uwb_link *link, const void *buf, size_t len, int timeout_ms, char *err,
                            size_t errlen)
{
    int n =
        sp_blocking_write(link->port, buf, len, timeout_ms < 0 ? 0 : (unsigned)(timeout_ms ? timeout_ms : 1));
    if (n >= 0 && (size_t)n == len)
        return UWB_LINK_OK;
    if (n >= 0) {
        snprintf(err, errlen, "%s: only %d of %zu bytes written within %d ms", link->endpoint, n, len,
                 timeout_ms);
        return UWB_LINK_ERR_TIMEOUT;
    }
    char why[256];
    describe(n, why, sizeof why);
    snprintf(err, errlen, "%s: write: %s", link->endpoint, why);
    return UWB_LINK_ERR_IO;
}

static int serial_fd(struct uwb_link *link)
{
    int fd = -1;
    if (sp_get_port_handle(link->port, &fd) != SP_OK)
        return -1;
    return fd;
}

static void serial_close(struct uwb_link *link)
{
    if (link->port) {
        sp_close(link->port);
        sp_free_port(link->port);
    }
    link->port = NULL;
}

const struct uwb_link_ops uwb_link_serial_ops = {
    .open = serial_open,
    .read = serial_read,
    .write_all = serial_write_all,
    .fd = serial_fd,
    .close = serial_close,
};
