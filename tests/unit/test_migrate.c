/* Migration: focuses a point where it is, and the fixed-point path matches
 * the float reference. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwb/condition.h"
#include "uwb/geometry.h"
#include "uwb/migrate.h"

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

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_float_focuses_a_point);
    RUN_TEST(test_fixed_focuses_a_point);
    RUN_TEST(test_off_grid_antennas_focus_too);
    RUN_TEST(test_fixed_point_matches_float_reference);
    RUN_TEST(test_migration_kind_names_round_trip);
    return UNITY_END();
}
