/* The height change's sigma covers a warmer or colder oil (issue 44, item
 * 2): the same tank, nothing moved, the oil's eps_r a little off the
 * header's between baseline and scan. Its wave speed moves the face's
 * range and the image, focused at the header's speed, blurs the shoulders
 * differently, so the crossings read a height change that is none: held
 * back, a tank read -0.96 mm at sigma 0.24 mm. Here the shared full-wave
 * tank's winding in the simulator, drawn over the family's ranges (5-8
 * disks, faces at 390-490 mm, pulses of 1.8-2.6 GHz), the scan made at
 * eps_r 2.16 or 2.26 with the header's 2.2 kept, as a configured
 * permittivity reads: each height change given lies within 2 sigma of 0. */
#include <math.h>
#include <stdio.h>

#include "scene_support.h"
#include "unity.h"
#include "uwb/evaluate.h"

void setUp(void)
{
}
void tearDown(void)
{
}

/* One tank of the draw: common settings (key, value, ... NULL). */
static const char *const tanks[][7] = {
    {NULL},
    {"face_z_m", "0.49", NULL},
    {"face_z_m", "0.39", "disks", "5", NULL},
    {"disks", "8", "disk_height_m", "0.024", NULL},
    {"centre_frequency_hz", "1.8e9", NULL},
    {"centre_frequency_hz", "2.6e9", "face_z_m", "0.46", NULL},
};
static const char *const oils[] = {"2.16", "2.26"};

static void test_a_changed_oil_reads_no_height_change_outside_its_sigma(void)
{
    int given = 0;
    for (size_t t = 0; t < sizeof tanks / sizeof tanks[0]; t++)
        for (size_t o = 0; o < sizeof oils / sizeof oils[0]; o++) {
            const char *const changed[] = {"eps_r", oils[o], NULL};
            struct uwb_scan base, cur;
            scene_tank_winding_pair_with(tanks[t], changed, &base, &cur);
            cur.eps_r = base.eps_r; /* the header's, configured; the oil's own changed */
            struct uwb_evaluate_options opt;
            uwb_evaluate_defaults(&opt);
            struct uwb_analysis ca, ba;
            struct uwb_verdict v;
            char err[512];
            struct uwb_baseline_record rec = {.scan = &base};
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, sizeof err),
                                          err);
            printf("tank %zu, oil eps_r %s: face range moved %+.2f mm, height change %+.3f +- %.3f mm%s%s\n",
                   t, oils[o], (ca.edges.face_z_m - ba.edges.face_z_m) * 1e3, v.height_change_m * 1e3,
                   v.height_change_uncertainty_m * 1e3, v.height_change_withheld[0] ? ", withheld: " : "",
                   v.height_change_withheld);
            TEST_ASSERT_TRUE_MESSAGE(ca.edges.found && ba.edges.found, "the winding not found");
            /* The oil is no move: the shift stays within its own sigma. */
            TEST_ASSERT_TRUE(fabs(v.axial_displacement_m) <= 2.0 * v.uncertainty_m);
            if (!v.height_change_withheld[0]) {
                given++;
                TEST_ASSERT_TRUE_MESSAGE(fabs(v.height_change_m) <= 2.0 * v.height_change_uncertainty_m,
                                         "a height change that is none, outside 2 sigma");
            }
            uwb_analysis_free(&ca);
            uwb_analysis_free(&ba);
            uwb_scan_free(&cur);
            uwb_scan_free(&base);
        }
    /* Each tank's oil changes by less than its 1 mm limit: not a test that
     * passes by withholding everything. */
    TEST_ASSERT_GREATER_OR_EQUAL_INT(8, given);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_changed_oil_reads_no_height_change_outside_its_sigma);
    return UNITY_END();
}
