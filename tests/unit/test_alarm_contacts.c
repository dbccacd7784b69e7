/* The alarm contacts' sequence (ISA-18.1 latching, fail-safe fault
 * contact), without lines. */
#include "unity.h"

#include "integrations/alarm_contacts.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static struct uwbd_contacts c;

/* "watch alarm fault" energised, e.g. "110". */
static void expect(const char *want, const char *when)
{
    char got[4] = {(char)('0' + uwbd_contacts_energised(&c, UWBD_CONTACT_WATCH)),
                   (char)('0' + uwbd_contacts_energised(&c, UWBD_CONTACT_ALARM)),
                   (char)('0' + uwbd_contacts_energised(&c, UWBD_CONTACT_FAULT)), 0};
    TEST_ASSERT_EQUAL_STRING_MESSAGE(want, got, when);
}

static void test_healthy_and_quiet_at_start(void)
{
    uwbd_contacts_init(&c, 1, 1);
    expect("001", "start: only the fault contact (healthy) energised");
}

static void test_latched_contacts_hold_until_ack(void)
{
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_verdict(&c, "watch", 0);
    expect("101", "watch");
    uwbd_contacts_verdict(&c, "alarm", 0);
    expect("111", "alarm: the second stage, watch still closed");
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("111", "ok after alarm: both latched");
    uwbd_contacts_verdict(&c, "inconclusive", 0);
    expect("111", "inconclusive changes nothing");
    uwbd_contacts_ack(&c);
    expect("001", "ack after ok: released");
}

static void test_ack_while_the_condition_holds(void)
{
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_ack(&c);
    expect("111", "ack during an alarm: the condition keeps them");
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("001", "ok after an acknowledged alarm: released, no second ack");
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("111", "a new alarm latches again");
}

static void test_unlatched_contacts_follow_the_verdict(void)
{
    uwbd_contacts_init(&c, 0, 1);
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_verdict(&c, "watch", 0);
    expect("111", "watch after alarm: alarm latched");
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("011", "ok: watch (not latched) released, alarm held");
    uwbd_contacts_ack(&c);
    expect("001", "ack");
}

static void test_fault_contact_is_fail_safe(void)
{
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_verdict(&c, "error", 0);
    expect("000", "error verdict: the fault contact opens");
    uwbd_contacts_verdict(&c, "watch", 0);
    expect("101", "a good scan again: healthy");
    uwbd_contacts_verdict(&c, "inconclusive", 1);
    expect("100", "a device fault (baseline) named in the verdict: open");
    uwbd_contacts_ack(&c);
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("001", "healthy again");
}

static void test_restart_restores_the_condition(void)
{
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT_NONE, NULL, "alarm", 0);
    expect("111", "alarm recorded before the restart, no latch kept (an older state directory)");
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("111", "still unacknowledged");
}

/* Issue 43, break 1: an alarm the winding came back from, not acknowledged,
 * then a restart: the latch kept in the state directory holds it. */
static void test_restart_keeps_an_unacknowledged_latch(void)
{
    struct uwbd_contacts_memory kept;
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("111", "ok after the alarm, not acknowledged");
    uwbd_contacts_remember(&c, &kept);
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT, &kept, "ok", 0);
    expect("111", "restart: the latch comes back although the latest verdict is ok");
    uwbd_contacts_ack(&c);
    expect("001", "ack after the restart releases it");
}

/* The latest verdict is an error: the fault contact stays open across a
 * restart, as uwbd-contacts(7) promises, and the latch with it. */
static void test_restart_after_an_error_keeps_the_fault_open(void)
{
    struct uwbd_contacts_memory kept;
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_verdict(&c, "error", 0);
    expect("110", "an error after the alarm");
    uwbd_contacts_remember(&c, &kept);
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT, &kept, "error", 0);
    expect("110", "restart after the error: alarm held, fault open");
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT_NONE, NULL, "ok", 1);
    expect("000", "restart after a verdict that names a device fault: fault open");
}

/* A power cut between the verdict's record and the latch's: the latch kept
 * predates the verdict, which is applied on top of it. Applying the verdict
 * the latch already reflects changes nothing (an ack stays an ack). */
static void test_restart_applies_the_latest_verdict_on_the_latch(void)
{
    struct uwbd_contacts_memory kept;
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_remember(&c, &kept);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT, &kept, "alarm", 0);
    expect("111", "latch kept before the alarm verdict was told to the contacts");
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("111", "and it latched");
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_verdict(&c, "alarm", 0);
    uwbd_contacts_ack(&c);
    uwbd_contacts_remember(&c, &kept);
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT, &kept, "alarm", 0);
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("001", "an alarm acknowledged before the restart is not raised again by its own verdict");
}

/* A latch file that cannot be read fails safe: watch and alarm held as
 * raised until `ack`. */
static void test_unreadable_latch_holds_the_alarm(void)
{
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT_UNREADABLE, NULL, "ok", 0);
    expect("111", "unreadable latch: held");
    uwbd_contacts_ack(&c);
    expect("001", "ack releases it");
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, UWBD_CONTACTS_KEPT_UNREADABLE, NULL, NULL, 0);
    expect("111", "unreadable latch, no verdict recorded: held");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_healthy_and_quiet_at_start);
    RUN_TEST(test_latched_contacts_hold_until_ack);
    RUN_TEST(test_ack_while_the_condition_holds);
    RUN_TEST(test_unlatched_contacts_follow_the_verdict);
    RUN_TEST(test_fault_contact_is_fail_safe);
    RUN_TEST(test_restart_restores_the_condition);
    RUN_TEST(test_restart_keeps_an_unacknowledged_latch);
    RUN_TEST(test_restart_after_an_error_keeps_the_fault_open);
    RUN_TEST(test_restart_applies_the_latest_verdict_on_the_latch);
    RUN_TEST(test_unreadable_latch_holds_the_alarm);
    return UNITY_END();
}
