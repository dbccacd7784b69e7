/* Scan progress and its time-left estimate (src/daemon/scan_progress.c). */
#include "unity.h"

#include <cjson/cJSON.h>
#include <stdlib.h>

#include "daemon/scan_progress.h"

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

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_nothing_acquired_has_no_estimate);
    RUN_TEST(test_pace_between_positions_not_homing);
    RUN_TEST(test_one_position_uses_its_time_from_the_start);
    RUN_TEST(test_left_never_negative_and_zero_at_the_end);
    RUN_TEST(test_progress_line);
    return UNITY_END();
}
