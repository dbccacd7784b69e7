/* The Modbus server (libmodbus): RTU on a serial line (RS-485) or, for the
 * tests, over a unix socket it connects to, or Modbus TCP listening on an
 * address. It lives in the daemon's poll() loop: it hands out its fds,
 * serves what polled readable, and asks the daemon for the registers just
 * before each reply, so a master never reads a stale verdict. */
#ifndef UWBD_INTEGRATIONS_MODBUS_SERVER_H
#define UWBD_INTEGRATIONS_MODBUS_SERVER_H

#include <poll.h>
#include <stddef.h>
#include <stdint.h>

#include "integrations/modbus_registers.h"

/* TCP masters at once; a fifth evicts the one idle longest (2 s or more),
 * else it is refused (closed on accept). */
#define UWBD_MODBUS_TCP_CLIENTS 4
/* A TCP master with nothing pending for this long is closed (the default
 * of modbus.idle_timeout_s). */
#define UWBD_MODBUS_IDLE_TIMEOUT_S 60.0
#define UWBD_MODBUS_POLL_FDS (1 + UWBD_MODBUS_TCP_CLIENTS)

struct uwbd_modbus_handlers {
    void *ctx;
    /* The registers now (the map in modbus_registers.h). */
    void (*fill)(void *ctx, uint16_t regs[UWBD_MODBUS_REGISTER_COUNT]);
    /* A coil written 1: the command for it. 0 = done; -1 = cannot (the
     * master gets exception 4, server device failure). NULL: the coil is
     * not wired (exception 2, illegal data address). */
    int (*coil[UWBD_MODBUS_COIL_COUNT])(void *ctx);
};

struct uwbd_modbus_server;

/* endpoint: serial:/dev/ttyX[?baud=N&parity=P&stopbits=S] or unix:PATH
 * (RTU; uwbd connects, and connects again every few seconds after the peer went away), or
 * tcp:HOST:PORT (Modbus TCP, listening). unit_id: the RTU address (1-247).
 * 0, or -1 with err naming the endpoint and the problem, or libmodbus when
 * it cannot be loaded. A serial or unix endpoint that cannot be opened yet
 * is not an error: it is retried. */
int uwbd_modbus_server_open(const char *endpoint, int unit_id, const struct uwbd_modbus_handlers *handlers,
                            struct uwbd_modbus_server **out, char *err, size_t errlen);
/* TCP: close a master with nothing pending for `seconds` (> 0; else unchanged). */
void uwbd_modbus_server_set_idle_timeout(struct uwbd_modbus_server *s, double seconds);
/* The fds to poll (at most UWBD_MODBUS_POLL_FDS) into fds; returns the count. */
int uwbd_modbus_server_poll_fds(struct uwbd_modbus_server *s, struct pollfd *fds, int max);
/* After poll(): fds/n as poll_fds filled them. Also opens a lost RTU link
 * again once its retry time came. */
void uwbd_modbus_server_serve(struct uwbd_modbus_server *s, const struct pollfd *fds, int n);
/* serve() in two halves, for a loop that calls back per fd: one fd that
 * polled ready, then (after every poll) the masters' deadlines and the RTU
 * link's retry. */
void uwbd_modbus_server_serve_fd(struct uwbd_modbus_server *s, int fd);
void uwbd_modbus_server_tick(struct uwbd_modbus_server *s);
/* Milliseconds until the server needs serve() without any fd (a retry, a
 * master's deadline); -1: never. */
int uwbd_modbus_server_timeout_ms(const struct uwbd_modbus_server *s);
/* NULL is a no-op. */
void uwbd_modbus_server_close(struct uwbd_modbus_server *s);

#endif
