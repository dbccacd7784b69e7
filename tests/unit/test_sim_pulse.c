/* Pulses: a measured pulse read from a file behaves like the analytic one it
 * samples; malformed files are refused with the file and line named. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "unity.h"
#include "uwbsim/uwbsim.h"

static char path[64];

void setUp(void)
{
    strcpy(path, "/tmp/uwbsim-pulse-XXXXXX");
    int fd = mkstemp(path);
    TEST_ASSERT_TRUE(fd >= 0);
    close(fd);
}

void tearDown(void)
{
    unlink(path);
}

static void write_file(const char *text)
{
    FILE *f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    fputs(text, f);
    fclose(f);
}

static void test_file_pulse_matches_analytic_ricker(void)
{
    FILE *f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    fprintf(f, "# Ricker 2 GHz sampled every 2 ps, scaled by 3 (the file's scale is not used)\n");
    for (int i = -600; i <= 600; i++) {
        double t = i * 2e-12, x = M_PI * 2e9 * t;
        fprintf(f, "%.6e %.9f\n", t, 3.0 * (1 - 2 * x * x) * exp(-x * x));
    }
    fclose(f);
    struct sim_scene a, b;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&a));
    a.noise = 0;
    a.jitter_s = 0;
    a.drift_db = 0;
    a.adc_bits = 0;
    b = a;
    b.pulse = SIM_PULSE_FILE;
    strcpy(b.pulse_file, path);
    struct uwb_scan sa, sb;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&a, 1, &sa, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&b, 1, &sb, err, sizeof err), err);
    size_t n = (size_t)sa.positions * sa.samples;
    double worst = 0, peak = 0;
    for (size_t i = 0; i < n; i++) {
        worst = fmax(worst, fabs((double)sa.data[i] - sb.data[i]));
        peak = fmax(peak, fabs(sa.data[i]));
    }
    TEST_ASSERT_TRUE_MESSAGE(worst < 0.002 * peak, "file pulse differs from the analytic one");
    uwb_scan_free(&sa);
    uwb_scan_free(&sb);
}

static void expect_refused(const char *text, const char *needle)
{
    if (text)
        write_file(text);
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.pulse = SIM_PULSE_FILE;
    strcpy(sc.pulse_file, path);
    struct sim_engine *e = NULL;
    char err[512];
    TEST_ASSERT_EQUAL_INT(-1, sim_engine_create(&sc, &e, err, sizeof err));
    TEST_ASSERT_NULL(e);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, path), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, needle), err);
}

static void test_bad_pulse_files(void)
{
    expect_refused("0 1\n1e-12 oops\n", "line 2");
    expect_refused("0 1\n2e-12 0.5\n1e-12 0.2\n3e-12 0\n", "increase");
    expect_refused("0 0\n1e-12 0\n2e-12 0\n3e-12 0\n", "zero");
    expect_refused("# nothing\n0 1\n", "at least");
    unlink(path);
    expect_refused(NULL, "No such file");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_file_pulse_matches_analytic_ricker);
    RUN_TEST(test_bad_pulse_files);
    return UNITY_END();
}
