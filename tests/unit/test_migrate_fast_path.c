/* The fast migration's parts: delay tables (mirrored rows, the Q15 split,
 * the zero pad), the SIMD inner loop against the portable one bit for bit,
 * and whole images against a direct double-precision sum. White-box where
 * it has to be: the private headers of src/imaging are included. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwb/geometry.h"
#include "uwb/migrate.h"

#include "../../src/imaging/delay_table.h"
#include "../../src/imaging/migrate_kernel.h"

void setUp(void)
{
}
void tearDown(void)
{
}

#define POSITIONS 21
#define SAMPLES 600

static uint32_t rng_state;
static uint32_t next_random(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state >> 8;
}
/* Uniform in [-1, 1]. */
static float random_unit(void)
{
    return (float)next_random() / (float)(1u << 23) - 1.0f;
}

/* A scan of noise at full scale (every sample can be the peak, so
 * interpolation and accumulation run at their limits), antennas 30 mm apart
 * with an optional jitter that takes them off the pixel grid. */
static void noise_scan(struct uwb_scan *s, double tx_dz, double jitter_m)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(s, POSITIONS, SAMPLES, err, sizeof err));
    s->sample_interval_s = 10e-12;
    s->t0_s = -0.5e-9;
    s->tx_m[0] = -0.02;
    s->tx_m[1] = tx_dz;
    s->rx_m[0] = 0.02;
    s->eps_r = 2.2;
    rng_state = 12345u;
    for (int k = 0; k < POSITIONS; k++)
        s->antenna_y_m[k] = 0.03 * k + (k % 2 ? jitter_m : 0.0);
    for (size_t i = 0; i < (size_t)POSITIONS * SAMPLES; i++)
        s->data[i] = random_unit();
}

/* Delay of (dy above the antenna, z) in samples after sample 0, the long way. */
static double delay_samples(const struct uwb_geometry *g, double dy, double z)
{
    return (uwb_two_way_delay(g, dy, z) - g->t0_s) / g->dt_s;
}

/* Every row of a shared fixed-point table, mirrored or not, holds its own
 * height's delays: index * 32768 + weight is the delay in Q15 (to one unit
 * of rounding), or the pad outside the record. Returns the stored rows. */
static int check_table_rows(const struct uwb_scan *s, const struct uwb_image *img)
{
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, s, 0.0);
    struct delay_table t;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_delay_table_plan(&t, DELAY_FIXED, s, &g, img, err, sizeof err));
    TEST_ASSERT_TRUE(t.shared);
    double y_top = s->antenna_y_m[POSITIONS - 1];
    for (int r = 0; r < t.rows; r++) {
        for (int iz = 0; iz < t.nz; iz++) {
            double d = delay_samples(&g, img->y0_m - y_top + r * img->dy_m, img->z0_m + iz * img->dz_m);
            size_t at = t.row_start[r] + (size_t)iz;
            if (d < 0.0 || d >= SAMPLES - 1 - 1e-6) {
                if (d < 0.0 || d >= SAMPLES - 1 + 1e-6) { /* clearly outside: the pad */
                    TEST_ASSERT_EQUAL_INT32(SAMPLES, t.index[at]);
                    TEST_ASSERT_EQUAL_INT16(0, t.weight_q15[at]);
                }
                continue;
            }
            double q = (double)t.index[at] * 32768.0 + t.weight_q15[at];
            TEST_ASSERT_DOUBLE_WITHIN(1.0, d * 32768.0, q);
            TEST_ASSERT_TRUE(t.weight_q15[at] >= 0 && t.weight_q15[at] <= 32767);
        }
    }
    int stored = t.stored_rows;
    uwb_delay_table_free(&t);
    return stored;
}

/* Phase centres' midpoint on a row: rows mirrored about it share storage,
 * and each still reads its own delays. */
static void test_mirrored_rows_hold_their_own_delays(void)
{
    struct uwb_scan s;
    noise_scan(&s, 0.0, 0.0);
    struct uwb_image img;
    fixture_image_grid(&img, 70, 37, -0.05, 0.01, 0.05, 0.02);
    int rows = img.ny + (int)lround(0.6 / 0.01);
    int stored = check_table_rows(&s, &img);
    TEST_ASSERT_TRUE_MESSAGE(stored < rows * 3 / 4, "mirrored rows were not shared");
    uwb_image_free(&img);
    /* Midpoint half-way between rows: shared too. */
    fixture_image_grid(&img, 70, 37, -0.055, 0.01, 0.05, 0.02);
    stored = check_table_rows(&s, &img);
    TEST_ASSERT_TRUE(stored < rows * 3 / 4);
    uwb_image_free(&img);
    uwb_scan_free(&s);
}

/* Tx and Rx at different ranges: no mirror, every row stored. */
static void test_no_mirror_when_ranges_differ(void)
{
    struct uwb_scan s;
    noise_scan(&s, 0.01, 0.0);
    struct uwb_image img;
    fixture_image_grid(&img, 70, 37, -0.05, 0.01, 0.05, 0.02);
    TEST_ASSERT_EQUAL_INT(img.ny + 60, check_table_rows(&s, &img));
    uwb_image_free(&img);
    uwb_scan_free(&s);
}

/* A fraction that rounds to a whole sample carries into the index. The
 * grid steps 2e-12 m in range around the range where the delay is exactly
 * 100 samples, so a few fractions fall in the last Q15 step below 1. */
static void test_weight_rounding_carries_into_the_index(void)
{
    struct uwb_scan s;
    noise_scan(&s, 0.0, 0.0);
    s.positions = 1;
    s.antenna_y_m[0] = 0.0;
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &s, 0.0);
    double leg = (100.0 * g.dt_s + g.t0_s) * g.velocity_m_s / 2.0; /* Tx and Rx legs alike */
    double z_exact = sqrt(leg * leg - 0.02 * 0.02);
    struct uwb_image img;
    fixture_image_grid(&img, 1, 401, 0.0, 0.001, z_exact - 200 * 2e-12, 2e-12);
    struct delay_table t;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_delay_table_plan(&t, DELAY_FIXED, &s, &g, &img, err, sizeof err));
    int carried = 0;
    for (int iz = 0; iz < img.nz; iz++) {
        double d = delay_samples(&g, 0.0, img.z0_m + iz * img.dz_m);
        double below = d - floor(d);
        if (below * 32768.0 >= 32767.5) { /* rounds to 1: the next sample, weight 0 */
            TEST_ASSERT_EQUAL_INT32((int32_t)floor(d) + 1, t.index[iz]);
            TEST_ASSERT_EQUAL_INT16(0, t.weight_q15[iz]);
            carried++;
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(carried > 0, "the grid did not reach a carrying fraction");
    uwb_delay_table_free(&t);
    uwb_image_free(&img);
    s.positions = POSITIONS;
    uwb_scan_free(&s);
}

/* The SIMD loop and the portable one give the same integers for every row
 * length (the SIMD tail included) and at the extremes of samples and weights. */
static void test_simd_row_equals_portable_row(void)
{
    enum { N = 67 };
    int16_t pairs[2 * (SAMPLES + 1)];
    float trace[SAMPLES];
    rng_state = 99u;
    for (int s = 0; s < SAMPLES; s++)
        trace[s] = s % 7 == 0 ? 1.0f : s % 7 == 1 ? -1.0f : random_unit();
    uwb_migrate_fill_pairs(trace, SAMPLES, 32767.0f, pairs);
    TEST_ASSERT_EQUAL_INT16(-32767, pairs[0]);      /* -q[0], q[0] = 32767 */
    TEST_ASSERT_EQUAL_INT16(-32767, pairs[1]);      /* q[1] = -32767 */
    TEST_ASSERT_EQUAL_INT16(0, pairs[2 * SAMPLES]); /* the pad */
    TEST_ASSERT_EQUAL_INT16(0, pairs[2 * SAMPLES + 1]);
    int32_t index[N];
    int16_t weight[N];
    for (int i = 0; i < N; i++) {
        index[i] = i % 11 == 0 ? SAMPLES : (int32_t)(next_random() % SAMPLES);
        weight[i] = i % 5 == 0 ? 0 : i % 5 == 1 ? 32767 : (int16_t)(next_random() % 32768);
    }
    for (int n = 0; n <= N; n++) {
        int32_t a[N], b[N];
        for (int i = 0; i < N; i++)
            a[i] = b[i] = (int32_t)(next_random() % 2001) - 1000;
        uwb_migrate_row_fixed_portable(index, weight, pairs, a, n);
        uwb_migrate_row_fixed_simd(index, weight, pairs, b, n);
        TEST_ASSERT_EQUAL_INT32_ARRAY(a, b, N);
    }
    /* And the portable loop is the interpolation it claims to be. */
    int32_t out[N] = {0};
    uwb_migrate_row_fixed_portable(index, weight, pairs, out, N);
    for (int i = 0; i < N; i++) {
        const int16_t *p = pairs + 2 * index[i];
        double a = -p[0], b = p[1];
        TEST_ASSERT_EQUAL_INT32((int32_t)floor(a + (b - a) * weight[i] / 32768.0 + 0.5), out[i]);
    }
}

/* The direct sum: double precision, delays from uwb_two_way_delay. */
static void direct_sum(const struct uwb_scan *s, const struct uwb_image *img, double *out)
{
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, s, 0.0);
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double sum = 0.0;
            for (int k = 0; k < s->positions; k++) {
                double d = delay_samples(&g, img->y0_m + iy * img->dy_m - s->antenna_y_m[k],
                                         img->z0_m + iz * img->dz_m);
                if (!(d >= 0.0) || d >= SAMPLES - 1)
                    continue;
                int i = (int)d;
                const float *tr = s->data + (size_t)k * SAMPLES;
                sum += tr[i] + (d - i) * ((double)tr[i + 1] - tr[i]);
            }
            out[(size_t)iy * img->nz + iz] = sum;
        }
}

/* Whole images on noise at full scale: float within float rounding of the
 * direct sum; fixed point within its bound (per trace half a step for the
 * samples, one for the weight, half for the rounding: 2 steps of 1/32767);
 * the SIMD and portable fixed paths identical. Shared and mirrored tables,
 * shared unmirrored, and per-trace tables (antennas off the grid). */
static void check_images(double tx_dz, double jitter_m, double y0)
{
    struct uwb_scan s;
    noise_scan(&s, tx_dz, jitter_m);
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &s, 0.0);
    struct uwb_image fx, port, fl;
    /* z from 2 cm to 1.2 m: delays run off the end of the record (the pad). */
    fixture_image_grid(&fx, 45, 61, y0, 0.015, 0.02, 0.0197);
    fixture_image_grid(&port, 45, 61, y0, 0.015, 0.02, 0.0197);
    fixture_image_grid(&fl, 45, 61, y0, 0.015, 0.02, 0.0197);
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_migrate(UWB_MIGRATE_FIXED, &s, &g, &fx, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwb_migrate(UWB_MIGRATE_FIXED_PORTABLE, &s, &g, &port, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwb_migrate(UWB_MIGRATE_FLOAT, &s, &g, &fl, err, sizeof err));
    size_t n = (size_t)fx.ny * fx.nz;
    TEST_ASSERT_EQUAL_MEMORY(port.pix, fx.pix, n * sizeof *fx.pix);
    double *ref = malloc(n * sizeof *ref);
    TEST_ASSERT_NOT_NULL(ref);
    direct_sum(&s, &fx, ref);
    double peak = 0.0;
    for (size_t i = 0; i < (size_t)POSITIONS * SAMPLES; i++)
        peak = fabs(s.data[i]) > peak ? fabs(s.data[i]) : peak;
    double fixed_bound = POSITIONS * 2.0 * peak / 32767.0;
    size_t zeros = 0;
    for (size_t i = 0; i < n; i++) {
        TEST_ASSERT_DOUBLE_WITHIN(1e-4, ref[i], fl.pix[i]);
        TEST_ASSERT_DOUBLE_WITHIN(fixed_bound, ref[i], fx.pix[i]);
        if (ref[i] == 0.0) { /* every delay beyond the record: nothing added */
            TEST_ASSERT_EQUAL_FLOAT(0.0f, fx.pix[i]);
            TEST_ASSERT_EQUAL_FLOAT(0.0f, fl.pix[i]);
            zeros++;
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(zeros > 0, "the grid never left the record");
    free(ref);
    uwb_image_free(&fx);
    uwb_image_free(&port);
    uwb_image_free(&fl);
    uwb_scan_free(&s);
}

static void test_images_with_mirrored_table(void)
{
    check_images(0.0, 0.0, -0.15);
}
static void test_images_with_unmirrored_table(void)
{
    check_images(0.013, 0.0, -0.15);
}
static void test_images_with_per_trace_tables(void)
{
    check_images(0.0, 0.0041, -0.15);
}

static void test_simd_name_is_known(void)
{
    const char *name = uwb_migration_simd();
    TEST_ASSERT_TRUE(strcmp(name, "SSE2") == 0 || strcmp(name, "NEON") == 0 || strcmp(name, "none") == 0);
#if defined(__x86_64__)
    TEST_ASSERT_EQUAL_STRING("SSE2", name);
#elif defined(__aarch64__)
    TEST_ASSERT_EQUAL_STRING("NEON", name);
#endif
    TEST_ASSERT_EQUAL_STRING("fixed-portable", uwb_migration_kind_name(UWB_MIGRATE_FIXED_PORTABLE));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_mirrored_rows_hold_their_own_delays);
    RUN_TEST(test_no_mirror_when_ranges_differ);
    RUN_TEST(test_weight_rounding_carries_into_the_index);
    RUN_TEST(test_simd_row_equals_portable_row);
    RUN_TEST(test_images_with_mirrored_table);
    RUN_TEST(test_images_with_unmirrored_table);
    RUN_TEST(test_images_with_per_trace_tables);
    RUN_TEST(test_simd_name_is_known);
    return UNITY_END();
}
