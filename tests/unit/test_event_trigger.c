/* The event input's debounce and rate limit (a protection relay's trip
 * contact in, "scan now" out), without lines. */
#include "unity.h"

#include "integrations/event_trigger.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static void test_event_input_is_debounced(void)
{
    struct uwbd_event_trigger t;
    uwbd_event_trigger_init(&t, 0.050, 600);
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_NONE, uwbd_event_trigger_sample(&t, 1, 100.000));
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_NONE, uwbd_event_trigger_sample(&t, 1, 100.040));
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWBD_EVENT_NONE, uwbd_event_trigger_sample(&t, 0, 100.045),
                                  "a bounce: restarts");
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_NONE, uwbd_event_trigger_sample(&t, 1, 100.060));
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_NONE, uwbd_event_trigger_sample(&t, 1, 100.100));
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_FIRE, uwbd_event_trigger_sample(&t, 1, 100.115));
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWBD_EVENT_NONE, uwbd_event_trigger_sample(&t, 1, 105.0),
                                  "held: one event");
    TEST_ASSERT_EQUAL_UINT(1, t.fired);
}

static void test_event_input_is_rate_limited(void)
{
    struct uwbd_event_trigger t;
    uwbd_event_trigger_init(&t, 0, 600);
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_FIRE, uwbd_event_trigger_sample(&t, 1, 1000));
    uwbd_event_trigger_sample(&t, 0, 1001);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWBD_EVENT_SUPPRESSED, uwbd_event_trigger_sample(&t, 1, 1002), "a reclose");
    uwbd_event_trigger_sample(&t, 0, 1003);
    TEST_ASSERT_EQUAL_INT(UWBD_EVENT_SUPPRESSED, uwbd_event_trigger_sample(&t, 1, 1599));
    uwbd_event_trigger_sample(&t, 0, 1599.5);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWBD_EVENT_FIRE, uwbd_event_trigger_sample(&t, 1, 1600),
                                  "after the interval");
    TEST_ASSERT_EQUAL_UINT(2, t.fired);
    TEST_ASSERT_EQUAL_UINT(2, t.suppressed);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_event_input_is_debounced);
    RUN_TEST(test_event_input_is_rate_limited);
    return UNITY_END();
}
