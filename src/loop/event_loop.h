/* Event sources in one registry walked by poll() (the pattern
 * of redis's aeCreateFileEvent): a source registers its fd, the events it
 * waits for and a callback; hooks run before each poll (to update fds and
 * bound the wait) and after it (deadlines that need no fd). Callbacks run in
 * registration order (the lowest free slot), so the order in which sources
 * are served is the order they were registered in. */
#ifndef UWB_LOOP_EVENT_LOOP_H
#define UWB_LOOP_EVENT_LOOP_H

/* Fixed capacity, no allocation: the daemon registers 7 sources of its own,
 * the control socket, the console and 16 client slots, the site's timer and
 * MQTT command fd, and the Modbus server's 5 fds (35); 48 leaves room for a
 * few more output modules. A full table refuses (returns -1). */
#define UWBD_EVENT_LOOP_MAX 48
#define UWBD_EVENT_LOOP_HOOKS 8

/* fd: the registered fd; revents as poll() gave them. */
typedef void (*uwbd_event_fn)(void *ctx, int fd, short revents);
/* Before poll(): returns milliseconds until the hook needs to run again
 * without any fd (-1: no deadline). */
typedef int (*uwbd_event_prepare_fn)(void *ctx);
/* After every poll() that did not fail, once the fds' callbacks ran. */
typedef void (*uwbd_event_after_fn)(void *ctx);

struct uwbd_event_entry {
    int in_use;
    int fd; /* < 0: registered but not polled this round */
    short events;
    unsigned generation; /* tells a slot reused during dispatch from the one polled */
    uwbd_event_fn fn;
    void *ctx;
};

struct uwbd_event_hook {
    int in_use;
    uwbd_event_prepare_fn prepare;
    uwbd_event_after_fn after;
    void *ctx;
};

struct uwbd_event_loop {
    struct uwbd_event_entry entries[UWBD_EVENT_LOOP_MAX];
    struct uwbd_event_hook hooks[UWBD_EVENT_LOOP_HOOKS];
    unsigned generation;
};

void uwbd_event_loop_init(struct uwbd_event_loop *loop);
/* Returns the entry's id, or -1 when the table is full or fn is NULL. */
int uwbd_event_loop_add(struct uwbd_event_loop *loop, int fd, short events, uwbd_event_fn fn, void *ctx);
/* A registered entry's fd and events for the next poll (fd < 0: skip it). */
void uwbd_event_loop_set(struct uwbd_event_loop *loop, int id, int fd, short events);
/* Safe from a callback, for its own entry or another: an entry removed
 * during dispatch is not called for this round's events. */
void uwbd_event_loop_remove(struct uwbd_event_loop *loop, int id);
/* Either function may be NULL. Returns the hook's id, or -1 when full. */
int uwbd_event_loop_add_hook(struct uwbd_event_loop *loop, uwbd_event_prepare_fn prepare,
                             uwbd_event_after_fn after, void *ctx);
void uwbd_event_loop_remove_hook(struct uwbd_event_loop *loop, int id);
/* One round: the prepare hooks, poll() for at most timeout_ms (-1: no
 * bound but the hooks'), the callbacks of the fds that fired, the after
 * hooks. Returns the number of callbacks run, or -1 with errno from poll(). */
int uwbd_event_loop_once(struct uwbd_event_loop *loop, int timeout_ms);

#endif
