/* The alarm contacts' states (see the header): plain logic, so that the
 * sequence is tested without lines; src/integrations/site_io.c drives the
 * GPIO outputs from it. */
#include "integrations/alarm_contacts.h"

#include <string.h>

void uwbd_contacts_init(struct uwbd_contacts *c, int latch_watch, int latch_alarm)
{
    memset(c, 0, sizeof *c);
    c->latch_watch = latch_watch;
    c->latch_alarm = latch_alarm;
    c->healthy = 1;
}

static void call(struct uwbd_contacts *c, int watch, int alarm)
{
    c->watch_unacked |= watch && !c->watch_called;
    c->alarm_unacked |= alarm && !c->alarm_called;
    c->watch_called = watch;
    c->alarm_called = alarm;
}

void uwbd_contacts_verdict(struct uwbd_contacts *c, const char *status, int device_fault)
{
    int error = strcmp(status, "error") == 0;
    c->healthy = !error && !device_fault;
    if (strcmp(status, "alarm") == 0)
        call(c, 1, 1);
    else if (strcmp(status, "watch") == 0)
        call(c, 1, 0);
    else if (strcmp(status, "ok") == 0)
        call(c, 0, 0);
    /* inconclusive, error: the winding's state is not known better than before */
}

void uwbd_contacts_remember(const struct uwbd_contacts *c, struct uwbd_contacts_memory *out)
{
    out->watch_called = c->watch_called;
    out->alarm_called = c->alarm_called;
    out->watch_unacked = c->watch_unacked;
    out->alarm_unacked = c->alarm_unacked;
}

void uwbd_contacts_restore(struct uwbd_contacts *c, enum uwbd_contacts_kept kept,
                           const struct uwbd_contacts_memory *memory, const char *latest_status,
                           int latest_fault)
{
    if (kept == UWBD_CONTACTS_KEPT && memory) {
        c->watch_called = memory->watch_called != 0;
        c->alarm_called = memory->alarm_called != 0;
        c->watch_unacked = memory->watch_unacked != 0;
        c->alarm_unacked = memory->alarm_unacked != 0;
    } else if (kept == UWBD_CONTACTS_KEPT_UNREADABLE) {
        /* Whether an alarm stood unacknowledged is unknown: hold it. */
        c->watch_unacked = 1;
        c->alarm_unacked = 1;
    }
    if (latest_status)
        uwbd_contacts_verdict(c, latest_status, latest_fault);
    else
        c->healthy = 1;
}

void uwbd_contacts_ack(struct uwbd_contacts *c)
{
    c->watch_unacked = 0;
    c->alarm_unacked = 0;
}

int uwbd_contacts_energised(const struct uwbd_contacts *c, enum uwbd_contact which)
{
    switch (which) {
    case UWBD_CONTACT_WATCH: return c->watch_called || (c->latch_watch && c->watch_unacked);
    case UWBD_CONTACT_ALARM: return c->alarm_called || (c->latch_alarm && c->alarm_unacked);
    case UWBD_CONTACT_FAULT: return c->healthy;
    case UWBD_CONTACT_COUNT: break;
    }
    return 0;
}

const char *uwbd_contact_name(enum uwbd_contact which)
{
    static const char *const names[UWBD_CONTACT_COUNT] = {"watch", "alarm", "fault"};
    return (int)which >= 0 && which < UWBD_CONTACT_COUNT ? names[which] : "?";
}
