/* The Modbus output module (the server: src/integrations/modbus_server.c):
 * opened at start and on a reload that changes modbus.*, its fds in the
 * event loop, given the registers from the latest verdict and the daemon's
 * state at each request, and its coils turned into commands. */
#include "daemon/output_modbus.h"

#include <poll.h>
#include <string.h>

#include "control/exit_codes.h"
#include "daemon/output_contacts.h"
#include "integrations/modbus_registers.h"
#include "integrations/modbus_server.h"
#include "util/log.h"

static struct uwbd_modbus_server *modbus; /* NULL: Modbus off */
static int fd_id[UWBD_MODBUS_POLL_FDS];   /* the server's fds' entries in the main loop */

int uwbd_modbus_listening(void)
{
    return modbus != NULL;
}

static void fill_registers(void *ctx, uint16_t regs[UWBD_MODBUS_REGISTER_COUNT])
{
    const struct uwbd_daemon_port *port = ctx;
    struct uwbd_modbus_status status;
    port->modbus_status(port->daemon, &status);
    struct uwbd_contact_states contacts;
    uwbd_contact_states(&contacts);
    /* -1: no contacts configured, none energised */
    status.contacts = (contacts.watch == 1 ? UWBD_MODBUS_CONTACT_WATCH : 0u) |
                      (contacts.alarm == 1 ? UWBD_MODBUS_CONTACT_ALARM : 0u) |
                      (contacts.fault == 1 ? UWBD_MODBUS_CONTACT_FAULT : 0u);
    uwbd_modbus_registers_fill(port->latest(port->daemon), &status, regs);
}

/* Coil 1: a scan as soon as the running one ends, as `event` does. */
static int coil_event(void *ctx)
{
    const struct uwbd_daemon_port *port = ctx;
    if (port->stopping(port->daemon))
        return -1;
    uwbd_log(UWBD_LOG_NOTICE, "modbus: event coil: scan requested");
    port->request_event_scan(port->daemon);
    return 0;
}

/* Coil 0: `ack`; a failure (no contacts configured) answers "server failure". */
static int coil_ack(void *ctx)
{
    const struct uwbd_daemon_port *port = ctx;
    char err[160];
    if (port->acknowledge(port->daemon, err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_NOTICE, "modbus: ack coil: %s", err);
        return -1;
    }
    uwbd_log(UWBD_LOG_NOTICE, "modbus: ack coil: latched contacts acknowledged");
    return 0;
}

static int modbus_start(const struct uwbd_daemon_port *port, char *err, size_t errlen)
{
    modbus = NULL;
    if (!port->cfg->modbus.enabled)
        return 0; /* nothing opened */
    struct uwbd_modbus_handlers h = {.ctx = (void *)port, .fill = fill_registers};
    h.coil[UWBD_MODBUS_COIL_EVENT] = coil_event;
    h.coil[UWBD_MODBUS_COIL_ACK] = coil_ack;
    if (uwbd_modbus_server_open(port->cfg->modbus.endpoint, port->cfg->modbus.unit_id, &h, &modbus, err,
                                errlen) != 0)
        return -1;
    uwbd_modbus_server_set_idle_timeout(modbus, port->cfg->modbus.idle_timeout_s);
    return 0;
}

static int modbus_open(const struct uwbd_daemon_port *port)
{
    char err[1024];
    if (modbus_start(port, err, sizeof err) == 0)
        return 0;
    uwbd_log(UWBD_LOG_ERR, "%s", err);
    return UWBD_EXIT_CANT_CREATE;
}

static void modbus_close(const struct uwbd_daemon_port *port)
{
    (void)port;
    uwbd_modbus_server_close(modbus);
    modbus = NULL;
}

static void modbus_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous_cfg)
{
    const struct uwbd_modbus_config *previous = &previous_cfg->modbus;
    const struct uwbd_modbus_config *now = &port->cfg->modbus;
    if (previous->enabled == now->enabled && previous->unit_id == now->unit_id &&
        strcmp(previous->endpoint, now->endpoint) == 0) {
        /* The same server: a new idle timeout applies to the masters connected. */
        if (modbus)
            uwbd_modbus_server_set_idle_timeout(modbus, now->idle_timeout_s);
        return;
    }
    modbus_close(port);
    char err[512];
    if (modbus_start(port, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "reload: %s; Modbus is off until the next reload", err);
}

static void modbus_ready(void *ctx, int fd, short revents)
{
    (void)ctx, (void)revents;
    if (modbus)
        uwbd_modbus_server_serve_fd(modbus, fd);
}

/* The server's fds this round (its TCP masters come and go), the wait
 * bounded by its next retry or master's deadline. */
static int modbus_prepare(void *ctx)
{
    const struct uwbd_daemon_port *port = ctx;
    struct pollfd fds[UWBD_MODBUS_POLL_FDS];
    int n = modbus ? uwbd_modbus_server_poll_fds(modbus, fds, UWBD_MODBUS_POLL_FDS) : 0;
    for (int i = 0; i < UWBD_MODBUS_POLL_FDS; i++)
        uwbd_event_loop_set(port->events, fd_id[i], i < n ? fds[i].fd : -1, POLLIN);
    return modbus ? uwbd_modbus_server_timeout_ms(modbus) : -1;
}

static void modbus_after(void *ctx)
{
    (void)ctx;
    if (modbus)
        uwbd_modbus_server_tick(modbus);
}

static int modbus_watch(const struct uwbd_daemon_port *port, struct uwbd_event_loop *loop)
{
    for (int i = 0; i < UWBD_MODBUS_POLL_FDS; i++)
        if ((fd_id[i] = uwbd_event_loop_add(loop, -1, POLLIN, modbus_ready, NULL)) < 0)
            return -1;
    return uwbd_event_loop_add_hook(loop, modbus_prepare, modbus_after, (void *)port) < 0 ? -1 : 0;
}

const struct uwbd_output_module uwbd_output_modbus = {
    .name = "modbus",
    .open = modbus_open,
    .reload = modbus_reload,
    .watch = modbus_watch,
    .close = modbus_close,
};
