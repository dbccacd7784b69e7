/* The site's lines as a module: the one GPIO handle the alarm contacts and
 * the event input share, and the timer that reads the event input (an
 * input, not an output: it asks for scans). Opened again on a reload only
 * when the site's configuration changed. */
#include "daemon/output_site_io.h"

#include <poll.h>

#include "control/exit_codes.h"
#include "util/log.h"

static struct uwbd_site_io *lines; /* NULL: not open */
static int timer_id = -1;          /* the event input's timer in the main loop */

struct uwbd_site_io *uwbd_site_lines(void)
{
    return lines;
}

static int site_io_open(const struct uwbd_daemon_port *port)
{
    char err[1024];
    int rc = uwbd_site_io_open(&lines, &port->cfg->site, err, sizeof err);
    if (rc == UWB_GPIO_OK)
        return 0;
    int code = uwbd_exit_for_rig_open(UWB_RIG_ERR_GPIO, rc);
    uwbd_log(UWBD_LOG_ERR, "%s (exit %d)", err, code);
    return code;
}

static void site_io_close(const struct uwbd_daemon_port *port)
{
    (void)port;
    uwbd_site_io_close(lines); /* contacts de-energised: the fault contact opens */
    lines = NULL;
}

static void site_io_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous)
{
    if (!uwbd_site_changed(port->cfg, previous))
        return;
    site_io_close(port);
    char err[1024];
    if (uwbd_site_io_open(&lines, &port->cfg->site, err, sizeof err) != UWB_GPIO_OK)
        uwbd_log(UWBD_LOG_ERR,
                 "reload: the site's lines: %s; alarm contacts and event input are off until "
                 "the next reload",
                 err);
}

/* The site's timer: the event input read, a lost line opened again. */
static void site_io_tick(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    const struct uwbd_daemon_port *port = ctx;
    if (uwbd_site_io_tick(lines) && !port->stopping(port->daemon))
        port->request_event_scan(port->daemon);
}

/* The timer changes when a reload opens the lines again. */
static int site_io_prepare(void *ctx)
{
    const struct uwbd_daemon_port *port = ctx;
    uwbd_event_loop_set(port->events, timer_id, uwbd_site_io_timer_fd(lines), POLLIN);
    return -1;
}

static int site_io_watch(const struct uwbd_daemon_port *port, struct uwbd_event_loop *loop)
{
    timer_id = uwbd_event_loop_add(loop, -1, POLLIN, site_io_tick, (void *)port);
    if (timer_id < 0)
        return -1;
    return uwbd_event_loop_add_hook(loop, site_io_prepare, NULL, (void *)port) < 0 ? -1 : 0;
}

const struct uwbd_output_module uwbd_output_site_io = {
    .name = "site lines",
    .open = site_io_open,
    .reload = site_io_reload,
    .watch = site_io_watch,
    .close = site_io_close,
};
