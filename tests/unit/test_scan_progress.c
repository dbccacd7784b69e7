/* Scan progress and its time-left estimate (src/control/scan_progress.c). */
#include "unity.h"

#include <cjson/cJSON.h>
#include <stdlib.h>

#include "control/scan_progress.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static void test_nothing_acquired_has_no_estimate(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate(0, 40, 100.0, 0, 0, 103.5, &p);
    TEST_ASSERT_EQUAL_INT(0, p.done);
    TEST_ASSERT_EQUAL_INT(40, p.total);
    TEST_ASSERT_EQUAL_DOUBLE(3.5, p.elapsed_s);
    TEST_ASSERT_FALSE(p.has_left);
}

/* The pace comes from the positions after the first: homing (10 s before the
 * first position) must not inflate it. 40 positions, 1 s apart. */
static void test_pace_between_positions_not_homing(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate(11, 40, 0.0, 10.0, 20.0, 20.0, &p);
    TEST_ASSERT_TRUE(p.has_left);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 29.0, p.left_s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 20.0, p.elapsed_s);
    /* 0.4 s after the 11th position, 0.4 s less is left. */
    uwbd_scan_progress_estimate(11, 40, 0.0, 10.0, 20.0, 20.4, &p);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 28.6, p.left_s);
}

static void test_one_position_uses_its_time_from_the_start(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate(1, 5, 2.0, 4.0, 4.0, 4.0, &p);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 8.0, p.left_s);
}

static void test_left_never_negative_and_zero_at_the_end(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate(39, 40, 0.0, 1.0, 39.0, 60.0, &p);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, p.left_s);
    uwbd_scan_progress_estimate(40, 40, 0.0, 1.0, 40.0, 40.0, &p);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, p.left_s);
    TEST_ASSERT_TRUE(p.has_left);
}

static void test_progress_line(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate(11, 40, 0.0, 10.0, 20.0, 20.04, &p);
    char *line = uwbd_reply_progress(&p);
    TEST_ASSERT_NOT_NULL(line);
    cJSON *o = cJSON_Parse(line);
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_EQUAL_STRING("PROGRESS", cJSON_GetObjectItem(o, "class")->valuestring);
    TEST_ASSERT_EQUAL_INT(11, cJSON_GetObjectItem(o, "position")->valueint);
    TEST_ASSERT_EQUAL_INT(40, cJSON_GetObjectItem(o, "positions")->valueint);
    TEST_ASSERT_EQUAL_DOUBLE(20.0, cJSON_GetObjectItem(o, "elapsed_s")->valuedouble);
    TEST_ASSERT_EQUAL_DOUBLE(29.0, cJSON_GetObjectItem(o, "left_s")->valuedouble);
    cJSON_Delete(o);
    free(line);
    uwbd_scan_progress_estimate(0, 40, 0.0, 0, 0, 1.0, &p);
    line = uwbd_reply_progress(&p);
    o = cJSON_Parse(line);
    TEST_ASSERT_NULL(cJSON_GetObjectItem(o, "left_s"));
    cJSON_Delete(o);
    free(line);
}

/* Issue 31, finding 10: `baseline set 3`, three passes of 10 positions, a
 * position a second and 5 s of homing before each pass. The fraction rises
 * over all 30 positions and is 1 only at the last; the time left counts the
 * passes to come (it was 0 at the end of each pass). */
static void test_passes_make_one_progress(void)
{
    struct uwbd_scan_progress p;
    double last_fraction = -1;
    for (int pass = 1; pass <= 3; pass++) {
        for (int done = 0; done <= 10; done++) {
            double t = (pass - 1) * 15.0 + 5.0 + done; /* 5 s homing, then 1 s a position */
            uwbd_scan_progress_estimate_passes(pass, 3, done, 10, 0.0, 6.0, t, t, &p);
            TEST_ASSERT_EQUAL_INT(pass, p.pass);
            TEST_ASSERT_EQUAL_INT(3, p.passes);
            TEST_ASSERT_TRUE(p.fraction >= last_fraction);
            TEST_ASSERT_EQUAL_INT(pass == 3 && done == 10, p.fraction == 1.0);
            last_fraction = p.fraction;
            if (done == 10 && pass < 3) {
                TEST_ASSERT_TRUE_MESSAGE(p.left_s > 10.0 * (3 - pass) - 1e-9, "time left at a pass's end");
            }
        }
    }
    TEST_ASSERT_EQUAL_DOUBLE(0.0, p.left_s);
    TEST_ASSERT_EQUAL_DOUBLE(45.0, p.elapsed_s);
    /* The end of pass 1: 20 positions left at the pace so far, 1 s. */
    uwbd_scan_progress_estimate_passes(1, 3, 10, 10, 0.0, 6.0, 15.0, 15.0, &p);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 20.0, p.left_s);
    /* Homing of pass 2 counts in the pace: 15 s between its 1st and pass 1's 1st. */
    uwbd_scan_progress_estimate_passes(2, 3, 1, 10, 0.0, 6.0, 21.0, 21.0, &p);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 19.0 * 1.5, p.left_s);

    char *line = uwbd_reply_progress(&p);
    cJSON *o = cJSON_Parse(line);
    TEST_ASSERT_EQUAL_INT(1, cJSON_GetObjectItem(o, "position")->valueint);
    TEST_ASSERT_EQUAL_INT(10, cJSON_GetObjectItem(o, "positions")->valueint);
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetObjectItem(o, "pass")->valueint);
    TEST_ASSERT_EQUAL_INT(3, cJSON_GetObjectItem(o, "passes")->valueint);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.3666, cJSON_GetObjectItem(o, "fraction")->valuedouble);
    cJSON_Delete(o);
    free(line);
    /* One pass: as before, and pass 1 of 1. */
    uwbd_scan_progress_estimate(11, 40, 0.0, 10.0, 20.0, 20.0, &p);
    TEST_ASSERT_EQUAL_INT(1, p.pass);
    TEST_ASSERT_EQUAL_INT(1, p.passes);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 11.0 / 40.0, p.fraction);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_nothing_acquired_has_no_estimate);
    RUN_TEST(test_pace_between_positions_not_homing);
    RUN_TEST(test_one_position_uses_its_time_from_the_start);
    RUN_TEST(test_left_never_negative_and_zero_at_the_end);
    RUN_TEST(test_progress_line);
    RUN_TEST(test_passes_make_one_progress);
    return UNITY_END();
}
