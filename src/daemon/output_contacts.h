/* The alarm contacts as an output module (output_contacts.c): their logic,
 * their latch, and `contacts test`'s sequence on their lines. */
#ifndef UWBD_DAEMON_OUTPUT_CONTACTS_H
#define UWBD_DAEMON_OUTPUT_CONTACTS_H

#include <stddef.h>

#include "daemon/output_module.h"
#include "integrations/alarm_contacts.h"
#include "integrations/site_io.h"

extern const struct uwbd_output_module uwbd_output_contacts;

/* Released seconds before and between the contacts `contacts test` energises. */
#define UWBD_CONTACTS_TEST_GAP_S 1

/* The contacts' states (-1 where there are none or their lines are off). */
void uwbd_contact_states(struct uwbd_contact_states *out);
/* Whether the appliance is healthy: the fault contact's state, contacts or not. */
int uwbd_appliance_healthy(void);
/* `ack`: latched contacts fall back to what the latest verdict calls for
 * (the caller has every module report then: outputs.h). -1 (err says why)
 * when there are no contacts. */
int uwbd_contacts_acknowledge(char *err, size_t errlen);
/* "an alarm" or "a watch" when one stands, else NULL. */
const char *uwbd_contacts_standing(void);
/* `contacts test`'s sequence: every contact released, then each energised
 * alone for hold_s seconds with UWBD_CONTACTS_TEST_GAP_S released between;
 * then the lines follow the logic again. Whether one runs (the lines are
 * then its, not the verdicts'). */
void uwbd_contacts_test_run(int hold_s);
int uwbd_contacts_testing(void);

#endif
