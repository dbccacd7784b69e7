/* The control clients' output module: the control socket's clients and the
 * console hear each verdict line (those waiting for the cycle, and those
 * that asked to `watch`). The control socket itself is opened early in
 * start(), before the hardware, so that a second uwbd stops there; this
 * module opens the console, registers the peers' fds and closes them all. */
#include <poll.h>

#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"

static int clients_open(struct daemon *d)
{
    uwbd_console_open(d);
    return 0;
}

static void clients_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                            double duration_s)
{
    (void)v, (void)duration_s;
    uwbd_peers_send_verdict(d, d->job.cycle, json, "out of memory for the verdict");
}

static void accept_client(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    uwbd_peer_accept(ctx);
}

struct peer_event {
    struct daemon *d;
    struct peer *p;
};
static struct peer_event peer_events[MAX_CLIENTS + 1]; /* one daemon per process */

static void peer_ready(void *ctx, int fd, short revents)
{
    (void)fd;
    struct peer_event *e = ctx;
    if ((revents & POLLOUT) && e->p->in_use)
        uwbd_peer_writable(e->d, e->p);
    if ((revents & ~POLLOUT) && e->p->in_use)
        uwbd_peer_readable(e->d, e->p);
}

/* Clients past their deadlines dropped first; then each peer's fd and whether it has replies to send. */
static int clients_prepare(void *ctx)
{
    struct daemon *d = ctx;
    int timeout_ms = uwbd_peers_expire(d);
    uwbd_event_loop_set(&d->events, d->control_id, d->stopping ? -1 : d->control.fd, POLLIN);
    uwbd_event_loop_set(&d->events, d->console_id, d->console.in_use ? uwb_link_fd(d->console.link) : -1,
                        POLLIN);
    for (int i = 0; i < MAX_CLIENTS; i++) {
        const struct peer *p = &d->clients[i];
        uwbd_event_loop_set(&d->events, d->client_id[i], p->in_use ? p->fd : -1,
                            (short)(POLLIN | (p->out_len ? POLLOUT : 0)));
    }
    return timeout_ms;
}

static int clients_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    if (uwbd_event_loop_add_hook(loop, clients_prepare, NULL, d) < 0)
        return -1;
    d->control_id = uwbd_event_loop_add(loop, -1, POLLIN, accept_client, d);
    peer_events[0] = (struct peer_event){d, &d->console};
    d->console_id = uwbd_event_loop_add(loop, -1, POLLIN, peer_ready, &peer_events[0]);
    if (d->control_id < 0 || d->console_id < 0)
        return -1;
    for (int i = 0; i < MAX_CLIENTS; i++) {
        peer_events[i + 1] = (struct peer_event){d, &d->clients[i]};
        d->client_id[i] = uwbd_event_loop_add(loop, -1, POLLIN, peer_ready, &peer_events[i + 1]);
        if (d->client_id[i] < 0)
            return -1;
    }
    return 0;
}

static void clients_close(struct daemon *d)
{
    for (int i = 0; i < MAX_CLIENTS; i++)
        if (d->clients[i].in_use)
            uwbd_peer_close(&d->clients[i]);
    if (d->console.in_use)
        uwbd_peer_close(&d->console);
    uwbd_control_close(&d->control);
}

const struct uwbd_output_module uwbd_output_clients = {
    .name = "control clients",
    .open = clients_open,
    .verdict = clients_verdict,
    .watch = clients_watch,
    .close = clients_close,
};
