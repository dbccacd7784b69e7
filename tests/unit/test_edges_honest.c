/* The published edges are honest (issue 44, item 2): on every noiseless
 * full-wave pair of the fixtures (the paper's, the tank's, its radial
 * deformations, the family's members and the fresh draws, the 3-D tanks),
 * each edge published, this scan's and the baseline's, lies within 2
 * sigma (edge_uncertainty_mm) of the truth, and this scan's edges are
 * withheld, with why, where no displacement was read on its face: a
 * deformed face (disks 4-5 of the tank bulged 6 mm read the lower edge
 * 10 mm off at sigma 4.8), a face no baseline confirms (the 3-D tanks:
 * 120-160 mm off at sigma 6-7). Before, fresh s108 -24 read its lower
 * edge 7.7 mm off at sigma 3.6 and the 3-D scans' edges were published. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fixture_support.h"
#include "unity.h"
#include <stdlib.h>

#include "uwb/evaluate.h"
#include "uwb/verdict_json.h"
#include "uwb/verdict_record.h"

void setUp(void)
{
}
void tearDown(void)
{
}

/* The baseline of a moved fixture: its tank's intact scan. */
static void baseline_of(const char *moved, char *base, size_t n)
{
    if (strstr(moved, "fdtd2d-paper-")) {
        snprintf(base, n, "%s", FIXTURE_INTACT);
        return;
    }
    if (strstr(moved, "fdtd2d-tank-") || strstr(moved, "fdtd2d-tankfresh-")) {
        snprintf(base, n, "tests/fixtures/fdtd2d-tank-d+00.0.uwbscan");
        return;
    }
    if (strstr(moved,
               "fdtd2d-paperscene-")) { /* the paper's scene deformed: its intact scan is the shared one */
        snprintf(base, n, "%s", FIXTURE_INTACT);
        return;
    }
    /* NAME-dSHIFT.uwbscan, or a fresh draw deformed: NAME-leanMM, NAME-rFROM-TO... */
    const char *kind = strstr(moved, "-lean");
    if (!kind && strstr(moved, "fdtd2d-fresh-s"))
        kind = strstr(strstr(moved, "fdtd2d-fresh-s") + 14, "-r");
    if (kind) {
        snprintf(base, n, "%.*s-d+00.uwbscan", (int)(kind - moved), moved);
        return;
    }
    const char *d = strrchr(moved, 'd');
    snprintf(base, n, "%.*sd+00.uwbscan", (int)(d - moved), moved);
}

static int intact(const char *path)
{
    return strstr(path, "-d+00.uwbscan") || strstr(path, "-d+00.0.uwbscan") ||
           strstr(path, "-intact.uwbscan");
}

static int within(double read_mm, double truth_m, double sigma_mm)
{
    return fabs(read_mm - truth_m * 1e3) <= 2.0 * sigma_mm;
}

static void test_every_edge_published_lies_within_two_sigma(void)
{
    glob_t g;
    TEST_ASSERT_EQUAL_INT(0, glob("tests/fixtures/fdtd*.uwbscan", 0, NULL, &g));
    int pairs = 0, published = 0, withheld_3d = 0;
    for (size_t i = 0; i < g.gl_pathc; i++) {
        const char *moved = g.gl_pathv[i];
        if (intact(moved))
            continue;
        char base_path[512];
        baseline_of(moved, base_path, sizeof base_path);
        struct uwb_scan cur, base;
        struct fixture_truth tc, tb;
        fixture_load_scan(moved, &cur);
        fixture_load_scan(base_path, &base);
        fixture_load_truth(moved, &tc);
        fixture_load_truth(base_path, &tb);
        struct uwb_evaluate_options opt;
        uwb_evaluate_defaults(&opt);
        struct uwb_analysis ca, ba;
        struct uwb_verdict v;
        char err[512];
        struct uwb_baseline_record rec = {.scan = &base};
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, sizeof err), err);
        struct uwb_verdict_record r;
        uwb_record_from_verdict(&r, &v);
        pairs++;
        char msg[768];
        snprintf(msg, sizeof msg,
                 "%s: edges %.1f..%.1f (truth %.1f..%.1f), baseline %.1f..%.1f (truth %.1f..%.1f), "
                 "sigma %.2f mm",
                 moved, r.lower_edge_mm, r.upper_edge_mm, tc.y1_m * 1e3, tc.y2_m * 1e3,
                 r.baseline_lower_edge_mm, r.baseline_upper_edge_mm, tb.y1_m * 1e3, tb.y2_m * 1e3,
                 r.edge_uncertainty_mm);
        printf("%s%s%s\n", msg, r.edges_withheld[0] ? "; withheld: " : "", r.edges_withheld);
        if (r.has_edges) {
            published++;
            TEST_ASSERT_TRUE_MESSAGE(within(r.lower_edge_mm, tc.y1_m, r.edge_uncertainty_mm), msg);
            TEST_ASSERT_TRUE_MESSAGE(within(r.upper_edge_mm, tc.y2_m, r.edge_uncertainty_mm), msg);
            TEST_ASSERT_TRUE_MESSAGE(within(r.center_mm, 0.5 * (tc.y1_m + tc.y2_m), r.edge_uncertainty_mm),
                                     msg);
            if (r.has_baseline) {
                TEST_ASSERT_TRUE_MESSAGE(within(r.baseline_lower_edge_mm, tb.y1_m, r.edge_uncertainty_mm),
                                         msg);
                TEST_ASSERT_TRUE_MESSAGE(within(r.baseline_upper_edge_mm, tb.y2_m, r.edge_uncertainty_mm),
                                         msg);
            }
        } else if (v.current.found) {
            TEST_ASSERT_TRUE_MESSAGE(r.edges_withheld[0] != '\0', msg);
            /* As published (JSON and back): the reason stays, and where the
             * pair was compared, why its height change is not given. */
            char *json = uwb_record_to_json(&r);
            struct uwb_verdict_record back;
            TEST_ASSERT_NOT_NULL(json);
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_json(json, &back, err, sizeof err), err);
            free(json);
            TEST_ASSERT_EQUAL_STRING(r.edges_withheld, back.edges_withheld);
            TEST_ASSERT_FALSE(back.has_edges || back.has_height_change);
            if (v.status != UWB_STATUS_INCONCLUSIVE) {
                TEST_ASSERT_TRUE_MESSAGE(back.height_change_withheld[0] != '\0', msg);
            }
        }
        if (strstr(moved, "fdtd3d-"))
            withheld_3d += !r.has_edges;
        uwb_analysis_free(&ca);
        uwb_analysis_free(&ba);
        uwb_scan_free(&cur);
        uwb_scan_free(&base);
    }
    globfree(&g);
    printf("%d pairs, %d with edges published\n", pairs, published);
    /* Not a test that passes by withholding: most pairs publish theirs. */
    TEST_ASSERT_GREATER_OR_EQUAL_INT(25, published);
    /* The 3-D tanks' faces beside a plate's edge are measured now (issue
     * 45); s012's -20 mm pair, whose profiles no shift maps onto each
     * other, withholds its edges. */
    TEST_ASSERT_EQUAL_INT(1, withheld_3d);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_edge_published_lies_within_two_sigma);
    return UNITY_END();
}
