/* The full-wave tank family (tests/fixtures/fdtd2d-var-*, fdtd3d-var-*:
 * randomly drawn tanks with a barrier, a core leg and clamp plates, true
 * oil eps_r off the header's), noiseless, default settings: the winding's
 * face is the same reflector in both scans of a pair, and each pair gives a
 * figure within 0.25 mm and 2 sigma of the truth or is inconclusive with a
 * reason, never a confident wrong figure. The truth files are read here, by
 * the test, never by the processing. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwb/analysis.h"
#include "uwb/evaluate.h"

#define FIXTURE(name) "tests/fixtures/" name ".uwbscan"

void setUp(void)
{
}

void tearDown(void)
{
}

struct replayed {
    struct uwb_verdict v;
    double true_mm, error_mm;
};

static void replay(const char *base_path, const char *cur_path, struct replayed *r)
{
    struct uwb_scan base, cur;
    struct fixture_truth bt, ct;
    fixture_load_scan(base_path, &base);
    fixture_load_scan(cur_path, &cur);
    fixture_load_truth(base_path, &bt);
    fixture_load_truth(cur_path, &ct);
    r->true_mm = 1e3 * (0.5 * (ct.y1_m + ct.y2_m) - 0.5 * (bt.y1_m + bt.y2_m));
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    char err[256];
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &r->v, &ca, &ba, err, sizeof err), err);
    r->error_mm = r->v.axial_displacement_m * 1e3 - r->true_mm;
    printf("%s: true %+.2f mm, read %+.2f mm, sigma %.2f mm, %s %s\n", cur_path, r->true_mm,
           r->v.axial_displacement_m * 1e3, r->v.uncertainty_m * 1e3, uwb_status_name(r->v.status),
           r->v.reason);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
}

/* A figure given is right: within `limit_mm` and 2 sigma of the truth. */
static void assert_right(const struct replayed *r, double limit_mm)
{
    char msg[400];
    snprintf(msg, sizeof msg, "read %+.2f mm for %+.2f mm, sigma %.2f mm", r->v.axial_displacement_m * 1e3,
             r->true_mm, r->v.uncertainty_m * 1e3);
    TEST_ASSERT_TRUE_MESSAGE(fabs(r->error_mm) <= limit_mm, msg);
    TEST_ASSERT_TRUE_MESSAGE(fabs(r->error_mm) <= 2.0 * r->v.uncertainty_m * 1e3, msg);
}

/* Each pair (baseline, moved) gives a figure, right within `limit_mm` and
 * 2 sigma. */
static void assert_pairs_give_right_figures(const char *const pairs[][2], size_t n, double limit_mm)
{
    for (size_t i = 0; i < n; i++) {
        struct replayed r;
        replay(pairs[i][0], pairs[i][1], &r);
        char msg[400];
        snprintf(msg, sizeof msg, "%s: %s", pairs[i][1], r.v.reason);
        TEST_ASSERT_NOT_EQUAL_MESSAGE(UWB_STATUS_INCONCLUSIVE, r.v.status, msg);
        assert_right(&r, limit_mm);
    }
}

/* Tank 1: a plate 70 mm in front of the face; its edge passes the coarse
 * search, its fine profile runs past the travel. The winding behind it was
 * not measured (inconclusive) until the search went on to the next
 * reflector. */
static void test_family_tank_behind_a_plate_edge_gets_a_right_figure(void)
{
    struct replayed r;
    replay(FIXTURE("fdtd2d-var-s01-d+00"), FIXTURE("fdtd2d-var-s01-d+02"), &r);
    TEST_ASSERT_NOT_EQUAL_MESSAGE(UWB_STATUS_INCONCLUSIVE, r.v.status, r.v.reason);
    assert_right(&r, 0.25);
}

/* 3-D tank 12: the plate below the winding was taken for the winding in the
 * moved scan, the winding in the baseline: -46.37 +- 0.14 mm, alarm, for a
 * true +7.5 mm. Now a right figure or withheld with a reason; right on the
 * 3-D tanks is within 2 sigma (issue 45's goal for them; the plate's edge
 * in the face's column reads +6.96 +- 0.57 mm), and within 1 mm. */
static void test_3d_tank_with_plate_below_is_right_or_withheld(void)
{
    struct replayed r;
    replay(FIXTURE("fdtd3d-var-s012-d+00"), FIXTURE("fdtd3d-var-s012-d+10"), &r);
    if (r.v.status == UWB_STATUS_INCONCLUSIVE) {
        TEST_ASSERT_TRUE_MESSAGE(strlen(r.v.reason) > 0, "inconclusive without a reason");
        return;
    }
    assert_right(&r, 1.0);
}

/* 3-D tank 12 moved -20 mm: both scans' faces are taken level with a steel
 * plate's front edge, and no shift within the fit's search maps one profile
 * onto the other: the fit ran to the edge of its search and read -10.25 +-
 * 0.10 mm, alarm, for a true -20 mm. Right within 2 sigma, or withheld with
 * a reason. */
static void test_3d_tank_whose_fit_finds_no_best_is_right_or_withheld(void)
{
    struct replayed r;
    replay(FIXTURE("fdtd3d-var-s012-d+00"), FIXTURE("fdtd3d-var-s012-d-20"), &r);
    if (r.v.status == UWB_STATUS_INCONCLUSIVE) {
        TEST_ASSERT_TRUE_MESSAGE(strlen(r.v.reason) > 0, "inconclusive without a reason");
        return;
    }
    assert_right(&r, 0.5);
}

/* Three more drawn tanks, every pair (a clamp plate above or below, a
 * squeezed spacer in one of each tank's two): a figure lies within 2 sigma
 * of the truth. Before the displacement's floor was the family's scatter
 * (it was the first tank's alone, 0.1 mm), four of these six read 2.2-5.0
 * sigma off: s04 +26 -0.50, s07 +14 -0.43, s07 -2 +0.24, s08 +2 +0.22 mm. */
static void test_family_figures_lie_within_two_sigma(void)
{
    static const char *const pairs[][2] = {
        {FIXTURE("fdtd2d-var-s04-d+00"), FIXTURE("fdtd2d-var-s04-d+26")},
        {FIXTURE("fdtd2d-var-s04-d+00"), FIXTURE("fdtd2d-var-s04-d-10")},
        {FIXTURE("fdtd2d-var-s07-d+00"), FIXTURE("fdtd2d-var-s07-d+14")},
        {FIXTURE("fdtd2d-var-s07-d+00"), FIXTURE("fdtd2d-var-s07-d-02")},
        {FIXTURE("fdtd2d-var-s08-d+00"), FIXTURE("fdtd2d-var-s08-d+02")},
        {FIXTURE("fdtd2d-var-s08-d+00"), FIXTURE("fdtd2d-var-s08-d+14")},
    };
    int figures = 0;
    for (size_t i = 0; i < sizeof pairs / sizeof pairs[0]; i++) {
        struct replayed r;
        replay(pairs[i][0], pairs[i][1], &r);
        if (r.v.status == UWB_STATUS_INCONCLUSIVE) {
            TEST_ASSERT_TRUE_MESSAGE(strlen(r.v.reason) > 0, "inconclusive without a reason");
            continue;
        }
        figures++;
        /* Within 2 sigma; 0.25 mm is the goal, not met by all. */
        assert_right(&r, INFINITY);
        /* No blanket inflation: sigma under max(0.5 mm, 8 % of the move),
         * its share of the move included (issue 44). */
        TEST_ASSERT_TRUE_MESSAGE(r.v.uncertainty_m * 1e3 < fmax(0.5, 0.08 * fabs(r.true_mm)), pairs[i][1]);
    }
    TEST_ASSERT_EQUAL_INT(6, figures);
}

/* One scan read on its own finds its winding: the face's range and both
 * ends within 10 mm of the truth's. */
static void assert_winding_found(const char *path)
{
    struct uwb_scan scan;
    struct fixture_truth t;
    fixture_load_scan(path, &scan);
    fixture_load_truth(path, &t);
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis a;
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_analyse_scan(&scan, &opt, &a, err, sizeof err), err);
    TEST_ASSERT_TRUE_MESSAGE(a.edges.found, a.edges.reason);
    char msg[200];
    snprintf(msg, sizeof msg, "face at %.3f m, %.3f..%.3f m; truth %.3f m, %.3f..%.3f m", a.edges.face_z_m,
             a.edges.lower_m, a.edges.upper_m, t.z_face_m, t.y1_m, t.y2_m);
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.010, t.z_face_m, a.edges.face_z_m, msg);
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.010, t.y1_m, a.edges.lower_m, msg);
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.010, t.y2_m, a.edges.upper_m, msg);
    uwb_analysis_free(&a);
    uwb_scan_free(&scan);
}

/* Tank 5: clamp plates above and below the winding, their front edges
 * 110 mm nearer than the face and in the search within 10 dB of it. Taken
 * as the nearest bright reflector, the lower plate's edge was the moved
 * scan's face (its edges 111..196 mm); it is a point, which the winding is
 * not. Read on its own, the moved scan finds the winding. */
static void test_family_plate_edge_is_passed_over_for_the_winding(void)
{
    assert_winding_found(FIXTURE("fdtd2d-var-s05-d+14"));
}

/* A 3-D tank drawn here (tools/fdtd/draw_tank3d.py, seed 201): its upper
 * plate's front edge, 10 mm in front of the face and 150 mm above the
 * winding's top, outshines the face in the face's range column, and its
 * blur runs past the travel's end (the plate 15 mm below it): the column
 * was rejected whole, and the winding "not found" for a point at 0.506 m. */
static void test_3d_face_beside_a_plate_edge_past_the_travel_is_found(void)
{
    assert_winding_found(FIXTURE("fdtd3d-fresh-s201-d+00"));
}

/* ...and its baseline, at the face's range, is brightest beyond the
 * winding's top, where the upper plate meets the winding's end ring: the
 * edges would be that corner's. The pair is inconclusive, and the reason
 * says what outshines the winding and where (it said "edge outside the
 * seen aperture", true of the corner, not of the winding). */
static void test_family_corner_level_with_the_face_is_named(void)
{
    struct replayed r;
    replay(FIXTURE("fdtd2d-var-s05-d+00"), FIXTURE("fdtd2d-var-s05-d+14"), &r);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_STATUS_INCONCLUSIVE, r.v.status, r.v.reason);
    const char *at = strstr(r.v.reason, "a reflector level with the face outshines the winding");
    TEST_ASSERT_NOT_NULL_MESSAGE(at, r.v.reason);
    const char *height = strstr(at, "the brightest height is ");
    TEST_ASSERT_NOT_NULL_MESSAGE(height, r.v.reason);
    struct fixture_truth t;
    fixture_load_truth(FIXTURE("fdtd2d-var-s05-d+00"), &t);
    double height_mm = 0.0;
    TEST_ASSERT_EQUAL_INT(1, sscanf(height + strlen("the brightest height is "), "%lf", &height_mm));
    /* Above the winding's top by more than a disk. */
    TEST_ASSERT_TRUE_MESSAGE(height_mm > t.y2_m * 1e3 + 50.0, r.v.reason);
}

/* Fresh draws (tests/fixtures/fdtd2d-fresh-*: tanks of the family's kind
 * drawn by tools/fdtd/draw_tank.py and simulated with gprMax after every
 * constant here was set, none tuned to them). The 14 pairs of 20 that
 * read within 2 sigma stay there (s104 +2 and s106 +4, a plate taken out
 * beside the winding, 0.03 and 0.14 mm off at the least sigma). The README's
 * "Fresh draws" lists the ones that do not (a clamp plate protruding in
 * front of the face near a winding's end: 0.7-3.3 mm off at 2.4-11 sigma),
 * an open bug of issue 28, not held here. s108 -24 (0.71 mm off) was
 * within 2 sigma only while a false lean of 2.02 mm widened its sigma. */
static void test_fresh_draws_that_read_right_stay_right(void)
{
    static const char *const pairs[][2] = {
        {FIXTURE("fdtd2d-fresh-s101-d+00"), FIXTURE("fdtd2d-fresh-s101-d+08")},
        {FIXTURE("fdtd2d-fresh-s101-d+00"), FIXTURE("fdtd2d-fresh-s101-d+14")},
        {FIXTURE("fdtd2d-fresh-s103-d+00"), FIXTURE("fdtd2d-fresh-s103-d+06")},
        {FIXTURE("fdtd2d-fresh-s103-d+00"), FIXTURE("fdtd2d-fresh-s103-d+28")},
        {FIXTURE("fdtd2d-fresh-s104-d+00"), FIXTURE("fdtd2d-fresh-s104-d+02")},
        {FIXTURE("fdtd2d-fresh-s104-d+00"), FIXTURE("fdtd2d-fresh-s104-d+16")},
        {FIXTURE("fdtd2d-fresh-s106-d+00"), FIXTURE("fdtd2d-fresh-s106-d+04")},
        {FIXTURE("fdtd2d-fresh-s107-d+00"), FIXTURE("fdtd2d-fresh-s107-d+04")},
        {FIXTURE("fdtd2d-fresh-s107-d+00"), FIXTURE("fdtd2d-fresh-s107-d-08")},
        {FIXTURE("fdtd2d-fresh-s108-d+00"), FIXTURE("fdtd2d-fresh-s108-d+02")},
        {FIXTURE("fdtd2d-fresh-s109-d+00"), FIXTURE("fdtd2d-fresh-s109-d+20")},
        {FIXTURE("fdtd2d-fresh-s109-d+00"), FIXTURE("fdtd2d-fresh-s109-d-24")},
        {FIXTURE("fdtd2d-fresh-s110-d+00"), FIXTURE("fdtd2d-fresh-s110-d+12")},
        {FIXTURE("fdtd2d-fresh-s110-d+00"), FIXTURE("fdtd2d-fresh-s110-d-14")},
        /* Drawn after the axial model term was set (0.1-0.4 sigma off). */
        {FIXTURE("fdtd2d-fresh-s111-d+00"), FIXTURE("fdtd2d-fresh-s111-d-12")},
        {FIXTURE("fdtd2d-fresh-s111-d+00"), FIXTURE("fdtd2d-fresh-s111-d-30")},
        {FIXTURE("fdtd2d-fresh-s112-d+00"), FIXTURE("fdtd2d-fresh-s112-d+10")},
        {FIXTURE("fdtd2d-fresh-s112-d+00"), FIXTURE("fdtd2d-fresh-s112-d+14")},
        {FIXTURE("fdtd2d-fresh-s113-d+00"), FIXTURE("fdtd2d-fresh-s113-d-20")},
        {FIXTURE("fdtd2d-fresh-s114-d+00"), FIXTURE("fdtd2d-fresh-s114-d+08")},
        {FIXTURE("fdtd2d-fresh-s114-d+00"), FIXTURE("fdtd2d-fresh-s114-d+20")},
    };
    /* Within 2 sigma; 0.25 mm, the goal, is not met by all. */
    assert_pairs_give_right_figures(pairs, sizeof pairs / sizeof pairs[0], INFINITY);
}

/* The controls: tanks s102 and s105, whose moves read 1.5-3.3 mm off with
 * their clamp plates (s102: 96 mm below and 140 mm above the disks, their
 * fronts 102 and 122 mm in front of the face; s105: 218 mm above, 56 mm
 * in front), simulated again without the plates: +30 and -24 mm read
 * right. What moves the figure there is the plates, not the winding's
 * own image. */
static void test_fresh_tanks_without_their_plates_read_right(void)
{
    static const char *const pairs[][2] = {
        {FIXTURE("fdtd2d-fresh-s102-noplate-d+00"), FIXTURE("fdtd2d-fresh-s102-noplate-d+30")},
        {FIXTURE("fdtd2d-fresh-s105-noplate-d+00"), FIXTURE("fdtd2d-fresh-s105-noplate-d-24")},
    };
    assert_pairs_give_right_figures(pairs, sizeof pairs / sizeof pairs[0], 0.25);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_family_tank_behind_a_plate_edge_gets_a_right_figure);
    RUN_TEST(test_3d_tank_with_plate_below_is_right_or_withheld);
    RUN_TEST(test_3d_tank_whose_fit_finds_no_best_is_right_or_withheld);
    RUN_TEST(test_family_figures_lie_within_two_sigma);
    RUN_TEST(test_family_plate_edge_is_passed_over_for_the_winding);
    RUN_TEST(test_3d_face_beside_a_plate_edge_past_the_travel_is_found);
    RUN_TEST(test_family_corner_level_with_the_face_is_named);
    RUN_TEST(test_fresh_draws_that_read_right_stay_right);
    RUN_TEST(test_fresh_tanks_without_their_plates_read_right);
    return UNITY_END();
}
