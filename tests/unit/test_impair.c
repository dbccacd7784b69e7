/* tools/impair: a noisy copy of a scan, exactly as documented, and the same
 * seed gives the same file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "fixture_support.h"
#include "impair/impair.h"
#include "scratch_support.h"
#include "unity.h"

#define TANK "tests/fixtures/fdtd2d-tank-d+10.0.uwbscan"

static struct uwb_scan clean;

void setUp(void)
{
    fixture_load_scan(TANK, &clean);
}

void tearDown(void)
{
    uwb_scan_free(&clean);
}

static void impaired(struct uwb_scan *out, double snr_db, int noise, double jitter_s, double lin, double rnd,
                     uint64_t seed, struct uwb_impairment_report *rep)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_copy(out, &clean, err, sizeof err));
    struct uwb_impairment imp = {noise, snr_db, jitter_s, lin, rnd, seed};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_impair_scan(out, &imp, rep, err, sizeof err), err);
}

static void test_noise_rms_is_the_peak_after_the_coupling_times_ten_to_minus_snr_over_20(void)
{
    struct uwb_scan a;
    struct uwb_impairment_report rep;
    impaired(&a, 20.0, 1, 0.0, 0.0, 0.0, 5, &rep);
    /* The reference: the largest |sample| from the gate on, found independently. */
    int first = (int)ceil((rep.gate_s - clean.t0_s) / clean.sample_interval_s);
    double peak = 0.0;
    for (int k = 0; k < clean.positions; k++)
        for (int i = first; i < clean.samples; i++)
            peak = fmax(peak, fabs(clean.data[(size_t)k * clean.samples + i]));
    TEST_ASSERT_EQUAL_DOUBLE(peak, rep.reference_peak);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9 * peak, 0.1 * peak, rep.noise_sigma);
    /* The gate: 0.1 m two-way plus two periods lies between the coupling and the face. */
    TEST_ASSERT_TRUE(rep.gate_s > 1.0e-9 && rep.gate_s < 3.0e-9);
    double ss = 0.0;
    size_t n = (size_t)clean.positions * clean.samples;
    for (size_t i = 0; i < n; i++)
        ss += ((double)a.data[i] - clean.data[i]) * ((double)a.data[i] - clean.data[i]);
    TEST_ASSERT_DOUBLE_WITHIN(0.01 * rep.noise_sigma, rep.noise_sigma, sqrt(ss / n));
    uwb_scan_free(&a);
}

static void test_same_seed_same_bytes_other_seed_other_bytes(void)
{
    struct uwb_scan a, b, c;
    impaired(&a, 20.0, 1, 3e-12, 0.02, 0.02, 42, NULL);
    impaired(&b, 20.0, 1, 3e-12, 0.02, 0.02, 42, NULL);
    impaired(&c, 20.0, 1, 3e-12, 0.02, 0.02, 43, NULL);
    size_t n = (size_t)clean.positions * clean.samples * sizeof(float);
    TEST_ASSERT_EQUAL_INT(0, memcmp(a.data, b.data, n));
    TEST_ASSERT_NOT_EQUAL(0, memcmp(a.data, c.data, n));
    uwb_scan_free(&a);
    uwb_scan_free(&b);
    uwb_scan_free(&c);
}

static void test_drift_scales_each_trace_and_leaves_the_noise_draws_alone(void)
{
    struct uwb_scan only_noise, drifted, lin;
    impaired(&only_noise, 20.0, 1, 0.0, 0.0, 0.0, 9, NULL);
    impaired(&drifted, 20.0, 1, 0.0, 0.02, 0.01, 9, NULL);
    impaired(&lin, 0.0, 0, 0.0, 0.05, 0.0, 9, NULL);
    int K = clean.positions, S = clean.samples;
    /* Linear only: gain 1 + 0.05 k/(K-1), exactly. */
    for (int k = 0; k < K; k += K - 1) {
        double g = 1.0 + 0.05 * k / (K - 1);
        for (int i = 0; i < S; i += 97)
            TEST_ASSERT_FLOAT_WITHIN(1e-4f * fabsf(clean.data[(size_t)k * S + i]) + 1e-6f,
                                     (float)(g * clean.data[(size_t)k * S + i]), lin.data[(size_t)k * S + i]);
    }
    /* With drift the noise is the same draw: drifted - gain*clean == noisy - clean,
     * the gain per trace recovered by least squares on the clean trace. */
    for (int k = 0; k < K; k++) {
        const float *c = clean.data + (size_t)k * S, *d = drifted.data + (size_t)k * S,
                    *o = only_noise.data + (size_t)k * S;
        double num = 0.0, den = 0.0;
        for (int i = 0; i < S; i++) {
            num += ((double)d[i] - o[i]) * c[i];
            den += (double)c[i] * c[i];
        }
        double g = 1.0 + num / den;
        TEST_ASSERT_TRUE(fabs(g - 1.0 - 0.02 * k / (K - 1)) < 0.06); /* linear plus a 1 % draw */
        for (int i = 0; i < S; i += 53)
            TEST_ASSERT_FLOAT_WITHIN(1e-3f * (fabsf(c[i]) + 1.0f), o[i] - c[i], (float)(d[i] - g * c[i]));
    }
    uwb_scan_free(&only_noise);
    uwb_scan_free(&drifted);
    uwb_scan_free(&lin);
}

/* Sub-sample delay of b against a: the cross-correlation peak, refined by a
 * parabola through it and its neighbours. */
static double delay_between(const float *a, const float *b, int n, double dt)
{
    int best = 0;
    double best_v = -INFINITY, v[3];
    for (int lag = -20; lag <= 20; lag++) {
        double s = 0.0;
        for (int i = 20; i < n - 20; i++)
            s += (double)a[i] * b[i + lag];
        if (s > best_v) {
            best_v = s;
            best = lag;
        }
    }
    for (int j = -1; j <= 1; j++) {
        double s = 0.0;
        for (int i = 20; i < n - 20; i++)
            s += (double)a[i] * b[i + best + j];
        v[j + 1] = s;
    }
    return (best + 0.5 * (v[0] - v[2]) / (v[0] - 2.0 * v[1] + v[2])) * dt;
}

static void test_jitter_delays_each_trace_with_the_given_rms(void)
{
    struct uwb_scan j;
    impaired(&j, 0.0, 0, 20e-12, 0.0, 0.0, 11, NULL);
    int K = clean.positions, S = clean.samples;
    double ss = 0.0;
    for (int k = 0; k < K; k++) {
        double d =
            delay_between(clean.data + (size_t)k * S, j.data + (size_t)k * S, S, clean.sample_interval_s);
        ss += d * d;
    }
    double rms = sqrt(ss / K);
    /* 21 draws of 20 ps rms: the sample rms lies within 0.6..1.4 of it. */
    TEST_ASSERT_TRUE_MESSAGE(rms > 12e-12 && rms < 28e-12, "jitter rms off");
    TEST_ASSERT_TRUE(rms > 1e-12);
    uwb_scan_free(&j);
}

static void test_the_program_writes_the_same_file_for_the_same_seed(void)
{
    char dir[64], cmd[1024], a[128], b[128], c[128];
    scratch_scratch_dir(dir, sizeof dir, "impair");
    snprintf(a, sizeof a, "%s/a.uwbscan", dir);
    snprintf(b, sizeof b, "%s/b.uwbscan", dir);
    snprintf(c, sizeof c, "%s/c.uwbscan", dir);
    const char *prefix = getenv("UWB_EXEC_PREFIX") ? getenv("UWB_EXEC_PREFIX") : "";
    const char *opts = "--snr-db 20 --jitter-ps 3 --drift-linear 0.02 --drift-random 0.02";
    snprintf(cmd, sizeof cmd, "%s %s/uwbimpair --seed 7 %s %s %s", prefix, UWB_BUILD_DIR, opts, TANK, a);
    TEST_ASSERT_EQUAL_INT(0, system(cmd));
    snprintf(cmd, sizeof cmd, "%s %s/uwbimpair --seed 7 %s %s %s", prefix, UWB_BUILD_DIR, opts, TANK, b);
    TEST_ASSERT_EQUAL_INT(0, system(cmd));
    snprintf(cmd, sizeof cmd, "%s %s/uwbimpair --seed 8 %s %s %s", prefix, UWB_BUILD_DIR, opts, TANK, c);
    TEST_ASSERT_EQUAL_INT(0, system(cmd));
    size_t la, lb, lc;
    char *fa = scratch_slurp(a, &la), *fb = scratch_slurp(b, &lb), *fc = scratch_slurp(c, &lc);
    TEST_ASSERT_NOT_NULL(fa);
    TEST_ASSERT_NOT_NULL(fb);
    TEST_ASSERT_NOT_NULL(fc);
    TEST_ASSERT_EQUAL_UINT64(la, lb);
    TEST_ASSERT_EQUAL_INT(0, memcmp(fa, fb, la));
    TEST_ASSERT_TRUE(la != lc || memcmp(fa, fc, la) != 0);
    TEST_ASSERT_NOT_NULL(strstr(fa, "impaired by uwbimpair: seed 7"));
    /* It reads back as a scan of the same shape. */
    struct uwb_scan back;
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(a, &back, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(clean.positions, back.positions);
    TEST_ASSERT_EQUAL_INT(clean.samples, back.samples);
    uwb_scan_free(&back);
    free(fa);
    free(fb);
    free(fc);
    snprintf(cmd, sizeof cmd, "%s %s/uwbimpair --jitter-ps -1 %s %s 2>/dev/null", prefix, UWB_BUILD_DIR, TANK,
             a);
    TEST_ASSERT_EQUAL_INT(64, WEXITSTATUS(system(cmd)));
    TEST_ASSERT_EQUAL_INT(0, scratch_remove_tree(dir));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_noise_rms_is_the_peak_after_the_coupling_times_ten_to_minus_snr_over_20);
    RUN_TEST(test_same_seed_same_bytes_other_seed_other_bytes);
    RUN_TEST(test_drift_scales_each_trace_and_leaves_the_noise_draws_alone);
    RUN_TEST(test_jitter_delays_each_trace_with_the_given_rms);
    RUN_TEST(test_the_program_writes_the_same_file_for_the_same_seed);
    return UNITY_END();
}
