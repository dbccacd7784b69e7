/* uwb_utc_parse: uwbd's own "YYYY-MM-DDTHH:MM:SSZ" stamps back to seconds,
 * anything else refused without touching the result. */
#include "unity.h"

#include <time.h>

#include "uwb/utc_time.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static void test_reads_what_strftime_writes(void)
{
    time_t t = 0;
    TEST_ASSERT_EQUAL_INT(0, uwb_utc_parse("1970-01-01T00:00:00Z", &t));
    TEST_ASSERT_EQUAL_INT64(0, (long long)t);
    TEST_ASSERT_EQUAL_INT(0, uwb_utc_parse("2026-11-24T08:31:54Z", &t));
    TEST_ASSERT_EQUAL_INT64(1795509114LL, (long long)t);
    /* Round trip through gmtime_r + strftime, as store.c and rig.c write it. */
    for (long long s = 0; s < 4000000000LL; s += 123456789LL) {
        time_t when = (time_t)s, back = -1;
        struct tm tm;
        char text[32];
        gmtime_r(&when, &tm);
        strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_utc_parse(text, &back), text);
        TEST_ASSERT_EQUAL_INT64_MESSAGE(s, (long long)back, text);
    }
}

static void test_refuses_other_shapes_and_out_of_range_fields(void)
{
    static const char *const bad[] = {
        "",
        "2026-11-24T08:31:54", /* no zone */
        "2026-11-24T08:31:54+01",
        "2026-11-24 08:31:54Z",
        "2026-1-24T08:31:54Z",
        "2026-11-24T8:31:54Z",
        "2026-11-24T08:31:54Zx",
        " 2026-11-24T08:31:54Z",
        "+026-11-24T08:31:54Z",
        "2026-00-24T08:31:54Z",
        "2026-13-24T08:31:54Z",
        "2026-11-00T08:31:54Z",
        "2026-11-32T08:31:54Z",
        "2026-11-24T24:00:00Z",
        "2026-11-24T08:60:00Z",
        "2026-11-24T08:31:61Z",
        "2026-11-24T08:31:5aZ",
        "2026/11/24T08:31:54Z",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        time_t t = 42;
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, uwb_utc_parse(bad[i], &t), bad[i]);
        TEST_ASSERT_EQUAL_INT64_MESSAGE(42, (long long)t, bad[i]);
    }
    time_t t = 42;
    TEST_ASSERT_EQUAL_INT(-1, uwb_utc_parse(NULL, &t));
    TEST_ASSERT_EQUAL_INT(0, uwb_utc_parse("2016-12-31T23:59:60Z", &t)); /* a leap second is a time */
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_reads_what_strftime_writes);
    RUN_TEST(test_refuses_other_shapes_and_out_of_range_fields);
    return UNITY_END();
}
