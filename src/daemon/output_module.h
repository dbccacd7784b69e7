/* An output module and what it sees of the daemon. A module owns its state
 * (in its own file: one daemon per process) and reaches the daemon only
 * through the port below: the configuration in force, the state directory,
 * the latest record, and the few things it may ask for (a scan, `ack`, a
 * command's reply). It never sees struct daemon, so no module calls back
 * into the daemon's files: the table (outputs.c) is above the modules, the
 * daemon above the table. */
#ifndef UWBD_DAEMON_OUTPUT_MODULE_H
#define UWBD_DAEMON_OUTPUT_MODULE_H

#include <stddef.h>
#include <string.h>

#include "config/config_load.h"
#include "integrations/modbus_registers.h"
#include "loop/event_loop.h"
#include "state/store.h"
#include "uwb/verdict_record.h"

struct uwbd_daemon_port {
    void *daemon;                   /* the first argument of the calls below */
    const struct uwbd_config *cfg;  /* the configuration in force (a reload changes it in place) */
    const struct uwbd_store *store; /* the state directory */
    struct uwbd_event_loop *events; /* the main loop, for a prepare hook to set its fds */
    /* The latest verdict as a record, or NULL. */
    const struct uwb_verdict_record *(*latest)(void *daemon);
    /* Whether the daemon is stopping (no new scan, no command). */
    int (*stopping)(void *daemon);
    /* A scan as soon as the running one ends, as `event` asks. */
    void (*request_event_scan)(void *daemon);
    /* `ack`: 0, or -1 with err saying why (no contacts); every module then reports. */
    int (*acknowledge)(void *daemon, char *err, size_t errlen);
    /* A command from the site (MQTT): its reply line (malloc'd; NULL: out of memory). */
    char *(*site_command)(void *daemon, const char *text);
    /* What the Modbus registers say of the daemon (all but the contacts). */
    void (*modbus_status)(void *daemon, struct uwbd_modbus_status *out);
};

struct uwbd_output_module {
    const char *name;
    /* At start, after the hardware and the latest verdict: 0, or the exit
     * code the daemon stops with (the module logged why). */
    int (*open)(const struct uwbd_daemon_port *port);
    /* A reload was applied; previous: the configuration before it. */
    void (*reload)(const struct uwbd_daemon_port *port, const struct uwbd_config *previous);
    /* A scan cycle ended with verdict line json (NULL: none could be
     * written) and record v (the latest), having taken duration_s. */
    void (*verdict)(const struct uwbd_daemon_port *port, const struct uwb_verdict_record *v, const char *json,
                    double duration_s);
    /* The contacts changed outside a verdict (`ack`): report them again. */
    void (*report)(const struct uwbd_daemon_port *port);
    /* Registers its fds and hooks: 0, or -1 when the loop is full. */
    int (*watch)(const struct uwbd_daemon_port *port, struct uwbd_event_loop *loop);
    /* At exit or a failed start; safe when open did not run or failed. */
    void (*close)(const struct uwbd_daemon_port *port);
};

/* Whether a reload changed the site's configuration (site.*, contacts.*,
 * event.*, prometheus.*, mqtt.*): the site's modules open again only then.
 * Byte comparison on purpose (see reload() in daemon.c): both sides are
 * zeroed before filling and copied with memcpy. */
static inline int uwbd_site_changed(const struct uwbd_config *now, const struct uwbd_config *previous)
{
    // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): padding zeroed, see above
    return memcmp(&previous->site, &now->site, sizeof now->site) != 0;
}

#endif
