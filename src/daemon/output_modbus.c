/* The Modbus output module (the server: src/integrations/modbus_server.c):
 * opened at start and on a reload that changes modbus.*, its fds in the
 * event loop, given the registers from the latest verdict and the daemon's
 * state at each request, and its coils turned into commands. */
#include <string.h>

#include "control/exit_codes.h"
#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"
#include "integrations/modbus_registers.h"
#include "integrations/modbus_server.h"

static void fill_registers(void *ctx, uint16_t regs[UWBD_MODBUS_REGISTER_COUNT])
{
    struct daemon *d = ctx;
    struct uwbd_modbus_status status = {
        .scan_count = (unsigned long)d->scans_this_run,
        .scanning = d->scanning,
        .device_fault = d->fault[0] != '\0',
        /* d->rig belongs to the worker while a scan runs: only read it when none does. */
        .rig_down = !d->scanning && !d->rig,
        .has_baseline = d->has_baseline,
    };
    struct uwbd_contact_states contacts;
    uwbd_contact_states(d, &contacts);
    /* -1: no contacts configured, none energised */
    status.contacts = (contacts.watch == 1 ? UWBD_MODBUS_CONTACT_WATCH : 0u) |
                      (contacts.alarm == 1 ? UWBD_MODBUS_CONTACT_ALARM : 0u) |
                      (contacts.fault == 1 ? UWBD_MODBUS_CONTACT_FAULT : 0u);
    uwbd_modbus_registers_fill(d->latest, &status, regs);
}

/* Coil 1: a scan as soon as the running one ends, as `event` does. */
static int coil_event(void *ctx)
{
    struct daemon *d = ctx;
    if (d->stopping)
        return -1;
    uwbd_log(UWBD_LOG_NOTICE, "modbus: event coil: scan requested");
    uwbd_scan_request(d, TRIGGER_EVENT);
    return 0;
}

/* Coil 0: `ack`; a failure (no contacts configured) answers "server failure". */
static int coil_ack(void *ctx)
{
    struct daemon *d = ctx;
    char err[160];
    if (uwbd_contacts_acknowledge(d, err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_NOTICE, "modbus: ack coil: %s", err);
        return -1;
    }
    uwbd_log(UWBD_LOG_NOTICE, "modbus: ack coil: latched contacts acknowledged");
    return 0;
}

static int modbus_start(struct daemon *d, char *err, size_t errlen)
{
    d->modbus = NULL;
    if (!d->cfg.modbus.enabled)
        return 0; /* nothing opened */
    struct uwbd_modbus_handlers h = {.ctx = d, .fill = fill_registers};
    h.coil[UWBD_MODBUS_COIL_EVENT] = coil_event;
    h.coil[UWBD_MODBUS_COIL_ACK] = coil_ack;
    if (uwbd_modbus_server_open(d->cfg.modbus.endpoint, d->cfg.modbus.unit_id, &h, &d->modbus, err, errlen) !=
        0)
        return -1;
    uwbd_modbus_server_set_idle_timeout(d->modbus, d->cfg.modbus.idle_timeout_s);
    return 0;
}

static int modbus_open(struct daemon *d)
{
    char err[1024];
    if (modbus_start(d, err, sizeof err) == 0)
        return 0;
    uwbd_log(UWBD_LOG_ERR, "%s", err);
    return UWBD_EXIT_CANT_CREATE;
}

static void modbus_close(struct daemon *d)
{
    uwbd_modbus_server_close(d->modbus);
    d->modbus = NULL;
}

static void modbus_reload(struct daemon *d, const struct uwbd_config *previous_cfg)
{
    const struct uwbd_modbus_config *previous = &previous_cfg->modbus;
    const struct uwbd_modbus_config *now = &d->cfg.modbus;
    if (previous->enabled == now->enabled && previous->unit_id == now->unit_id &&
        strcmp(previous->endpoint, now->endpoint) == 0) {
        /* The same server: a new idle timeout applies to the masters connected. */
        if (d->modbus)
            uwbd_modbus_server_set_idle_timeout(d->modbus, now->idle_timeout_s);
        return;
    }
    modbus_close(d);
    char err[512];
    if (modbus_start(d, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "reload: %s; Modbus is off until the next reload", err);
}

static void modbus_ready(void *ctx, int fd, short revents)
{
    (void)revents;
    struct daemon *d = ctx;
    if (d->modbus)
        uwbd_modbus_server_serve_fd(d->modbus, fd);
}

/* The server's fds this round (its TCP masters come and go), the wait
 * bounded by its next retry or master's deadline. */
static int modbus_prepare(void *ctx)
{
    struct daemon *d = ctx;
    struct pollfd fds[UWBD_MODBUS_POLL_FDS];
    int n = d->modbus ? uwbd_modbus_server_poll_fds(d->modbus, fds, UWBD_MODBUS_POLL_FDS) : 0;
    for (int i = 0; i < UWBD_MODBUS_POLL_FDS; i++)
        uwbd_event_loop_set(&d->events, d->modbus_id[i], i < n ? fds[i].fd : -1, POLLIN);
    return d->modbus ? uwbd_modbus_server_timeout_ms(d->modbus) : -1;
}

static void modbus_after(void *ctx)
{
    struct daemon *d = ctx;
    if (d->modbus)
        uwbd_modbus_server_tick(d->modbus);
}

static int modbus_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    for (int i = 0; i < UWBD_MODBUS_POLL_FDS; i++)
        if ((d->modbus_id[i] = uwbd_event_loop_add(loop, -1, POLLIN, modbus_ready, d)) < 0)
            return -1;
    return uwbd_event_loop_add_hook(loop, modbus_prepare, modbus_after, d) < 0 ? -1 : 0;
}

const struct uwbd_output_module uwbd_output_modbus = {
    .name = "modbus",
    .open = modbus_open,
    .reload = modbus_reload,
    .watch = modbus_watch,
    .close = modbus_close,
};
