/* Debounce and rate limit of the event input (see the header). */
#include "integrations/event_trigger.h"

#include <string.h>

void uwbd_event_trigger_init(struct uwbd_event_trigger *t, double debounce_s, double min_interval_s)
{
    memset(t, 0, sizeof *t);
    t->debounce_s = debounce_s;
    t->min_interval_s = min_interval_s;
}

enum uwbd_event_result uwbd_event_trigger_sample(struct uwbd_event_trigger *t, int active, double now_s)
{
    if (!active) {
        t->active = 0;
        t->counted = 0;
        return UWBD_EVENT_NONE;
    }
    if (!t->active) {
        t->active = 1;
        t->active_since_s = now_s;
    }
    if (t->counted || now_s - t->active_since_s < t->debounce_s)
        return UWBD_EVENT_NONE;
    t->counted = 1;
    if (t->has_fired && now_s - t->last_fired_s < t->min_interval_s) {
        t->suppressed++;
        return UWBD_EVENT_SUPPRESSED;
    }
    t->has_fired = 1;
    t->last_fired_s = now_s;
    t->fired++;
    return UWBD_EVENT_FIRE;
}
