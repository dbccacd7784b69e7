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
    uwbd_contacts_restore(&c, "alarm");
    expect("111", "alarm recorded before the restart");
    uwbd_contacts_verdict(&c, "ok", 0);
    expect("111", "still unacknowledged");
    uwbd_contacts_init(&c, 1, 1);
    uwbd_contacts_restore(&c, "error");
    expect("001", "an old error verdict: the hardware just opened, healthy");
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
    return UNITY_END();
}
