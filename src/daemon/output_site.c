/* The site's output module: the alarm contacts, the event input, the
 * Prometheus textfile and MQTT, one object (src/integrations/site.c) since
 * the textfile and MQTT's health report carry the contacts' states. Opened
 * again on a reload only when site.* changed. */
#include <poll.h>
#include <string.h>

#include "daemon/exit_codes.h"
#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"

static int site_open(struct daemon *d)
{
    char err[1024];
    int rc = uwbd_site_open(&d->site, &d->cfg, d->latest, err, sizeof err);
    if (rc == UWB_GPIO_OK)
        return 0;
    int code = uwbd_exit_for_rig_open(UWB_RIG_ERR_GPIO, rc);
    uwbd_log(UWBD_LOG_ERR, "%s (exit %d)", err, code);
    return code;
}

static void site_reload(struct daemon *d, const struct uwbd_config *previous)
{
    /* Byte comparison on purpose (see reload() in daemon.c): both sides are
     * zeroed before filling and copied with memcpy. */
    // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): padding zeroed, see above
    if (memcmp(&previous->site, &d->cfg.site, sizeof d->cfg.site) == 0)
        return;
    uwbd_site_close(d->site);
    d->site = NULL;
    char err[1024];
    if (uwbd_site_open(&d->site, &d->cfg, d->latest, err, sizeof err) != UWB_GPIO_OK)
        uwbd_log(UWBD_LOG_ERR,
                 "reload: the site's lines: %s; alarm contacts and event input are off until "
                 "the next reload",
                 err);
}

static void site_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                         double duration_s)
{
    if (json && v)
        uwbd_site_verdict(d->site, v, json, duration_s);
}

/* The site's timer: the event input read, a lost line opened again. */
static void site_tick(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    struct daemon *d = ctx;
    if (uwbd_site_tick(d->site) && !d->stopping)
        uwbd_scan_request(d, TRIGGER_EVENT);
}

static void site_commands(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    uwbd_run_site_commands(ctx);
}

/* The site's fds change when a reload opens it again; MQTT's commands wait while the daemon stops. */
static int site_prepare(void *ctx)
{
    struct daemon *d = ctx;
    uwbd_event_loop_set(&d->events, d->site_timer_id, uwbd_site_timer_fd(d->site), POLLIN);
    uwbd_event_loop_set(&d->events, d->site_command_id, d->stopping ? -1 : uwbd_site_command_fd(d->site),
                        POLLIN);
    return -1;
}

static int site_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    d->site_timer_id = uwbd_event_loop_add(loop, -1, POLLIN, site_tick, d);
    d->site_command_id = uwbd_event_loop_add(loop, -1, POLLIN, site_commands, d);
    if (d->site_timer_id < 0 || d->site_command_id < 0)
        return -1;
    return uwbd_event_loop_add_hook(loop, site_prepare, NULL, d) < 0 ? -1 : 0;
}

static void site_close(struct daemon *d)
{
    uwbd_site_close(d->site); /* contacts de-energised: the fault contact opens */
    d->site = NULL;
}

const struct uwbd_output_module uwbd_output_site = {
    .name = "site",
    .open = site_open,
    .reload = site_reload,
    .verdict = site_verdict,
    .watch = site_watch,
    .close = site_close,
};
