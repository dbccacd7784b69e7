/* The site's lines as a module: the one GPIO handle the alarm contacts and
 * the event input share, and the timer that reads the event input (an
 * input, not an output: it asks for scans). Opened again on a reload only
 * when the site's configuration changed. */
#include <poll.h>

#include "control/exit_codes.h"
#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"

static int site_io_open(struct daemon *d)
{
    char err[1024];
    int rc = uwbd_site_io_open(&d->site_io, &d->cfg.site, err, sizeof err);
    if (rc == UWB_GPIO_OK)
        return 0;
    int code = uwbd_exit_for_rig_open(UWB_RIG_ERR_GPIO, rc);
    uwbd_log(UWBD_LOG_ERR, "%s (exit %d)", err, code);
    return code;
}

static void site_io_close(struct daemon *d)
{
    uwbd_site_io_close(d->site_io); /* contacts de-energised: the fault contact opens */
    d->site_io = NULL;
}

static void site_io_reload(struct daemon *d, const struct uwbd_config *previous)
{
    if (!uwbd_site_changed(d, previous))
        return;
    site_io_close(d);
    char err[1024];
    if (uwbd_site_io_open(&d->site_io, &d->cfg.site, err, sizeof err) != UWB_GPIO_OK)
        uwbd_log(UWBD_LOG_ERR,
                 "reload: the site's lines: %s; alarm contacts and event input are off until "
                 "the next reload",
                 err);
}

/* The site's timer: the event input read, a lost line opened again. */
static void site_io_tick(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    struct daemon *d = ctx;
    if (uwbd_site_io_tick(d->site_io) && !d->stopping)
        uwbd_scan_request(d, TRIGGER_EVENT);
}

/* The timer changes when a reload opens the lines again. */
static int site_io_prepare(void *ctx)
{
    struct daemon *d = ctx;
    uwbd_event_loop_set(&d->events, d->site_timer_id, uwbd_site_io_timer_fd(d->site_io), POLLIN);
    return -1;
}

static int site_io_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    d->site_timer_id = uwbd_event_loop_add(loop, -1, POLLIN, site_io_tick, d);
    if (d->site_timer_id < 0)
        return -1;
    return uwbd_event_loop_add_hook(loop, site_io_prepare, NULL, d) < 0 ? -1 : 0;
}

const struct uwbd_output_module uwbd_output_site_io = {
    .name = "site lines",
    .open = site_io_open,
    .reload = site_io_reload,
    .watch = site_io_watch,
    .close = site_io_close,
};
