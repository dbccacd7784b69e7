/* The daemon's side of the Modbus server (src/integrations/modbus_server.c):
 * opened at start and on a reload that changes modbus.*, polled with the
 * loop's other fds, given the registers from the latest verdict and the
 * daemon's state at each request, and its coils turned into commands. */
#include <string.h>

#include "daemon_internal.h"
#include "util/log.h"
#include "integrations/modbus_registers.h"
#include "integrations/modbus_server.h"
#include "integrations/site.h"

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
    uwbd_site_contact_states(d->site, &contacts);
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
    if (uwbd_site_ack(d->site, err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_NOTICE, "modbus: ack coil: %s", err);
        return -1;
    }
    uwbd_log(UWBD_LOG_NOTICE, "modbus: ack coil: latched contacts acknowledged");
    return 0;
}

int uwbd_modbus_open(struct daemon *d, char *err, size_t errlen)
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

void uwbd_modbus_close(struct daemon *d)
{
    uwbd_modbus_server_close(d->modbus);
    d->modbus = NULL;
}

void uwbd_modbus_reload(struct daemon *d, const struct uwbd_modbus_config *previous)
{
    const struct uwbd_modbus_config *now = &d->cfg.modbus;
    if (previous->enabled == now->enabled && previous->unit_id == now->unit_id &&
        strcmp(previous->endpoint, now->endpoint) == 0) {
        /* The same server: a new idle timeout applies to the masters connected. */
        if (d->modbus)
            uwbd_modbus_server_set_idle_timeout(d->modbus, now->idle_timeout_s);
        return;
    }
    uwbd_modbus_close(d);
    char err[512];
    if (uwbd_modbus_open(d, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "reload: %s; Modbus is off until the next reload", err);
}

int uwbd_modbus_poll_add(struct daemon *d, struct pollfd *fds, int *timeout_ms)
{
    if (!d->modbus)
        return 0;
    int retry_ms = uwbd_modbus_server_timeout_ms(d->modbus);
    if (retry_ms >= 0 && (*timeout_ms < 0 || retry_ms < *timeout_ms))
        *timeout_ms = retry_ms;
    return uwbd_modbus_server_poll_fds(d->modbus, fds, UWBD_MODBUS_POLL_FDS);
}

void uwbd_modbus_poll_serve(struct daemon *d, const struct pollfd *fds, int n)
{
    if (d->modbus)
        uwbd_modbus_server_serve(d->modbus, fds, n);
}
