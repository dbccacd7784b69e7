/* The radial change in the verdict (issue 30): its status joins the
 * axial one, the reason says when it decides, the axial figure is never a
 * confident wrong one on a deformed face, and the verdict's JSON carries
 * the "radial" object as documented. Full-wave fixtures (gprMax): the
 * shared tank's radial scans against its intact scan, and a pure shift. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "scene_support.h"
#include "unity.h"
#include "uwb/evaluate.h"
#include "uwb/verdict_json.h"
#include "uwb/verdict_record.h"

#define TANK_BASE "tests/fixtures/fdtd2d-tank-d+00.0.uwbscan"

void setUp(void)
{
}
void tearDown(void)
{
}

static int emulated(void)
{
    const char *prefix = getenv("UWB_EXEC_PREFIX");
    return prefix && *prefix;
}

static struct uwb_verdict verdict;

static void evaluate(const char *name)
{
    char path[256];
    snprintf(path, sizeof path, "tests/fixtures/%s.uwbscan", name);
    struct uwb_scan cur, base;
    fixture_load_scan(path, &cur);
    fixture_load_scan(TANK_BASE, &base);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    char err[256];
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &verdict, &ca, &ba, err, sizeof err),
                                  err);
    printf("%s: %s (%s); axial %+.2f +- %.2f mm%s; radial %s %+.2f mm at %.0f mm\n", name,
           uwb_status_name(verdict.status), verdict.reason, verdict.axial_displacement_m * 1e3,
           verdict.uncertainty_m * 1e3, verdict.axial_withheld ? " withheld" : "",
           uwb_status_name(verdict.radial.status), verdict.radial.max_change_m * 1e3,
           verdict.radial.at_m * 1e3);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
}

/* Never a confident wrong axial figure: withheld, or within 2 sigma. */
static void assert_axial_honest(double truth_m)
{
    if (verdict.axial_withheld)
        return;
    TEST_ASSERT_TRUE_MESSAGE(fabs(verdict.axial_displacement_m - truth_m) <= 2.0 * verdict.uncertainty_m,
                             "axial figure outside 2 sigma of the truth");
}

static void test_a_bulge_of_4_mm_is_a_radial_watch(void)
{
    evaluate("fdtd2d-tank-radial-r2-4+4-d+00.0");
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_WATCH, verdict.radial.status);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_WATCH, verdict.status);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(verdict.reason, "radial change +", 15), verdict.reason);
    TEST_ASSERT_TRUE(verdict.height_change_withheld[0] != '\0');
    assert_axial_honest(0.0);
}

static void test_a_bulge_of_8_mm_is_a_radial_alarm(void)
{
    evaluate("fdtd2d-tank-radial-r5-7+8-d+00.0");
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, verdict.radial.status);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, verdict.status);
    assert_axial_honest(0.0);
}

static void test_a_dent_reads_negative(void)
{
    evaluate("fdtd2d-tank-radial-r3-5-4-d+00.0");
    TEST_ASSERT_TRUE(verdict.radial.max_change_m < -0.002);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_WATCH, verdict.status);
    assert_axial_honest(0.0);
}

static void test_a_bulge_with_a_rise_gives_no_confident_axial_figure(void)
{
    evaluate("fdtd2d-tank-radial-r4-5+6-d+10.0");
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, verdict.radial.status);
    assert_axial_honest(0.010);
}

static void test_a_pure_shift_is_radially_ok_and_axial_decides(void)
{
    evaluate("fdtd2d-tank-d+10.0");
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_OK, verdict.radial.status);
    TEST_ASSERT_TRUE(fabs(verdict.radial.max_change_m) <= 0.001);
    TEST_ASSERT_FALSE(verdict.axial_withheld);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, verdict.status);
    TEST_ASSERT_EQUAL_STRING("", verdict.reason);
}

/* The tank's winding moved up 30 mm, nothing changed radially: the face's
 * range carries a ripple the tank and the aperture hold in place (it does
 * not move with the winding), which compared row by row along the winding
 * read -1.53 mm at 315 mm and a lean of -1.66 mm. The goal: at
 * most 1 mm. Its tilt goal, 1.5 mm, is missed here (1.96 mm, about
 * 0.065 mm per mm moved on the tank's pure shifts: test_radial_profile);
 * its sigma (over 1 mm at this shift) puts its 95 % interval across the
 * watch limit, so the tilt is withheld with that interval (the decision
 * rule, as for every figure), and no lean grades the status. */
static void test_a_shift_of_30_mm_reads_no_radial_change_and_no_lean(void)
{
    evaluate("fdtd2d-tank-d+30.0");
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_OK, verdict.radial.status);
    TEST_ASSERT_TRUE_MESSAGE(fabs(verdict.radial.max_change_m) <= 0.001, "max_change");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(verdict.radial.tilt_withheld, "across a status limit"),
                                 verdict.radial.tilt_withheld);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, verdict.radial.tilt_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, verdict.radial.tilt_least_m);
}

/* A leaning winding is a deformation like a bulge (issue 45): the shared
 * tank's winding in the simulator, its top 3 or 6 mm nearer and no disk
 * bulged, reads the lean as the tilt and no change (+3.40 and +6.81 mm:
 * make accuracy-radial-limits); a lean past the radial limits grades the
 * radial status and the verdict like a bulge, the reason saying it leans.
 * A pure shift's lean (within 2 sigma of none) stays ok:
 * test_a_shift_of_30_mm_reads_no_radial_change_and_no_lean. */
static void check_lean_grades(const char *tilt_m, enum uwb_status want)
{
    char err[512];
    struct uwb_scan base, cur;
    scene_tank_winding_pair("face_tilt_m", tilt_m, &base, &cur);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &verdict, &ca, &ba, err, sizeof err),
                                  err);
    printf("lean %s m: %s (%s); tilt %+.2f +- %.2f mm; radial %s\n", tilt_m, uwb_status_name(verdict.status),
           verdict.reason, verdict.radial.tilt_m * 1e3, verdict.radial.tilt_uncertainty_m * 1e3,
           uwb_status_name(verdict.radial.status));
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, verdict.radial.status, "radial status");
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, verdict.status, "verdict status");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(verdict.reason, "leans"), verdict.reason);
}

static void test_a_lean_past_the_radial_limits_raises_watch_or_alarm(void)
{
    check_lean_grades("0.003", UWB_STATUS_WATCH);
    check_lean_grades("0.006", UWB_STATUS_ALARM);
}

/* The verdict's JSON: "radial" with the documented keys, read back alike. */
static void test_the_json_carries_the_radial_object(void)
{
    evaluate("fdtd2d-tank-radial-r2-4+4-d+00.0");
    struct uwb_verdict_record *r = malloc(sizeof *r), *back = malloc(sizeof *back);
    TEST_ASSERT_TRUE(r && back);
    uwb_record_from_verdict(r, &verdict);
    char *json = uwb_record_to_json(r);
    TEST_ASSERT_NOT_NULL(json);
    cJSON *o = cJSON_Parse(json);
    const cJSON *radial = cJSON_GetObjectItemCaseSensitive(o, "radial");
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsObject(radial), json);
    static const char *const keys[] = {"max_change_mm", "at_mm",          "from_mm",
                                       "to_mm",         "uncertainty_mm", "tilt_mm"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(radial, keys[i])), keys[i]);
    TEST_ASSERT_EQUAL_STRING("watch", cJSON_GetObjectItemCaseSensitive(radial, "status")->valuestring);
    TEST_ASSERT_NULL_MESSAGE(cJSON_GetObjectItemCaseSensitive(o, "axial_displacement_mm"),
                             "the withheld axial figure is not published");
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_json(json, back, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(r->radial_status, back->radial_status);
    TEST_ASSERT_EQUAL_DOUBLE(r->radial_max_change_mm, back->radial_max_change_mm);
    TEST_ASSERT_EQUAL_DOUBLE(r->radial_from_mm, back->radial_from_mm);
    TEST_ASSERT_EQUAL_INT(r->radial_has_span, back->radial_has_span);
    cJSON_Delete(o);
    free(json);
    free(r);
    free(back);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_bulge_of_4_mm_is_a_radial_watch);
    RUN_TEST(test_the_json_carries_the_radial_object);
    RUN_TEST(test_a_lean_past_the_radial_limits_raises_watch_or_alarm);
    if (!emulated()) {
        RUN_TEST(test_a_bulge_of_8_mm_is_a_radial_alarm);
        RUN_TEST(test_a_dent_reads_negative);
        RUN_TEST(test_a_bulge_with_a_rise_gives_no_confident_axial_figure);
        RUN_TEST(test_a_pure_shift_is_radially_ok_and_axial_decides);
        RUN_TEST(test_a_shift_of_30_mm_reads_no_radial_change_and_no_lean);
    }
    return UNITY_END();
}
