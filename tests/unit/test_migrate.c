/* Migration: focuses a point where it is, and the fixed-point path matches
 * the float reference. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "imaging/imaging_internal.h"
#include "unity.h"
#include "uwb/condition.h"
#include "uwb/geometry.h"
#include "uwb/migrate.h"

/* The huge-image case asks calloc for 2^62 bytes: under ASan that is NULL,
 * as it is from libc, instead of a report that ends the run. */
const char *__asan_default_options(void);
const char *__asan_default_options(void)
{
    return "allocator_may_return_null=1";
}

void setUp(void)
{
}
void tearDown(void)
{
}

/* A point scatterer at (yp, zp) seen by a bistatic pair, Ricker 2 GHz. */
static void point_scan(struct uwb_scan *s, double yp, double zp, double jitter_m)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(s, 21, 1024, err, sizeof err));
    s->sample_interval_s = 10e-12;
    s->t0_s = -0.5e-9;
    s->tx_m[0] = -0.02;
    s->rx_m[0] = 0.02;
    s->eps_r = 2.2;
    struct uwb_geometry g;
    for (int k = 0; k < 21; k++)
        s->antenna_y_m[k] = 0.03 * k + (k % 2 ? jitter_m : 0.0);
    uwb_geometry_from_scan(&g, s, 0.0);
    double f = 2e9;
    for (int k = 0; k < 21; k++) {
        double tau = uwb_two_way_delay(&g, yp - s->antenna_y_m[k], zp);
        for (int i = 0; i < 1024; i++) {
            double t = s->t0_s + i * s->sample_interval_s - tau;
            double a = M_PI * M_PI * f * f * t * t;
            s->data[(size_t)k * 1024 + i] = (float)((1.0 - 2.0 * a) * exp(-a));
        }
    }
}

static void peak_of(const struct uwb_image *img, double *y, double *z)
{
    size_t best = 0;
    for (size_t i = 1; i < (size_t)img->ny * img->nz; i++)
        if (fabsf(img->pix[i]) > fabsf(img->pix[best]))
            best = i;
    *y = img->y0_m + (double)(best / img->nz) * img->dy_m;
    *z = img->z0_m + (double)(best % img->nz) * img->dz_m;
}

static void focus_case(enum uwb_migration_kind kind, double jitter)
{
    struct uwb_scan s;
    point_scan(&s, 0.317, 0.55, jitter);
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &s, 0.0);
    struct uwb_image img;
    fixture_image_grid(&img, 301, 201, 0.15, 0.001, 0.45, 0.001);
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_migrate(kind, &s, &g, &img, err, sizeof err));
    double y, z;
    peak_of(&img, &y, &z);
    TEST_ASSERT_DOUBLE_WITHIN(0.0015, 0.317, y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0015, 0.55, z);
    /* The sum is coherent there: every trace adds its peak of 1. */
    TEST_ASSERT_FLOAT_WITHIN(
        1.5f, 21.0f,
        fabsf(img.pix[(size_t)lround((y - 0.15) / 0.001) * 201 + (size_t)lround((z - 0.45) / 0.001)]));
    uwb_image_free(&img);
    uwb_scan_free(&s);
}

static void test_float_focuses_a_point(void)
{
    focus_case(UWB_MIGRATE_FLOAT, 0.0);
}
static void test_fixed_focuses_a_point(void)
{
    focus_case(UWB_MIGRATE_FIXED, 0.0);
}
/* Antenna heights off the pixel grid take the per-trace delay tables. */
static void test_off_grid_antennas_focus_too(void)
{
    focus_case(UWB_MIGRATE_FLOAT, 0.00037);
    focus_case(UWB_MIGRATE_FIXED, 0.00037);
}

static double snr_db(const struct uwb_image *ref, const struct uwb_image *test)
{
    double signal = 0.0, noise = 0.0;
    for (size_t i = 0; i < (size_t)ref->ny * ref->nz; i++) {
        double d = (double)test->pix[i] - ref->pix[i];
        signal += (double)ref->pix[i] * ref->pix[i];
        noise += d * d;
    }
    return 10.0 * log10(signal / noise);
}

/* The appliance's fixed-point image against the float reference on a
 * full-wave scan, over a 600 x 400 image at 1 mm: at least 50 dB. */
static void test_fixed_point_matches_float_reference(void)
{
    struct uwb_scan raw, s;
    fixture_load_scan(FIXTURE_UP20, &raw);
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &raw, 0.0);
    struct uwb_condition_options copt;
    uwb_condition_defaults(&copt);
    char err[256];
    double dominant_hz;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_dominant_frequency(&raw, &dominant_hz, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, uwb_condition(&raw, &g, &copt, dominant_hz, NULL, &s, err, sizeof err));
    struct uwb_image ref, fixed;
    fixture_image_grid(&ref, 600, 400, 0.0, 0.001, 0.25, 0.001);
    fixture_image_grid(&fixed, 600, 400, 0.0, 0.001, 0.25, 0.001);
    TEST_ASSERT_EQUAL_INT(0, uwb_migrate(UWB_MIGRATE_FLOAT, &s, &g, &ref, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwb_migrate(UWB_MIGRATE_FIXED, &s, &g, &fixed, err, sizeof err));
    double snr = snr_db(&ref, &fixed);
    TEST_ASSERT_TRUE_MESSAGE(snr >= 50.0, "fixed-point image below 50 dB SNR against float");
    /* And it is not trivially identical: the paths really differ. */
    TEST_ASSERT_TRUE(snr < 200.0);
    uwb_image_free(&ref);
    uwb_image_free(&fixed);
    uwb_scan_free(&s);
    uwb_scan_free(&raw);
}

static void test_migration_kind_names_round_trip(void)
{
    enum uwb_migration_kind k;
    TEST_ASSERT_EQUAL_INT(0, uwb_migration_kind_parse("float", &k));
    TEST_ASSERT_EQUAL_INT(UWB_MIGRATE_FLOAT, k);
    TEST_ASSERT_EQUAL_STRING("float", uwb_migration_kind_name(k));
    TEST_ASSERT_EQUAL_INT(0, uwb_migration_kind_parse("fixed", &k));
    TEST_ASSERT_EQUAL_STRING("fixed", uwb_migration_kind_name(k));
    TEST_ASSERT_EQUAL_INT(-1, uwb_migration_kind_parse("double", &k));
}

/* An image too small or too large to hold is refused with its size (and
 * quietly when there is no error buffer); freeing nothing is harmless. */
static void test_image_sizes_that_cannot_be_held_are_refused(void)
{
    struct uwb_image img;
    char err[256];
    TEST_ASSERT_EQUAL_INT(-1, uwb_image_alloc(&img, 0, 5, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("image: size 0 x 5, both must be at least 1", err);
    /* 2^62 pixels fit a 64-bit size_t; no machine allocates them. */
    TEST_ASSERT_EQUAL_INT(-1, uwb_image_alloc(&img, INT_MAX, INT_MAX, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("image: cannot allocate 2147483647 x 2147483647 pixels: Cannot allocate memory",
                             err);
    TEST_ASSERT_NULL(img.pix);
    TEST_ASSERT_EQUAL_INT(-1, uwb_image_alloc(&img, -1, 5, NULL, 0));
    TEST_ASSERT_EQUAL_INT(-1, uwb_image_alloc(&img, INT_MAX, INT_MAX, NULL, 0));
    uwb_image_free(NULL);
}

/* eps_r below 1 (no dielectric is) is taken as 1: waves never outrun light. */
static void test_a_permittivity_below_one_is_taken_as_vacuum(void)
{
    struct uwb_scan s;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&s, 2, 8, err, sizeof err));
    s.eps_r = 0.25;
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &s, 0.0);
    TEST_ASSERT_EQUAL_DOUBLE(UWB_SPEED_OF_LIGHT, g.velocity_m_s);
    s.eps_r = 4.0;
    uwb_geometry_from_scan(&g, &s, 0.0);
    TEST_ASSERT_EQUAL_DOUBLE(UWB_SPEED_OF_LIGHT / 2.0, g.velocity_m_s);
    uwb_scan_free(&s);
}

/* An imaging grid is over the whole travel, whatever the antennas' order;
 * pixel sizes that are not positive and finite, spans too long for them
 * and grids too small to image are each refused with the figures. */
static void test_imaging_grids_span_the_travel_and_refuse_degenerate_pixels(void)
{
    struct uwb_scan s;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&s, 3, 8, err, sizeof err));
    s.antenna_y_m[0] = 0.10;
    s.antenna_y_m[1] = 0.30; /* the highest in the middle */
    s.antenna_y_m[2] = 0.05; /* the lowest last */
    struct uwb_image img;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_imaging_grid(&img, &s, 0.02, 0.01, 0.4, 0.6, 0.001, err, sizeof err),
                                  err);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.03, img.y0_m);
    TEST_ASSERT_EQUAL_INT(30, img.ny); /* 0.03 .. 0.32 m */
    TEST_ASSERT_EQUAL_INT(201, img.nz);
    uwb_image_free(&img);

    const double bad_dy[] = {0.0, -0.01, NAN, INFINITY, 1e-9};
    for (size_t i = 0; i < sizeof bad_dy / sizeof bad_dy[0]; i++) {
        TEST_ASSERT_EQUAL_INT(-1,
                              uwb_imaging_grid(&img, &s, 0.02, bad_dy[i], 0.4, 0.6, 0.001, err, sizeof err));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is not at most 200000 pixels a side"), err);
    }
    TEST_ASSERT_EQUAL_INT(-1, uwb_imaging_grid(&img, &s, 0.02, 0.01, 0.4, INFINITY, 0.001, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is not at most 200000 pixels a side"), err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_imaging_grid(&img, &s, 0.02, 0.01, 0.4, 0.404, 0.001, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("imaging: grid of 30 x 5 pixels is too small", err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_imaging_grid(&img, &s, 0.0, 1.0, 0.4, 0.6, 0.001, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("imaging: grid of 1 x 201 pixels is too small", err);
    uwb_scan_free(&s);
}

/* The face's profile: a range outside the image, and a face that
 * overflows single precision, are refused by name with no profile kept. */
static void test_face_profiles_outside_the_image_or_overflowing_are_refused(void)
{
    struct uwb_image img;
    fixture_image_grid(&img, 4, 10, 0.0, 0.01, 0.5, 0.001);
    for (size_t i = 0; i < (size_t)img.ny * img.nz; i++)
        img.pix[i] = 1.0f;
    struct uwb_face_profile p = {0};
    char err[256];
    TEST_ASSERT_EQUAL_INT(-1, uwb_face_profile_measure(&img, 0.9, 0.002, &p, NULL, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("face range 0.900 m is outside the image", err);
    TEST_ASSERT_NULL(p.value);
    /* a window reaching past both ends is clipped to the image */
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_face_profile_measure(&img, 0.505, 0.5, &p, NULL, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_INT(4, p.n);
    TEST_ASSERT_EQUAL_FLOAT(1.0f, p.value[3]);
    free(p.value);
    img.pix[2 * 10 + 4] = INFINITY;
    p.value = NULL;
    TEST_ASSERT_EQUAL_INT(-1, uwb_face_profile_measure(&img, 0.505, 0.5, &p, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "overflows single precision at y = 0.020 m"), err);
    TEST_ASSERT_NULL(p.value);
    TEST_ASSERT_EQUAL_INT(0, p.n);
    uwb_image_free(&img);
}

/* A scan with no spectrum, and a dominant frequency that is none (zero,
 * or at or past Nyquist), are refused by conditioning with the figures;
 * nothing is left allocated in the output. */
static void test_conditioning_refuses_scans_without_a_spectrum(void)
{
    struct uwb_scan s;
    char err[256];
    double hz = -1.0;
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&s, 3, 1, err, sizeof err));
    s.sample_interval_s = 10e-12;
    TEST_ASSERT_EQUAL_INT(-1, uwb_dominant_frequency(&s, &hz, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("dominant frequency: a scan of 3 positions x 1 samples has no spectrum", err);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, hz);
    uwb_scan_free(&s);
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&s, 3, 64, err, sizeof err)); /* sample interval 0 */
    TEST_ASSERT_EQUAL_INT(-1, uwb_dominant_frequency(&s, &hz, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("dominant frequency: a scan of 3 positions x 64 samples has no spectrum", err);

    s.sample_interval_s = 10e-12; /* Nyquist 50 GHz */
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &s, 0.0);
    struct uwb_condition_options opt;
    uwb_condition_defaults(&opt);
    const double no_signal[] = {0.0, -1e9, 50e9, NAN};
    for (size_t i = 0; i < sizeof no_signal / sizeof no_signal[0]; i++) {
        struct uwb_scan out;
        TEST_ASSERT_EQUAL_INT(-1, uwb_condition_prepare(&s, &g, &opt, no_signal[i], &out, err, sizeof err));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "conditioning: no usable signal spectrum"), err);
        TEST_ASSERT_NULL(out.data);
    }
    /* a scan that cannot be copied is refused by both steps */
    uwb_scan_free(&s);
    struct uwb_scan out;
    TEST_ASSERT_EQUAL_INT(-1, uwb_condition_prepare(&s, &g, &opt, 2e9, &out, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan: positions is 0, must be between 1 and 4096", err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_condition_finish(&s, &g, &opt, 2e9, NULL, &out, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan: positions is 0, must be between 1 and 4096", err);
}

/* The dominant frequency is the scene's, whatever gain each trace came
 * with: a digitiser whose gain drifts from position to position (2 % rms
 * in make accuracy) must not move it. Here 11 traces carry a 2.5 GHz burst
 * and 10 a 1.5 GHz one of the same envelope and peak: 2.5 GHz dominates.
 * With the 10 at 10 % more gain their summed power would outweigh the 11,
 * as on the full-wave family's s04, whose comb-like spectrum has two
 * highest bins within 0.3 % of each other. */
static void test_dominant_frequency_ignores_each_traces_gain(void)
{
    const int positions = 21, samples = 1000;
    const double dt = 10e-12, t0 = 5e-9, width = 0.6e-9;
    for (int gained = 0; gained < 2; gained++) {
        struct uwb_scan s;
        char err[256];
        TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&s, positions, samples, err, sizeof err));
        s.sample_interval_s = dt;
        for (int k = 0; k < positions; k++) {
            int low = k % 2 == 0 && k < 20; /* 10 traces */
            double f = low ? 1.5e9 : 2.5e9, gain = low && gained ? 1.1 : 1.0;
            for (int i = 0; i < samples; i++) {
                double t = i * dt - t0;
                s.data[(size_t)k * samples + i] =
                    (float)(gain * exp(-0.5 * (t / width) * (t / width)) * cos(2.0 * M_PI * f * t));
            }
        }
        double hz = 0.0;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_dominant_frequency(&s, &hz, err, sizeof err), err);
        TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.1e9, 2.5e9, hz,
                                          gained ? "10 % more gain on the 1.5 GHz traces moved it"
                                                 : "2.5 GHz on 11 traces of 21");
        uwb_scan_free(&s);
    }
}

/* A shift needs the winding in both scans: edges not found on either side,
 * or a profile missing, is refused and the shift left alone. */
static void test_a_shift_needs_the_winding_in_both_scans(void)
{
    static float values[8];
    struct uwb_analysis found, missing;
    memset(&found, 0, sizeof found);
    memset(&missing, 0, sizeof missing);
    found.edges.found = 1;
    found.profile.n = 8;
    found.profile.dy_m = 0.001;
    found.profile.value = values;
    char err[128];
    double shift = 42.0;
    TEST_ASSERT_EQUAL_INT(-1, uwb_measure_shift(&found, &missing, &shift, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("shift: the winding is not established in both scans", err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_measure_shift(&missing, &found, &shift, err, sizeof err));
    missing.edges.found = 1; /* edges, but no profile */
    TEST_ASSERT_EQUAL_INT(-1, uwb_measure_shift(&found, &missing, &shift, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(-1, uwb_measure_shift(&missing, &found, &shift, err, sizeof err));
    TEST_ASSERT_EQUAL_DOUBLE(42.0, shift);
}
int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_float_focuses_a_point);
    RUN_TEST(test_fixed_focuses_a_point);
    RUN_TEST(test_off_grid_antennas_focus_too);
    RUN_TEST(test_fixed_point_matches_float_reference);
    RUN_TEST(test_migration_kind_names_round_trip);
    RUN_TEST(test_image_sizes_that_cannot_be_held_are_refused);
    RUN_TEST(test_a_permittivity_below_one_is_taken_as_vacuum);
    RUN_TEST(test_imaging_grids_span_the_travel_and_refuse_degenerate_pixels);
    RUN_TEST(test_face_profiles_outside_the_image_or_overflowing_are_refused);
    RUN_TEST(test_conditioning_refuses_scans_without_a_spectrum);
    RUN_TEST(test_dominant_frequency_ignores_each_traces_gain);
    RUN_TEST(test_a_shift_needs_the_winding_in_both_scans);
    return UNITY_END();
}
