/* The alarm contacts' logic (src/integrations/alarm_contacts.c), apart
 * from the lines that carry it: which of watch, alarm and device fault is
 * energised after each verdict, `ack` and a change of health.
 *
 * Watch and alarm follow ISA-18.1's latching sequence: a contact is
 * energised while the latest verdict calls for it (alarm also calls for
 * watch, as the second stage of a two-stage relay does) and, when it
 * latches, from then until an `ack` as well. The fault contact is
 * energised while the appliance is healthy, so a dead board opens it. */
#ifndef UWB_DAEMON_ALARM_CONTACTS_H
#define UWB_DAEMON_ALARM_CONTACTS_H

struct uwbd_contacts {
    int latch_watch, latch_alarm;
    int watch_called, alarm_called;   /* the latest verdict calls for it */
    int watch_unacked, alarm_unacked; /* raised since the last `ack` */
    int healthy;
};

enum uwbd_contact { UWBD_CONTACT_WATCH, UWBD_CONTACT_ALARM, UWBD_CONTACT_FAULT, UWBD_CONTACT_COUNT };

/* Healthy, nothing called for. */
void uwbd_contacts_init(struct uwbd_contacts *c, int latch_watch, int latch_alarm);
/* A verdict's status ("ok", "watch", "alarm", "inconclusive", "error")
 * and whether it names a device fault (its "fault" field). An error or a
 * fault opens the fault contact; inconclusive leaves watch and alarm as
 * they are (nothing was learnt about the winding). */
void uwbd_contacts_verdict(struct uwbd_contacts *c, const char *status, int device_fault);
/* What a restart must not lose: what the verdicts called for and what is
 * raised unacknowledged (kept in the state directory: contacts_latch.c). */
struct uwbd_contacts_memory {
    int watch_called, alarm_called;
    int watch_unacked, alarm_unacked;
};
enum uwbd_contacts_kept {
    UWBD_CONTACTS_KEPT_NONE,      /* nothing kept: an older or a new state directory */
    UWBD_CONTACTS_KEPT,           /* the memory read back */
    UWBD_CONTACTS_KEPT_UNREADABLE /* a file that cannot be read: fail safe */
};
void uwbd_contacts_remember(const struct uwbd_contacts *c, struct uwbd_contacts_memory *out);
/* At start, after init: the memory kept before the restart (`memory` read
 * when `kept` is UWBD_CONTACTS_KEPT; an unreadable one holds watch and
 * alarm as raised until `ack`), then the latest recorded verdict on top of
 * it (NULL: none), since the latch may have been kept just before that
 * verdict came; applying a verdict the memory already reflects changes
 * nothing. The fault contact follows that verdict: open after an error or
 * a device fault. */
void uwbd_contacts_restore(struct uwbd_contacts *c, enum uwbd_contacts_kept kept,
                           const struct uwbd_contacts_memory *memory, const char *latest_status,
                           int latest_fault);
void uwbd_contacts_ack(struct uwbd_contacts *c);
/* Whether `which` is energised now. */
int uwbd_contacts_energised(const struct uwbd_contacts *c, enum uwbd_contact which);
const char *uwbd_contact_name(enum uwbd_contact which);

#endif
