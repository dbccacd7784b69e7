/* A face that changed shape is a finding, not a failure to match (issue
 * 45): an 8 mm buckle over two disks moves the face's echo strength and
 * ends so that the reflector match ("not the same reflector in both
 * scans") or the axial fit ("no shift ... maps the baseline's face
 * profile") fails, and the whole pair read inconclusive, "the face's range
 * was not compared". The rows that did not change still match at the
 * shift one end (or the centre) moved by: the radial change is read there
 * with its sign and place, and the axial figure withheld with why. The
 * shared tank's winding in the simulator, without and with its clutter
 * (a 6 mm barrier 40 mm out). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene_support.h"
#include "unity.h"
#include "uwb/evaluate.h"

void setUp(void)
{
}
void tearDown(void)
{
}

/* Disk k (1 at the bottom) of tools/uwbsim/scenes/fdtd2d-tank-winding.json. */
#define DISK_LO_M(k) (0.230 + 0.024 * ((k)-1))
#define DISK_HI_M(k) (DISK_LO_M(k) + 0.018)

static const char *const with_barrier[] = {"clutter", "true", "barrier_gap_m", "0.04", "barrier_thickness_m",
                                           "0.006",   NULL};

static void check_buckle(const char *const *common, int from, int to, double size_m)
{
    char radial[32];
    snprintf(radial, sizeof radial, "%d-%d:%g", from, to, size_m);
    const char *changed[] = {"radial_m", radial, NULL};
    struct uwb_scan base, cur;
    scene_tank_winding_pair_with(common, changed, &base, &cur);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    struct uwb_verdict v;
    char err[512];
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, sizeof err), err);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    const struct uwb_radial_verdict *r = &v.radial;
    printf("disks %d-%d %+.0f mm%s: %s (%s); radial %+.2f +- %.2f mm at %.0f mm (disks %.0f..%.0f mm)\n",
           from, to, size_m * 1e3, common ? ", clutter" : "", uwb_status_name(v.status), v.reason,
           r->max_change_m * 1e3, r->uncertainty_m * 1e3, r->at_m * 1e3, DISK_LO_M(from) * 1e3,
           DISK_HI_M(to) * 1e3);
    TEST_ASSERT_TRUE_MESSAGE(r->measured, r->withheld[0] ? r->withheld : v.reason);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_STATUS_ALARM, v.status, v.reason);
    TEST_ASSERT_TRUE_MESSAGE(v.axial_withheld, "axial withheld");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(v.reason, "the face changed shape"), v.reason);
    TEST_ASSERT_TRUE_MESSAGE(r->max_change_m * size_m > 0.0, "sign");
    /* The issue holds changes over 3 disks or more to max(1 mm, 20 %);
     * narrower ones blur more (radial_profile.c), held to 2 sigma. */
    double tolerance = to - from + 1 >= 3 ? fmax(1e-3, 0.2 * fabs(size_m)) : 2.0 * r->uncertainty_m;
    TEST_ASSERT_TRUE_MESSAGE(fabs(r->max_change_m - size_m) <= tolerance, "size");
    TEST_ASSERT_TRUE_MESSAGE(r->at_m >= DISK_LO_M(from) - 0.010 && r->at_m <= DISK_HI_M(to) + 0.010, "place");
}

/* Disks 2-3: "not the same reflector"; disks 4-5: "no shift maps". */
static void test_a_buckle_over_two_disks_reads_radially(void)
{
    check_buckle(NULL, 2, 3, 0.008);
    check_buckle(NULL, 4, 5, 0.008);
}

static void test_the_same_in_the_tank_with_its_barrier(void)
{
    check_buckle(with_barrier, 2, 3, 0.008);
    check_buckle(with_barrier, 4, 5, 0.008);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_buckle_over_two_disks_reads_radially);
    RUN_TEST(test_the_same_in_the_tank_with_its_barrier);
    return UNITY_END();
}
