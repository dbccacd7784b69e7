/* The daemon's event registry and its poll() round (see the header). */
#include "loop/event_loop.h"

#include <poll.h>
#include <string.h>

void uwbd_event_loop_init(struct uwbd_event_loop *loop)
{
    memset(loop, 0, sizeof *loop);
}

int uwbd_event_loop_add(struct uwbd_event_loop *loop, int fd, short events, uwbd_event_fn fn, void *ctx)
{
    if (!fn)
        return -1;
    for (int i = 0; i < UWBD_EVENT_LOOP_MAX; i++) {
        struct uwbd_event_entry *e = &loop->entries[i];
        if (e->in_use)
            continue;
        *e = (struct uwbd_event_entry){
            .in_use = 1, .fd = fd, .events = events, .generation = ++loop->generation, .fn = fn, .ctx = ctx};
        return i;
    }
    return -1;
}

static struct uwbd_event_entry *entry(struct uwbd_event_loop *loop, int id)
{
    if (id < 0 || id >= UWBD_EVENT_LOOP_MAX || !loop->entries[id].in_use)
        return NULL;
    return &loop->entries[id];
}

void uwbd_event_loop_set(struct uwbd_event_loop *loop, int id, int fd, short events)
{
    struct uwbd_event_entry *e = entry(loop, id);
    if (!e)
        return;
    e->fd = fd;
    e->events = events;
}

void uwbd_event_loop_remove(struct uwbd_event_loop *loop, int id)
{
    struct uwbd_event_entry *e = entry(loop, id);
    if (e)
        e->in_use = 0;
}

int uwbd_event_loop_add_hook(struct uwbd_event_loop *loop, uwbd_event_prepare_fn prepare,
                             uwbd_event_after_fn after, void *ctx)
{
    for (int i = 0; i < UWBD_EVENT_LOOP_HOOKS; i++) {
        struct uwbd_event_hook *h = &loop->hooks[i];
        if (h->in_use)
            continue;
        *h = (struct uwbd_event_hook){.in_use = 1, .prepare = prepare, .after = after, .ctx = ctx};
        return i;
    }
    return -1;
}

void uwbd_event_loop_remove_hook(struct uwbd_event_loop *loop, int id)
{
    if (id >= 0 && id < UWBD_EVENT_LOOP_HOOKS)
        loop->hooks[id].in_use = 0;
}

static int earlier(int a_ms, int b_ms)
{
    if (a_ms < 0)
        return b_ms;
    if (b_ms < 0)
        return a_ms;
    return a_ms < b_ms ? a_ms : b_ms;
}

int uwbd_event_loop_once(struct uwbd_event_loop *loop, int timeout_ms)
{
    for (int i = 0; i < UWBD_EVENT_LOOP_HOOKS; i++)
        if (loop->hooks[i].in_use && loop->hooks[i].prepare)
            timeout_ms = earlier(timeout_ms, loop->hooks[i].prepare(loop->hooks[i].ctx));
    struct pollfd fds[UWBD_EVENT_LOOP_MAX];
    int id[UWBD_EVENT_LOOP_MAX];
    unsigned generation[UWBD_EVENT_LOOP_MAX];
    nfds_t n = 0;
    for (int i = 0; i < UWBD_EVENT_LOOP_MAX; i++) {
        const struct uwbd_event_entry *e = &loop->entries[i];
        if (!e->in_use || e->fd < 0)
            continue;
        id[n] = i;
        generation[n] = e->generation;
        fds[n++] = (struct pollfd){.fd = e->fd, .events = e->events};
    }
    if (poll(fds, n, timeout_ms) < 0)
        return -1;
    int ran = 0;
    for (nfds_t k = 0; k < n; k++) {
        const struct uwbd_event_entry *e = &loop->entries[id[k]];
        /* Removed (or removed and its slot taken again) by an earlier callback. */
        if (!fds[k].revents || !e->in_use || e->generation != generation[k])
            continue;
        e->fn(e->ctx, fds[k].fd, fds[k].revents);
        ran++;
    }
    for (int i = 0; i < UWBD_EVENT_LOOP_HOOKS; i++)
        if (loop->hooks[i].in_use && loop->hooks[i].after)
            loop->hooks[i].after(loop->hooks[i].ctx);
    return ran;
}
