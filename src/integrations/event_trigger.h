/* The event input's logic (src/integrations/event_trigger.c): samples of
 * a protection relay's trip contact in, "scan now" out, debounced (the
 * input must stay active for the debounce time) and rate-limited (at most
 * one event scan per interval; a relay that chatters or recloses does not
 * keep the carriage running). One activation is one event however long it
 * lasts. */
#ifndef UWB_DAEMON_EVENT_TRIGGER_H
#define UWB_DAEMON_EVENT_TRIGGER_H

struct uwbd_event_trigger {
    double debounce_s, min_interval_s;
    int active;            /* the last sample */
    double active_since_s; /* when the input last went active */
    int counted;           /* this activation has been counted */
    int has_fired;
    double last_fired_s;
    unsigned long fired, suppressed;
};

enum uwbd_event_result {
    UWBD_EVENT_NONE,       /* nothing new */
    UWBD_EVENT_FIRE,       /* an event: scan as soon as possible */
    UWBD_EVENT_SUPPRESSED, /* an event inside min_interval_s of the last: dropped */
};

void uwbd_event_trigger_init(struct uwbd_event_trigger *t, double debounce_s, double min_interval_s);
/* One sample of the input (1 = active) at now_s (CLOCK_MONOTONIC). */
enum uwbd_event_result uwbd_event_trigger_sample(struct uwbd_event_trigger *t, int active, double now_s);

#endif
