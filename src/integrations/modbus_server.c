/* The Modbus server on libmodbus (see modbus_server.h). RTU over a link:
 * the RTU context is made with modbus_new_rtu but never connected;
 * modbus_set_socket gives it the link's fd (libserialport's tty, or a unix
 * socket in the tests), and libmodbus's RTU backend reads and writes that
 * fd. TCP: modbus_tcp_pi_listen, then one context serving each accepted
 * socket in turn through modbus_set_socket. */
#include "integrations/modbus_server.h"

#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "util/log.h"
#include "integrations/modbus_loader.h"
#include "uwb/link.h"
#include "uwb/monotonic.h"

/* A lost RTU link (the peer of a unix: endpoint went away, the USB adapter
 * was unplugged) is opened again after this. */
#define RETRY_S 5.0
/* RTU: a master that starts a request must finish it within this, and
 * its bytes come at most this far apart (libmodbus's indication and byte
 * timeouts; on a bus they are milliseconds apart). The loop waits for an
 * RTU frame at most a few seconds, and only for someone on the bus. */
#define REQUEST_TIMEOUT_US 500000
#define BYTE_TIMEOUT_US 50000
/* TCP: a request is gathered without blocking, frame by frame (its MBAP
 * header gives its length); one not complete within this drops its
 * connection. The loop never waits for a TCP master. */
#define TCP_FRAME_S 2.0
#define MBAP_HEADER 7
/* With every slot taken, a new master evicts the one idle longest, if it
 * has been idle at least this long (so four busy masters are not churned). */
#define TCP_EVICT_IDLE_S 2.0
/* TCP keepalive on accepted sockets: a master that vanished (a reboot, a
 * cut cable) leaves a half-open socket that is found dead after
 * KEEPIDLE + KEEPCNT x KEEPINTVL = 2 minutes, even within the idle timeout. */
#define TCP_KEEPIDLE_S 60
#define TCP_KEEPINTVL_S 10
#define TCP_KEEPCNT 6

/* Function codes that write registers: the map is read-only. */
#define FC_WRITE_SINGLE_COIL 0x05
#define FC_WRITE_SINGLE_REGISTER 0x06
#define FC_WRITE_MULTIPLE_COILS 0x0F
#define FC_WRITE_MULTIPLE_REGISTERS 0x10
#define FC_MASK_WRITE_REGISTER 0x16
#define FC_WRITE_AND_READ_REGISTERS 0x17

struct uwbd_modbus_server {
    const struct uwbd_modbus_api *lib; /* libmodbus, loaded (modbus_loader.h) */
    char endpoint[UWB_ENDPOINT_MAX];
    struct uwb_endpoint ep;
    int unit_id;
    struct uwbd_modbus_handlers h;
    modbus_mapping_t *map;
    double idle_timeout_s; /* a TCP master with nothing pending this long is closed */

    /* RTU */
    modbus_t *rtu;
    struct uwb_link *link; /* NULL while closed */
    double retry_at_s;     /* CLOCK_MONOTONIC of the next open attempt */
    int failing;           /* log an outage once, not every retry */

    /* TCP */
    modbus_t *tcp;
    int listen_fd;
    struct tcp_client {
        int fd; /* -1: free */
        uint8_t frame[MODBUS_TCP_MAX_ADU_LENGTH];
        int len;          /* bytes of the current request so far */
        double started_s; /* CLOCK_MONOTONIC of its first byte */
        double active_s;  /* CLOCK_MONOTONIC of its connection or last byte */
    } clients[UWBD_MODBUS_TCP_CLIENTS];
};

static void rtu_try_open(struct uwbd_modbus_server *s)
{
    char err[512];
    if (uwb_link_open(s->endpoint, &s->link, err, sizeof err) != UWB_LINK_OK) {
        s->link = NULL;
        s->retry_at_s = uwb_monotonic_s() + RETRY_S;
        if (!s->failing)
            uwbd_log(UWBD_LOG_WARNING, "modbus: %s; trying again every %.0f s", err, RETRY_S);
        s->failing = 1;
        return;
    }
    s->lib->set_socket(s->rtu, uwb_link_fd(s->link));
    uwbd_log(UWBD_LOG_INFO, "modbus: RTU unit %d on %s", s->unit_id, s->endpoint);
    s->failing = 0;
}

static void rtu_lost(struct uwbd_modbus_server *s, const char *why)
{
    uwbd_log(UWBD_LOG_WARNING, "modbus: %s: %s; opening it again in %.0f s", s->endpoint, why, RETRY_S);
    s->lib->set_socket(s->rtu, -1);
    uwb_link_close(s->link);
    s->link = NULL;
    s->retry_at_s = uwb_monotonic_s() + RETRY_S;
}

static modbus_t *set_up(const struct uwbd_modbus_server *s, modbus_t *ctx, int unit_id)
{
    if (!ctx)
        return NULL;
    s->lib->set_slave(ctx, unit_id);
    s->lib->set_indication_timeout(ctx, 0, REQUEST_TIMEOUT_US);
    s->lib->set_byte_timeout(ctx, 0, BYTE_TIMEOUT_US);
    return ctx;
}

/* Acquires all or none: the endpoint and the library are checked before
 * anything is held, and from the server's allocation on every failure goes
 * to `fail`, where close() releases whatever was acquired so far. */
int uwbd_modbus_server_open(const char *endpoint, int unit_id, const struct uwbd_modbus_handlers *handlers,
                            struct uwbd_modbus_server **out, char *err, size_t errlen)
{
    *out = NULL;
    struct uwb_endpoint ep;
    char why[512];
    if (uwb_endpoint_parse(endpoint, &ep, why, sizeof why) != UWB_LINK_OK) {
        snprintf(err, errlen, "modbus.endpoint: %s", why);
        return -1;
    }
    const struct uwbd_modbus_api *lib = uwbd_modbus_load(err, errlen);
    if (!lib)
        return -1;
    struct uwbd_modbus_server *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "modbus: out of memory");
        return -1;
    }
    s->lib = lib;
    s->ep = ep;
    s->listen_fd = -1;
    s->idle_timeout_s = UWBD_MODBUS_IDLE_TIMEOUT_S;
    for (int i = 0; i < UWBD_MODBUS_TCP_CLIENTS; i++)
        s->clients[i].fd = -1;
    s->unit_id = unit_id;
    s->h = *handlers;
    snprintf(s->endpoint, sizeof s->endpoint, "%s", endpoint);
    s->map = s->lib->mapping_new(UWBD_MODBUS_COIL_COUNT, 0, UWBD_MODBUS_REGISTER_COUNT,
                                 UWBD_MODBUS_REGISTER_COUNT);
    if (!s->map) {
        snprintf(err, errlen, "modbus: out of memory for the register map");
        goto fail;
    }
    if (s->ep.kind == UWB_ENDPOINT_TCP) {
        s->tcp = set_up(s, s->lib->new_tcp_pi(s->ep.host, s->ep.port), unit_id);
        if (!s->tcp || (s->listen_fd = s->lib->tcp_pi_listen(s->tcp, UWBD_MODBUS_TCP_CLIENTS)) < 0) {
            snprintf(err, errlen, "modbus: cannot listen on %s: %s", endpoint, s->lib->strerror(errno));
            goto fail;
        }
        uwbd_log(UWBD_LOG_INFO, "modbus: TCP listening on %s", endpoint);
    } else {
        /* The line's framing is the link's (src/hw/link_serial.c sets the
         * tty); libmodbus is told the same, for its timing. unix: is 8N1. */
        int serial = s->ep.kind == UWB_ENDPOINT_SERIAL;
        s->rtu = set_up(s,
                        s->lib->new_rtu(s->ep.path, s->ep.baud > 0 ? s->ep.baud : UWB_SERIAL_DEFAULT_BAUD,
                                        serial ? s->ep.parity : 'N', 8, serial ? s->ep.stop_bits : 1),
                        unit_id);
        if (!s->rtu) {
            snprintf(err, errlen, "modbus: RTU context for %s: %s", endpoint, s->lib->strerror(errno));
            goto fail;
        }
        rtu_try_open(s); /* a link not there yet is tried again, not an error */
    }
    *out = s;
    return 0;
fail:
    uwbd_modbus_server_close(s);
    return -1;
}

void uwbd_modbus_server_set_idle_timeout(struct uwbd_modbus_server *s, double seconds)
{
    if (seconds > 0)
        s->idle_timeout_s = seconds;
}

int uwbd_modbus_server_poll_fds(struct uwbd_modbus_server *s, struct pollfd *fds, int max)
{
    int n = 0;
    if (s->link && n < max)
        fds[n++] = (struct pollfd){.fd = uwb_link_fd(s->link), .events = POLLIN};
    if (s->listen_fd >= 0 && n < max)
        fds[n++] = (struct pollfd){.fd = s->listen_fd, .events = POLLIN};
    for (int i = 0; i < UWBD_MODBUS_TCP_CLIENTS && n < max; i++)
        if (s->clients[i].fd >= 0)
            fds[n++] = (struct pollfd){.fd = s->clients[i].fd, .events = POLLIN};
    return n;
}

static int ms_until(double when_s)
{
    double left_s = when_s - uwb_monotonic_s();
    return left_s <= 0 ? 0 : (int)(left_s * 1000.0) + 1;
}

int uwbd_modbus_server_timeout_ms(const struct uwbd_modbus_server *s)
{
    int ms = -1;
    if (s->rtu && !s->link)
        ms = ms_until(s->retry_at_s);
    for (int i = 0; i < UWBD_MODBUS_TCP_CLIENTS; i++) {
        if (s->clients[i].fd < 0)
            continue;
        int left = s->clients[i].len ? ms_until(s->clients[i].started_s + TCP_FRAME_S)
                                     : ms_until(s->clients[i].active_s + s->idle_timeout_s);
        if (ms < 0 || left < ms)
            ms = left;
    }
    return ms;
}

static int coil_wired(const struct uwbd_modbus_server *s, int first, int count)
{
    for (int c = first; c < first + count; c++)
        if (c >= 0 && c < UWBD_MODBUS_COIL_COUNT && !s->h.coil[c])
            return 0;
    return 1;
}

/* Coil writes run their commands before the reply, so that the reply says
 * whether the command was taken; a write of 0 does nothing. Returns 0, or
 * the Modbus exception to answer. */
static int run_coils(struct uwbd_modbus_server *s, const uint8_t *pdu, int pdu_len)
{
    int function = pdu[0];
    if (pdu_len < 5)
        return 0; /* malformed: modbus_reply answers it */
    int address = (pdu[1] << 8) | pdu[2];
    int set[UWBD_MODBUS_COIL_COUNT] = {0};
    if (function == FC_WRITE_SINGLE_COIL) {
        if (!coil_wired(s, address, 1))
            return address < UWBD_MODBUS_COIL_COUNT ? MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS : 0;
        if (address < UWBD_MODBUS_COIL_COUNT && pdu[3] == 0xFF && pdu[4] == 0x00)
            set[address] = 1;
    } else {
        int count = (pdu[3] << 8) | pdu[4];
        if (address + count > UWBD_MODBUS_COIL_COUNT || pdu_len < 6 || pdu_len < 6 + pdu[5])
            return 0; /* out of the map or malformed: modbus_reply answers it */
        if (!coil_wired(s, address, count))
            return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
        for (int i = 0; i < count; i++)
            set[address + i] = (pdu[6 + i / 8] >> (i % 8)) & 1;
    }
    for (int c = 0; c < UWBD_MODBUS_COIL_COUNT; c++)
        if (set[c] && s->h.coil[c](s->h.ctx) != 0)
            return MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE;
    return 0;
}

/* Answers one whole request (query, len bytes, as libmodbus frames it)
 * on ctx, its socket set: -1 when the connection is gone. */
static int answer(struct uwbd_modbus_server *s, modbus_t *ctx, const uint8_t *query, int len)
{
    int header = s->lib->get_header_length(ctx);
    if (len <= header)
        return 0;
    const uint8_t *pdu = query + header;
    int pdu_len = len - header - (ctx == s->rtu ? 2 : 0); /* RTU's CRC */
    int function = pdu[0];
    int exception = 0;
    if (function == FC_WRITE_SINGLE_REGISTER || function == FC_WRITE_MULTIPLE_REGISTERS ||
        function == FC_MASK_WRITE_REGISTER || function == FC_WRITE_AND_READ_REGISTERS)
        exception = MODBUS_EXCEPTION_ILLEGAL_FUNCTION; /* the registers are read-only */
    else if (function == FC_WRITE_SINGLE_COIL || function == FC_WRITE_MULTIPLE_COILS)
        exception = run_coils(s, pdu, pdu_len);
    int rc;
    if (exception) {
        rc = s->lib->reply_exception(ctx, query, (unsigned)exception);
    } else {
        uint16_t regs[UWBD_MODBUS_REGISTER_COUNT];
        s->h.fill(s->h.ctx, regs);
        memcpy(s->map->tab_input_registers, regs, sizeof regs);
        memcpy(s->map->tab_registers, regs, sizeof regs);
        rc = s->lib->reply(ctx, query, len, s->map);
        memset(s->map->tab_bits, 0, UWBD_MODBUS_COIL_COUNT); /* coils are momentary */
    }
    if (rc < 0 && ctx == s->tcp)
        return -1; /* a master that does not take its reply (EAGAIN) or went away */
    if (rc < 0 && (errno == EPIPE || errno == ECONNRESET || errno == EBADF || errno == EIO))
        return -1;
    return 0;
}

/* One RTU request from the link: -1 when the link is gone. */
static int serve_rtu(struct uwbd_modbus_server *s)
{
    uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
    int len = s->lib->receive(s->rtu, query);
    if (len == 0)
        return 0; /* a request for another unit on the bus */
    if (len < 0) {
        if (errno == ECONNRESET || errno == EPIPE || errno == EBADF || errno == EIO || errno == ENOTCONN)
            return -1;
        s->lib->flush(s->rtu); /* a bad CRC or a half frame: wait for the next */
        return 0;
    }
    return answer(s, s->rtu, query, len);
}

/* What a TCP master sent, gathered without blocking; a whole request is
 * answered. -1: drop the connection (closed, not Modbus, or an error). */
static int serve_tcp(struct uwbd_modbus_server *s, struct tcp_client *c)
{
    int want = c->len < MBAP_HEADER ? MBAP_HEADER : 6 + ((c->frame[4] << 8) | c->frame[5]);
    ssize_t n = recv(c->fd, c->frame + c->len, (size_t)(want - c->len), MSG_DONTWAIT);
    if (n == 0)
        return -1;
    if (n < 0)
        return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : -1;
    c->active_s = uwb_monotonic_s();
    if (c->len == 0)
        c->started_s = c->active_s;
    c->len += (int)n;
    if (c->len == MBAP_HEADER) {
        int length = (c->frame[4] << 8) | c->frame[5];
        /* protocol id 0; unit id and at least a function code; within an ADU */
        if (c->frame[2] || c->frame[3] || length < 2 || 6 + length > MODBUS_TCP_MAX_ADU_LENGTH)
            return -1;
        want = 6 + length;
    }
    if (c->len < want || c->len < MBAP_HEADER)
        return 0;
    int len = c->len;
    c->len = 0;
    s->lib->set_socket(s->tcp, c->fd);
    int rc = answer(s, s->tcp, c->frame, len);
    s->lib->set_socket(s->tcp, -1);
    return rc;
}

static void drop_client(struct tcp_client *c)
{
    close(c->fd);
    c->fd = -1;
    c->len = 0;
}

/* Keepalive probes on an accepted socket; a failure only loses the early
 * detection (the idle timeout still closes it), so it is logged, not fatal. */
static void keep_alive(int fd)
{
    int on = 1, idle = TCP_KEEPIDLE_S, interval = TCP_KEEPINTVL_S, count = TCP_KEEPCNT;
    if (setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &on, sizeof on) != 0 ||
        setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &idle, sizeof idle) != 0 ||
        setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &interval, sizeof interval) != 0 ||
        setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &count, sizeof count) != 0)
        uwbd_log(UWBD_LOG_WARNING, "modbus: TCP keepalive on a master's socket: %s", strerror(errno));
}

/* The master idle longest (nothing pending), if it has been idle
 * TCP_EVICT_IDLE_S or more; NULL when every master is busy. */
static struct tcp_client *longest_idle(struct uwbd_modbus_server *s, double now_s)
{
    struct tcp_client *oldest = NULL;
    for (int i = 0; i < UWBD_MODBUS_TCP_CLIENTS; i++) {
        struct tcp_client *c = &s->clients[i];
        if (c->fd < 0 || c->len > 0 || now_s - c->active_s < TCP_EVICT_IDLE_S)
            continue;
        if (!oldest || c->active_s < oldest->active_s)
            oldest = c;
    }
    return oldest;
}

static void accept_client(struct uwbd_modbus_server *s)
{
    int fd = accept(s->listen_fd, NULL, NULL);
    if (fd < 0)
        return;
    fcntl(fd, F_SETFD, FD_CLOEXEC); /* accept4 is a GNU extension */
    /* Replies are sent without blocking too: a master that does not read
     * them is dropped when its socket's buffer is full. */
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    keep_alive(fd);
    double now_s = uwb_monotonic_s();
    struct tcp_client *slot = NULL;
    for (int i = 0; i < UWBD_MODBUS_TCP_CLIENTS && !slot; i++)
        if (s->clients[i].fd < 0)
            slot = &s->clients[i];
    if (!slot && (slot = longest_idle(s, now_s)) != NULL) {
        uwbd_log(UWBD_LOG_NOTICE,
                 "modbus: %d TCP masters connected; dropping one idle for %.0f s for a new one",
                 UWBD_MODBUS_TCP_CLIENTS, now_s - slot->active_s);
        drop_client(slot);
    }
    if (!slot) {
        uwbd_log(UWBD_LOG_WARNING,
                 "modbus: a TCP master refused: %d already connected, each busy within %.0f s",
                 UWBD_MODBUS_TCP_CLIENTS, TCP_EVICT_IDLE_S);
        close(fd);
        return;
    }
    slot->fd = fd;
    slot->len = 0;
    slot->active_s = now_s;
}

void uwbd_modbus_server_serve_fd(struct uwbd_modbus_server *s, int fd)
{
    if (s->link && fd == uwb_link_fd(s->link)) {
        if (serve_rtu(s) < 0)
            rtu_lost(s, "the link closed");
        return;
    }
    if (fd == s->listen_fd) {
        accept_client(s);
        return;
    }
    for (int c = 0; c < UWBD_MODBUS_TCP_CLIENTS; c++)
        if (s->clients[c].fd == fd && serve_tcp(s, &s->clients[c]) < 0)
            drop_client(&s->clients[c]);
}

void uwbd_modbus_server_tick(struct uwbd_modbus_server *s)
{
    double now_s = uwb_monotonic_s();
    for (int c = 0; c < UWBD_MODBUS_TCP_CLIENTS; c++) {
        if (s->clients[c].fd < 0)
            continue;
        if (s->clients[c].len > 0 && now_s - s->clients[c].started_s >= TCP_FRAME_S) {
            uwbd_log(UWBD_LOG_WARNING, "modbus: a TCP master dropped: no whole request within %.0f s",
                     TCP_FRAME_S);
            drop_client(&s->clients[c]);
        } else if (s->clients[c].len == 0 && now_s - s->clients[c].active_s >= s->idle_timeout_s) {
            uwbd_log(UWBD_LOG_INFO, "modbus: a TCP master dropped: idle for %g s (modbus.idle_timeout_s)",
                     s->idle_timeout_s);
            drop_client(&s->clients[c]);
        }
    }
    if (s->rtu && !s->link && uwb_monotonic_s() >= s->retry_at_s)
        rtu_try_open(s);
}

void uwbd_modbus_server_serve(struct uwbd_modbus_server *s, const struct pollfd *fds, int n)
{
    for (int i = 0; i < n; i++)
        if (fds[i].revents)
            uwbd_modbus_server_serve_fd(s, fds[i].fd);
    uwbd_modbus_server_tick(s);
}

void uwbd_modbus_server_close(struct uwbd_modbus_server *s)
{
    if (!s)
        return;
    if (s->rtu) {
        s->lib->set_socket(s->rtu, -1); /* the link owns the fd */
        s->lib->free(s->rtu);
    }
    uwb_link_close(s->link);
    if (s->tcp) {
        s->lib->set_socket(s->tcp, -1);
        s->lib->free(s->tcp);
    }
    if (s->listen_fd >= 0)
        close(s->listen_fd);
    for (int i = 0; i < UWBD_MODBUS_TCP_CLIENTS; i++)
        if (s->clients[i].fd >= 0)
            close(s->clients[i].fd);
    if (s->map)
        s->lib->mapping_free(s->map);
    free(s);
}
