/* The peers in the main loop: the control socket, its clients and the
 * console, each an entry whose fd and interest change round by round, and
 * all of them closed at the end. The control socket itself is opened early
 * in start(), before the hardware, so that a second uwbd stops there. */
#include <poll.h>

#include "daemon_internal.h"

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

int uwbd_peers_watch(struct daemon *d, struct uwbd_event_loop *loop)
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

void uwbd_peers_close_all(struct daemon *d)
{
    for (int i = 0; i < MAX_CLIENTS; i++)
        if (d->clients[i].in_use)
            uwbd_peer_close(&d->clients[i]);
    if (d->console.in_use)
        uwbd_peer_close(&d->console);
    uwbd_control_close(&d->control);
}
