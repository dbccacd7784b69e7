/* The analysis' steps when a resource runs out: every step reports it as a
 * hard error naming the step, never a figure computed from a placeholder.
 *
 * FFTW's buffer allocator is replaced here (this program's definition of
 * fftwf_alloc_real wins over the shared library's), so a chosen call can be
 * made to fail as an exhausted board would. */
#include "unity.h"

#include <fftw3.h>
#include <math.h>
#include <string.h>

#include "fixture_support.h"
#include "uwb/analysis.h"
#include "uwb/image.h"
#include "imaging/imaging_internal.h"

static int real_allocs_to_fail; /* the next this many fftwf_alloc_real calls return NULL */

float *fftwf_alloc_real(size_t n)
{
    if (real_allocs_to_fail > 0) {
        real_allocs_to_fail--;
        return NULL;
    }
    return fftwf_malloc(n * sizeof(float));
}

static struct uwb_scan scan;

void setUp(void)
{
    fixture_load_scan(FIXTURE_INTACT, &scan);
    real_allocs_to_fail = 0;
}

void tearDown(void)
{
    uwb_scan_free(&scan);
}

/* The dominant frequency is the analysis' first FFT: with no memory for it
 * there is no wavelength, and the analysis must stop there rather than
 * divide by a frequency of 0. */
static void test_no_memory_for_the_dominant_frequency_is_a_hard_error(void)
{
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis a;
    char err[256] = "";
    real_allocs_to_fail = 1;
    int rc = uwb_analyse_scan(&scan, &opt, &a, err, sizeof err);
    char msg[400];
    snprintf(msg, sizeof msg, "rc %d, found %d, reason \"%s\", err \"%s\"", rc, a.edges.found, a.edges.reason,
             err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, rc, msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "dominant frequency"), msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "out of memory"), msg);
    uwb_analysis_free(&a);
}

/* The same scan with memory enough is analysed (the override itself is sound). */
static void test_with_memory_the_scan_is_analysed(void)
{
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis a;
    char err[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_analyse_scan(&scan, &opt, &a, err, sizeof err), err);
    TEST_ASSERT_TRUE_MESSAGE(a.edges.found, a.edges.reason);
    TEST_ASSERT_TRUE(a.dominant_hz > 0.0);
    uwb_analysis_free(&a);
}

/* The display image (the migrated PNG) spans the face's range +- the
 * option, which defaults to 0.25 m. */
static void test_display_image_spans_the_optioned_range_about_the_face(void)
{
    const double halves[2] = {0.25, 0.1};
    for (int i = 0; i < 2; i++) {
        struct uwb_analysis_options opt;
        uwb_analysis_defaults(&opt);
        if (i == 0)
            TEST_ASSERT_EQUAL_DOUBLE(0.25, opt.display_half_range_m);
        opt.display_half_range_m = halves[i];
        struct uwb_analysis a;
        char err[256] = "";
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_analyse_scan(&scan, &opt, &a, err, sizeof err), err);
        TEST_ASSERT_TRUE_MESSAGE(a.edges.found, a.edges.reason);
        double z_first = a.intensity.z0_m,
               z_last = a.intensity.z0_m + (a.intensity.nz - 1) * a.intensity.dz_m;
        TEST_ASSERT_DOUBLE_WITHIN(a.intensity.dz_m, a.edges.face_z_m - halves[i], z_first);
        TEST_ASSERT_DOUBLE_WITHIN(a.intensity.dz_m, a.edges.face_z_m + halves[i], z_last);
        uwb_analysis_free(&a);
    }
}

/* A range column with no usable pixel (all NaN, e.g. from a damaged
 * scan) has no peak: -1, and its row is set (0), never left unset for
 * the face search to read. */
static void test_column_peak_of_a_column_without_numbers_is_minus_one_at_row_0(void)
{
    struct uwb_image img = {0};
    char err[128];
    TEST_ASSERT_EQUAL_INT(0, uwb_image_alloc(&img, 4, 2, err, sizeof err));
    for (int iy = 0; iy < 4; iy++) {
        img.pix[iy * 2 + 0] = (float)NAN;
        img.pix[iy * 2 + 1] = (float)(iy == 2 ? 5.0 : 1.0);
    }
    int row = 12345;
    TEST_ASSERT_EQUAL_DOUBLE(-1.0, uwb_image_column_peak(&img, 0, &row));
    TEST_ASSERT_EQUAL_INT(0, row);
    TEST_ASSERT_EQUAL_DOUBLE(5.0, uwb_image_column_peak(&img, 1, &row));
    TEST_ASSERT_EQUAL_INT(2, row);
    uwb_image_free(&img);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_no_memory_for_the_dominant_frequency_is_a_hard_error);
    RUN_TEST(test_with_memory_the_scan_is_analysed);
    RUN_TEST(test_display_image_spans_the_optioned_range_about_the_face);
    RUN_TEST(test_column_peak_of_a_column_without_numbers_is_minus_one_at_row_0);
    return UNITY_END();
}
