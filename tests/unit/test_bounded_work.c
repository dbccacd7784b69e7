/* Issue 17, break 5: an in-memory scan the reader would refuse (it never
 * reaches the analysis through a file) still gets a message from the
 * imaging, not a conversion of 1.9e302 or NaN to int (undefined behaviour,
 * caught by `make test SAN=1`'s float-cast-overflow) and not a grid of
 * -2147483647 rows or gigabytes of pixels. */
#include "unity.h"

#include <math.h>
#include <string.h>

#include "fixture_support.h"
#include "uwb/analysis.h"

static char err[512];
static struct uwb_scan scan;

void setUp(void)
{
    fixture_load_scan("tests/fixtures/fdtd2d-paper-intact.uwbscan", &scan);
}

void tearDown(void)
{
    uwb_scan_free(&scan);
}

/* The analysis either refuses with an imaging message or finds nothing:
 * never a confident edge. */
static void expect_refused(const char *what)
{
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis a;
    memset(&a, 0, sizeof a);
    err[0] = '\0';
    int rc = uwb_analyse_scan(&scan, &opt, &a, err, sizeof err);
    char msg[700];
    snprintf(msg, sizeof msg, "%s: rc %d, found %d, err \"%s\"", what, rc, rc == 0 ? a.edges.found : -1, err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, rc, msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "pixels a side"), msg);
    uwb_analysis_free(&a);
}

static void test_positions_spread_over_1e302_m_are_refused(void)
{
    for (int k = 0; k < scan.positions; k++)
        scan.antenna_y_m[k] = k * 1e301;
    expect_refused("1e302 m travel");
}

static void test_positions_spread_over_600_km_are_refused_before_allocating(void)
{
    for (int k = 0; k < scan.positions; k++)
        scan.antenna_y_m[k] = k * 3e4;
    expect_refused("600 km travel");
}

static void test_a_nanometre_step_is_refused(void)
{
    for (int k = 0; k < scan.positions; k++)
        scan.antenna_y_m[k] = k * 1e-9 + k * k * 0.03; /* first step 1 nm + 30 mm */
    scan.antenna_y_m[1] = scan.antenna_y_m[0] + 1e-9;
    expect_refused("1 nm step");
}

/* The format allows any finite sample; the analysis squares sums of them in
 * single precision. A sample that would overflow is refused by name; one
 * a digitiser frame can carry (32767 counts x 1e6 V per count) is not. */
static void test_a_sample_too_large_to_image_is_refused_by_name(void)
{
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis a;
    scan.data[(size_t)3 * scan.samples + 7] = -2e12f;
    int rc = uwb_analyse_scan(&scan, &opt, &a, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, rc, "a sample of -2e12 was imaged");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "sample 7 of position 3 is -2e+12"), err);

    float peak = 0.0f;
    for (size_t i = 0; i < (size_t)scan.positions * scan.samples; i++)
        peak = fmaxf(peak, fabsf(scan.data[i] = i == (size_t)3 * scan.samples + 7 ? 0.0f : scan.data[i]));
    for (size_t i = 0; i < (size_t)scan.positions * scan.samples; i++)
        scan.data[i] *= 3.3e10f / peak;
    rc = uwb_analyse_scan(&scan, &opt, &a, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, err);
    TEST_ASSERT_TRUE_MESSAGE(a.edges.found, a.edges.reason);
    TEST_ASSERT_TRUE(isfinite(a.edges.center_m) && isfinite(a.edges.sigma_center_m));
    uwb_analysis_free(&a);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_positions_spread_over_1e302_m_are_refused);
    RUN_TEST(test_positions_spread_over_600_km_are_refused_before_allocating);
    RUN_TEST(test_a_nanometre_step_is_refused);
    RUN_TEST(test_a_sample_too_large_to_image_is_refused_by_name);
    return UNITY_END();
}
