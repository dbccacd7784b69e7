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

void uwbd_contacts_restore(struct uwbd_contacts *c, const char *status)
{
    uwbd_contacts_verdict(c, status, 0);
    c->healthy = 1; /* the daemon has just opened its hardware */
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
