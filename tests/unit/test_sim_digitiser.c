/* The simulated digitiser: noise at the stated SNR, stacking, ADC clipping
 * and quantisation, trigger jitter, gain drift. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "unity.h"
#include "uwbsim/uwbsim.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static void quiet(struct sim_scene *sc)
{
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(sc));
    sc->jitter_s = 0;
    sc->drift_db = 0;
    sc->adc_bits = 0;
}

static void make(const struct sim_scene *sc, uint64_t seed, struct uwb_scan *scan)
{
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(sc, seed, scan, err, sizeof err), err);
}

/* Peak |winding echo| measured on the scene's noiseless winding-only traces. */
static double winding_peak(const struct sim_scene *sc)
{
    struct sim_engine *e;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(sc, &e, err, sizeof err), err);
    double *tr = malloc((size_t)sc->samples * sizeof *tr), peak = 0;
    for (int k = 0; k < sc->positions; k++) {
        sim_engine_clean_trace(e, sim_scene_antenna_y_m(sc, k), SIM_PART_WINDING, 0.0, tr);
        for (int i = 0; i < sc->samples; i++)
            peak = fmax(peak, fabs(tr[i]));
    }
    free(tr);
    sim_engine_free(e);
    return peak;
}

/* rms of (noisy - clean) over the whole scan */
static double noise_rms(const struct sim_scene *sc, uint64_t seed)
{
    struct sim_scene clean = *sc;
    clean.noise = 0;
    struct uwb_scan a, b;
    make(sc, seed, &a);
    make(&clean, seed, &b);
    size_t n = (size_t)a.positions * a.samples;
    double s = 0;
    for (size_t i = 0; i < n; i++)
        s += ((double)a.data[i] - b.data[i]) * ((double)a.data[i] - b.data[i]);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
    return sqrt(s / n);
}

static void test_snr_is_honoured(void)
{
    const double snrs[] = {30.0, 10.0};
    for (int j = 0; j < 2; j++) {
        struct sim_scene sc;
        quiet(&sc);
        sc.snr_db = snrs[j];
        double peak = winding_peak(&sc), sigma = noise_rms(&sc, 7);
        double measured = 20 * log10(peak / sigma);
        printf("SNR asked %.1f dB, measured %.2f dB (peak echo %.4f V, noise rms %.5f V)\n", snrs[j],
               measured, peak, sigma);
        TEST_ASSERT_DOUBLE_WITHIN(0.25, snrs[j], measured);
    }
}

/* Band-limited noise keeps the per-sample SNR but holds no power above its
 * bandwidth. */
static void test_band_limited_noise(void)
{
    struct sim_scene sc;
    quiet(&sc);
    sc.snr_db = 20;
    sc.noise_bandwidth_hz = 4e9;
    double peak = winding_peak(&sc), sigma = noise_rms(&sc, 8);
    double measured = 20 * log10(peak / sigma);
    /* its spectrum: average |FFT|^2 of (noisy - clean) traces above and below 4 GHz */
    struct sim_scene clean = sc;
    clean.noise = 0;
    struct uwb_scan a, b;
    make(&sc, 8, &a);
    make(&clean, 8, &b);
    int S = a.samples;
    double below = 0, above = 0;
    for (int k = 0; k < a.positions; k++) {
        for (int f = 1; f < S / 2; f += 3) { /* a DFT at every third bin is plenty */
            double re = 0, im = 0, w = 2 * M_PI * f / S;
            for (int i = 0; i < S; i++) {
                double x = (double)a.data[(size_t)k * S + i] - b.data[(size_t)k * S + i];
                re += x * cos(w * i);
                im -= x * sin(w * i);
            }
            double hz = f / (S * sc.sample_interval_s), pw = re * re + im * im;
            if (hz < 3.5e9)
                below += pw;
            else if (hz > 5e9)
                above += pw;
        }
    }
    printf("band-limited noise: SNR %.2f dB, power above 5 GHz / below 3.5 GHz = %.2e\n", measured,
           above / below);
    TEST_ASSERT_DOUBLE_WITHIN(0.25, 20.0, measured);
    TEST_ASSERT_TRUE(above < 0.01 * below);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
}

static void test_stacking_lowers_noise_by_sqrt_n(void)
{
    struct sim_scene sc;
    quiet(&sc);
    double one = noise_rms(&sc, 3);
    sc.stack = 16;
    double sixteen = noise_rms(&sc, 3);
    printf("stacking: noise rms %.5f V (1 pulse) / %.5f V (16 pulses) = %.3f\n", one, sixteen, one / sixteen);
    TEST_ASSERT_DOUBLE_WITHIN(0.2, 4.0, one / sixteen);
}

static void test_adc_clips_at_full_scale_and_quantises(void)
{
    struct sim_scene sc;
    quiet(&sc);
    sc.adc_bits = 8;
    sc.adc_full_scale_v = 0.05; /* the direct coupling (~0.3 V) overdrives it */
    struct uwb_scan s;
    make(&sc, 1, &s);
    double lsb = 2 * sc.adc_full_scale_v / 256.0;
    double top = 127 * lsb, bottom = -128 * lsb, hi = -1, lo = 1;
    size_t n = (size_t)s.positions * s.samples, off_grid = 0;
    for (size_t i = 0; i < n; i++) {
        hi = fmax(hi, s.data[i]);
        lo = fmin(lo, s.data[i]);
        double codes = s.data[i] / lsb;
        if (fabs(codes - nearbyint(codes)) > 1e-3)
            off_grid++;
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-7, top, hi);
    TEST_ASSERT_DOUBLE_WITHIN(1e-7, bottom, lo);
    TEST_ASSERT_EQUAL_UINT64(0, off_grid);
    uwb_scan_free(&s);
}

/* Many traces at one height: each is the jitter-free trace shifted by its
 * own random delay, whose rms is jitter_s. */
static void test_jitter_rms(void)
{
    struct sim_scene sc;
    quiet(&sc);
    sc.noise = 0;
    sc.clutter = 0; /* the direct coupling is what we time */
    sc.positions = 300;
    sc.position_step_m = 0;
    sc.jitter_s = 20e-12;
    struct uwb_scan s;
    make(&sc, 11, &s);
    struct sim_engine *e;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &e, err, sizeof err), err);
    int S = sc.samples;
    double *ref = malloc((size_t)S * sizeof *ref);
    float *reff = malloc((size_t)S * sizeof *reff);
    sim_engine_clean_trace(e, 0.0, SIM_PART_ALL, 0.0, ref);
    for (int i = 0; i < S; i++)
        reff[i] = (float)ref[i];
    double ss = 0;
    int i1 = (int)((0.8e-9 - sc.t0_s) / sc.sample_interval_s); /* the direct coupling */
    for (int k = 0; k < sc.positions; k++) {
        double lag = sim_xcorr_lag(reff, s.data + (size_t)k * S, S, 1, i1, 10) * sc.sample_interval_s;
        ss += lag * lag;
    }
    double rms = sqrt(ss / sc.positions);
    printf("jitter: asked %.1f ps rms, measured %.2f ps\n", sc.jitter_s * 1e12, rms * 1e12);
    TEST_ASSERT_DOUBLE_WITHIN(0.15 * sc.jitter_s, sc.jitter_s, rms);
    free(ref);
    free(reff);
    sim_engine_free(e);
    uwb_scan_free(&s);
}

/* Gain drift is a random walk: successive traces' gains differ by drift_db rms. */
static void test_drift_random_walk(void)
{
    struct sim_scene sc;
    quiet(&sc);
    sc.noise = 0;
    sc.clutter = 0;
    sc.positions = 300;
    sc.position_step_m = 0;
    sc.drift_db = 0.1;
    struct uwb_scan s;
    make(&sc, 5, &s);
    int S = sc.samples;
    double prev = 0, ss = 0, first = 0;
    for (int k = 0; k < sc.positions; k++) {
        /* gain against trace 0 by least squares (traces are otherwise identical) */
        double num = 0, den = 0;
        for (int i = 0; i < S; i++) {
            num += (double)s.data[(size_t)k * S + i] * s.data[i];
            den += (double)s.data[i] * s.data[i];
        }
        double db = 20 * log10(num / den);
        if (k == 0)
            first = db;
        else
            ss += (db - prev) * (db - prev);
        prev = db;
    }
    double step = sqrt(ss / (sc.positions - 1));
    printf("drift: asked %.3f dB per step, measured %.4f dB\n", sc.drift_db, step);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0, first);
    TEST_ASSERT_DOUBLE_WITHIN(0.015, sc.drift_db, step);
    uwb_scan_free(&s);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_snr_is_honoured);
    RUN_TEST(test_band_limited_noise);
    RUN_TEST(test_stacking_lowers_noise_by_sqrt_n);
    RUN_TEST(test_adc_clips_at_full_scale_and_quantises);
    RUN_TEST(test_jitter_rms);
    RUN_TEST(test_drift_random_walk);
    return UNITY_END();
}
