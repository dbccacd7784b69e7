/* The evaluation's policy against a baseline, which the daemon and
 * `uwbd --replay` share (issue 18, item 1): time zero must be found and
 * must not have moved past the tolerance since the one recorded with the
 * baseline, or the scan is not compared; a time zero not recorded is
 * measured on the baseline scan; the repeatability recorded with a
 * baseline of N scans enters the uncertainty as spread / sqrt(N). */
#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwb/direct_coupling.h"
#include "uwb/evaluate.h"
#include "uwb/verdict_json.h"

static struct uwb_scan intact, up20;
static struct uwb_evaluate_options opt;
static double intact_arrival_s;

void setUp(void)
{
    fixture_load_scan(FIXTURE_INTACT, &intact);
    fixture_load_scan(FIXTURE_UP20, &up20);
    uwb_evaluate_defaults(&opt);
    char why[200];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0,
                                  uwb_direct_coupling_arrival(&intact, opt.direct_coupling.window_end_s,
                                                              &intact_arrival_s, why, sizeof why),
                                  why);
}

void tearDown(void)
{
    uwb_scan_free(&intact);
    uwb_scan_free(&up20);
}

static void evaluate(const struct uwb_baseline_record *rec, struct uwb_verdict *v)
{
    struct uwb_analysis a, b;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&up20, rec, &opt, v, &a, &b, err, sizeof err), err);
    uwb_analysis_free(&a);
    uwb_analysis_free(&b);
}

static cJSON *as_json(const struct uwb_verdict *v)
{
    cJSON *o = uwb_verdict_object(v);
    TEST_ASSERT_NOT_NULL(o);
    return o;
}

static void test_a_time_zero_moved_past_the_tolerance_is_not_compared(void)
{
    /* Recorded 40 ps later than this scan's: twice the default 20 ps. */
    struct uwb_baseline_record rec = {
        .scan = &intact, .has_direct_coupling = 1, .direct_coupling_s = intact_arrival_s + 40e-12};
    struct uwb_verdict v;
    evaluate(&rec, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_INCONCLUSIVE, v.status);
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(v.reason, "direct coupling moved -40 ps since the baseline (tolerance 20 ps)"), v.reason);
    cJSON *o = as_json(&v);
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(o, "axial_displacement_mm"));
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(o, "baseline"));
    TEST_ASSERT_DOUBLE_WITHIN(0.05, -40.0,
                              cJSON_GetObjectItemCaseSensitive(o, "direct_coupling_shift_ps")->valuedouble);
    TEST_ASSERT_TRUE(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(o, "lower_edge_mm")));
    cJSON_Delete(o);

    /* A wider tolerance (direct_coupling.tolerance_ps) lets the same pair be compared. */
    opt.direct_coupling.tolerance_s = 50e-12;
    evaluate(&rec, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, v.status);
}

static void test_a_time_zero_within_the_tolerance_is_compared(void)
{
    struct uwb_baseline_record rec = {
        .scan = &intact, .has_direct_coupling = 1, .direct_coupling_s = intact_arrival_s - 5e-12};
    struct uwb_verdict v;
    evaluate(&rec, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, v.status);
    TEST_ASSERT_TRUE(v.has_direct_coupling_shift);
    TEST_ASSERT_DOUBLE_WITHIN(1e-13, 5e-12, v.direct_coupling_shift_s);
    TEST_ASSERT_DOUBLE_WITHIN(0.0005, 0.020, v.axial_displacement_m);
}

static void test_a_time_zero_not_recorded_is_measured_on_the_baseline(void)
{
    struct uwb_baseline_record rec = {.scan = &intact};
    struct uwb_verdict v;
    evaluate(&rec, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, v.status);
    TEST_ASSERT_TRUE(v.has_direct_coupling && v.has_direct_coupling_shift);
    TEST_ASSERT_DOUBLE_WITHIN(1e-13, 0.0, v.direct_coupling_shift_s);

    /* Without a baseline: the arrival alone, no shift. */
    evaluate(NULL, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_EDGES, v.status);
    TEST_ASSERT_TRUE(v.has_direct_coupling);
    TEST_ASSERT_FALSE(v.has_direct_coupling_shift);
}

/* A shift a hair under zero is printed 0, not -0. */
static void test_a_shift_that_rounds_to_zero_prints_as_zero(void)
{
    struct uwb_baseline_record rec = {
        .scan = &intact, .has_direct_coupling = 1, .direct_coupling_s = intact_arrival_s + 0.01e-12};
    struct uwb_verdict v;
    evaluate(&rec, &v);
    TEST_ASSERT_TRUE(v.direct_coupling_shift_s < 0);
    char *text = uwb_verdict_to_json(&v);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"direct_coupling_shift_ps\":0,"), text);
    cJSON_free(text);
}

static void test_a_scan_without_a_direct_coupling_is_not_compared(void)
{
    /* Nothing but a constant in the direct-coupling window: a disconnected cable. */
    int n = (int)((opt.direct_coupling.window_end_s - up20.t0_s) / up20.sample_interval_s) + 1;
    for (int k = 0; k < up20.positions; k++)
        for (int i = 0; i < n && i < up20.samples; i++)
            up20.data[(size_t)k * up20.samples + i] = 0.0f;
    struct uwb_baseline_record rec = {.scan = &intact};
    struct uwb_verdict v;
    evaluate(&rec, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_INCONCLUSIVE, v.status);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(v.reason, "direct coupling not found in this scan"), v.reason);
    TEST_ASSERT_FALSE(v.has_direct_coupling);
}

static void test_the_recorded_repeatability_adds_spread_over_root_n(void)
{
    /* The sum in quadrature alone: the least sigma (0.3 mm) is above the
     * noiseless pair's own terms (0.1 mm) and would hide them. */
    opt.compare.least_displacement_uncertainty_m = 0.0;
    struct uwb_baseline_record rec = {.scan = &intact};
    struct uwb_verdict plain, repeat;
    evaluate(&rec, &plain);
    rec.has_repeatability = 1;
    rec.repeatability_m = 0.0008;
    rec.scans = 4; /* the mean of 4 carries 0.4 mm */
    evaluate(&rec, &repeat);
    double want = sqrt(plain.uncertainty_m * plain.uncertainty_m + 0.0004 * 0.0004);
    TEST_ASSERT_DOUBLE_WITHIN(1e-7, want, repeat.uncertainty_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, plain.axial_displacement_m, repeat.axial_displacement_m);
}

/* The least sigma: a noiseless pair whose terms sum to 0.1 mm reads 0.3;
 * a repeatability that takes the sum past it is carried whole. */
static void test_no_sigma_is_given_under_the_least(void)
{
    /* The floor alone: the share of the move (1.2 mm on this 20 mm pair)
     * would lift the sum past it. */
    opt.compare.axial_sigma_per_shift = 0.0;
    struct uwb_baseline_record rec = {.scan = &intact};
    struct uwb_verdict plain, repeat;
    evaluate(&rec, &plain);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, opt.compare.least_displacement_uncertainty_m, plain.uncertainty_m);
    TEST_ASSERT_TRUE(plain.uncertainty_noise_m < plain.uncertainty_m);
    rec.has_repeatability = 1;
    rec.repeatability_m = 0.0008;
    rec.scans = 1;
    evaluate(&rec, &repeat);
    TEST_ASSERT_TRUE(repeat.uncertainty_m >= 0.0008);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_time_zero_moved_past_the_tolerance_is_not_compared);
    RUN_TEST(test_a_time_zero_within_the_tolerance_is_compared);
    RUN_TEST(test_a_time_zero_not_recorded_is_measured_on_the_baseline);
    RUN_TEST(test_a_shift_that_rounds_to_zero_prints_as_zero);
    RUN_TEST(test_a_scan_without_a_direct_coupling_is_not_compared);
    RUN_TEST(test_the_recorded_repeatability_adds_spread_over_root_n);
    RUN_TEST(test_no_sigma_is_given_under_the_least);
    return UNITY_END();
}
