/* Acquiring again within a cycle: averaging weighted by pulses, the spread
 * of commissioning scans, how many more acquisitions bring a verdict's
 * uncertainty under the limit, and the baseline's repeatability in sigma. */
#include "unity.h"

#include <math.h>
#include <string.h>

#include "uwb/compare.h"
#include "daemon/acquire_more.h"

static char err[512];

void setUp(void)
{
}
void tearDown(void)
{
}

static void make(struct uwb_scan *s, float value, int stack)
{
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(s, 3, 8, err, sizeof err));
    s->sample_interval_s = 1e-11;
    s->stack = stack;
    for (int k = 0; k < 3; k++)
        s->antenna_y_m[k] = 0.03 * k;
    for (int i = 0; i < 24; i++)
        s->data[i] = value;
}

static void test_scans_average_weighted_by_their_pulses(void)
{
    struct uwb_scan a, b;
    make(&a, 1.0f, 4);
    make(&b, 4.0f, 12);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_scan_accumulate(&a, &b, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(16, a.stack);
    TEST_ASSERT_EQUAL_FLOAT(3.25f, a.data[0]); /* (4 x 1 + 12 x 4) / 16 */
    TEST_ASSERT_EQUAL_FLOAT(3.25f, a.data[23]);
    b.antenna_y_m[2] = 0.07;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_scan_accumulate(&a, &b, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "position 2"), err);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
}

static void test_spread_is_the_sample_deviation_of_what_was_found(void)
{
    double centres[] = {0.300, 0.302, NAN, 0.304};
    int used = 0;
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.002, uwbd_spread(centres, 4, &used));
    TEST_ASSERT_EQUAL_INT(3, used);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, uwbd_spread(centres, 1, &used));
}

static void test_acquisitions_needed_follow_the_noise_part_alone(void)
{
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    /* 1.2 mm of which 1.0 mm is this scan's noise: 0.66 mm is left, so the
     * noise must fall to 0.75 mm: (1.0 / 0.75)^2 = 1.79 times the pulses. */
    v.current.sigma_center_noise_m = 0.0010;
    v.uncertainty_m = sqrt(0.0012 * 0.0012);
    TEST_ASSERT_EQUAL_INT(1, uwbd_acquisitions_needed(&v, 0.001, 4, 4));  /* 7.1 pulses: one more of 4 */
    TEST_ASSERT_EQUAL_INT(7, uwbd_acquisitions_needed(&v, 0.001, 16, 2)); /* 28.6 pulses: 12.6 more, 7 of 2 */
    v.current.sigma_center_noise_m = 0.0003; /* the rest, 1.16 mm, is over the limit alone */
    TEST_ASSERT_EQUAL_INT(-1, uwbd_acquisitions_needed(&v, 0.001, 4, 4));
    v.current.sigma_center_noise_m = 0.0005;
    v.uncertainty_m = 0.0008;
    TEST_ASSERT_EQUAL_INT(0, uwbd_acquisitions_needed(&v, 0.001, 4, 4));
    v.current.sigma_center_noise_m = 0; /* no term given: all of it taken as noise, 1.44 x the pulses */
    v.uncertainty_m = 0.0012;
    TEST_ASSERT_EQUAL_INT(1, uwbd_acquisitions_needed(&v, 0.001, 4, 4));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_acquisitions_needed(&v, 0.001, 4, 0)); /* no pulses each */
}

/* sigma^2 = 0.5 + 4 / pulses (mm^2): 1.5 at 4 pulses, 1.0 at 8. Under 1.01 mm
 * the 8 are enough; under 0.8 mm it takes 28.6 pulses (0.5 + 4 / P <= 0.64),
 * 6 more acquisitions of 4; under 0.7 mm none can (0.49 < 0.5). */
static void test_acquisitions_needed_from_two_measurements(void)
{
    double s4 = sqrt(0.5 + 4.0 / 4) * 1e-3, s8 = sqrt(0.5 + 4.0 / 8) * 1e-3;
    TEST_ASSERT_EQUAL_INT(0, uwbd_acquisitions_needed_fit(s4, 4, s8, 8, 0.00101, 4));
    TEST_ASSERT_EQUAL_INT(6, uwbd_acquisitions_needed_fit(s4, 4, s8, 8, 0.0008, 4));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_acquisitions_needed_fit(s4, 4, s8, 8, 0.0007, 4));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_acquisitions_needed_fit(s8, 4, s4, 8, 0.001, 4));  /* sigma rose */
    TEST_ASSERT_EQUAL_INT(-1, uwbd_acquisitions_needed_fit(s4, 4, s8, 8, 0.0008, 0)); /* no pulses each */
}

static void test_the_baselines_repeatability_enters_the_uncertainty(void)
{
    struct uwb_compare_options opt;
    uwb_compare_defaults(&opt);
    struct uwb_edges cur, base;
    memset(&cur, 0, sizeof cur);
    cur.found = 1;
    cur.center_m = 0.312;
    cur.sigma_center_noise_m = 0.0003;
    base = cur;
    base.center_m = 0.300;
    struct uwb_verdict without, with;
    memset(&without, 0, sizeof without);
    memset(&with, 0, sizeof with);
    uwb_compare_edges(&without, &cur, &base, &opt);
    opt.baseline_repeatability_m = 0.0004;
    uwb_compare_edges(&with, &cur, &base, &opt);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, sqrt(without.uncertainty_m * without.uncertainty_m + 0.0004 * 0.0004),
                              with.uncertainty_m);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, with.status);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_scans_average_weighted_by_their_pulses);
    RUN_TEST(test_spread_is_the_sample_deviation_of_what_was_found);
    RUN_TEST(test_acquisitions_needed_follow_the_noise_part_alone);
    RUN_TEST(test_acquisitions_needed_from_two_measurements);
    RUN_TEST(test_the_baselines_repeatability_enters_the_uncertainty);
    return UNITY_END();
}
