/* The imaging core against full-wave FDTD scans of the paper's experiment:
 * a solver that shares nothing with ours, with the true edges known. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwb/evaluate.h"

static struct uwb_scan intact, up20;
static struct fixture_truth truth_intact, truth_up20;

void setUp(void)
{
    fixture_load_scan(FIXTURE_INTACT, &intact);
    fixture_load_scan(FIXTURE_UP20, &up20);
    fixture_load_truth(FIXTURE_INTACT, &truth_intact);
    fixture_load_truth(FIXTURE_UP20, &truth_up20);
}

void tearDown(void)
{
    uwb_scan_free(&intact);
    uwb_scan_free(&up20);
}

static void evaluate(enum uwb_migration_kind kind, const struct uwb_scan *cur, const struct uwb_scan *base,
                     struct uwb_verdict *v)
{
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    opt.analysis.migration = kind;
    struct uwb_analysis a, b;
    char err[512];
    struct uwb_baseline_record rec = {.scan = base};
    if (uwb_evaluate(cur, base ? &rec : NULL, &opt, v, &a, &b, err, sizeof err) != 0)
        TEST_FAIL_MESSAGE(err);
    uwb_analysis_free(&a);
    uwb_analysis_free(&b);
}

static void check_edges(const struct uwb_edges *e, const struct fixture_truth *t)
{
    TEST_ASSERT_TRUE_MESSAGE(e->found, e->reason);
    TEST_ASSERT_DOUBLE_WITHIN(0.002, t->y1_m, e->lower_m);
    TEST_ASSERT_DOUBLE_WITHIN(0.002, t->y2_m, e->upper_m);
    TEST_ASSERT_DOUBLE_WITHIN(0.002, 0.5 * (t->y1_m + t->y2_m), e->center_m);
    /* The face range is found without being told (a wavelength is 150 mm). */
    TEST_ASSERT_DOUBLE_WITHIN(0.01, t->z_face_m, e->face_z_m);
}

static void displacement_case(enum uwb_migration_kind kind)
{
    struct uwb_verdict v;
    evaluate(kind, &up20, &intact, &v);
    check_edges(&v.current, &truth_up20);
    check_edges(&v.baseline, &truth_intact);
    TEST_ASSERT_DOUBLE_WITHIN(0.0005, truth_up20.displacement_mm * 1e-3, v.axial_displacement_m);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, v.status);
    /* Honest uncertainty: the true error lies inside two sigma. */
    double error = fabs(v.axial_displacement_m - truth_up20.displacement_mm * 1e-3);
    TEST_ASSERT_TRUE(error <= 2.0 * v.uncertainty_m);
    /* ...and no wider than the share of the move allows (issue 44). */
    TEST_ASSERT_TRUE(v.uncertainty_m < fmax(0.0005, 0.08 * fabs(truth_up20.displacement_mm * 1e-3)));
}

static void test_fdtd_displacement_fixed_point(void)
{
    displacement_case(UWB_MIGRATE_FIXED);
}
static void test_fdtd_displacement_float(void)
{
    displacement_case(UWB_MIGRATE_FLOAT);
}

static void test_fdtd_moving_down_reads_negative(void)
{
    struct uwb_verdict v;
    evaluate(UWB_MIGRATE_FIXED, &intact, &up20, &v);
    TEST_ASSERT_DOUBLE_WITHIN(0.0005, -truth_up20.displacement_mm * 1e-3, v.axial_displacement_m);
}

static void test_fdtd_same_scan_is_ok_and_zero(void)
{
    struct uwb_verdict v;
    evaluate(UWB_MIGRATE_FIXED, &intact, &intact, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_OK, v.status);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 0.0, v.axial_displacement_m);
}

static void test_fdtd_edges_without_baseline(void)
{
    struct uwb_verdict v;
    evaluate(UWB_MIGRATE_FIXED, &intact, NULL, &v);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_EDGES, v.status);
    check_edges(&v.current, &truth_intact);
}

/* A time-zero error moves everything in range, barely in height. */
static void test_time_zero_offset_moves_range_not_height(void)
{
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    opt.analysis.time_zero_offset_s = 100e-12;
    struct uwb_verdict v;
    struct uwb_analysis a, b;
    char err[512];
    struct uwb_baseline_record rec = {.scan = &intact};
    TEST_ASSERT_EQUAL_INT(0, uwb_evaluate(&up20, &rec, &opt, &v, &a, &b, err, sizeof err));
    /* Sample 0 taken as 100 ps later: every echo looks 15 mm farther. */
    TEST_ASSERT_DOUBLE_WITHIN(0.004, truth_up20.z_face_m + 0.015, v.current.face_z_m);
    TEST_ASSERT_DOUBLE_WITHIN(0.0005, 0.020, v.axial_displacement_m);
    uwb_analysis_free(&a);
    uwb_analysis_free(&b);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_fdtd_displacement_fixed_point);
    RUN_TEST(test_fdtd_displacement_float);
    RUN_TEST(test_fdtd_moving_down_reads_negative);
    RUN_TEST(test_fdtd_same_scan_is_ok_and_zero);
    RUN_TEST(test_fdtd_edges_without_baseline);
    RUN_TEST(test_time_zero_offset_moves_range_not_height);
    return UNITY_END();
}
