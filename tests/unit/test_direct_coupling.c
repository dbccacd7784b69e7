/* Time zero from the direct coupling: the arrival follows a delay to a
 * fraction of a sample, ignores the pulse's amplitude, the digitiser's DC
 * offset and echoes after the window, and says so when it cannot be found.
 * On simulated scans it is stable from scan to scan. */
#include "unity.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "uwb/direct_coupling.h"
#include "uwbsim/uwbsim.h"

#define K 8
#define S 512
#define DT 10e-12
#define T0 (-1e-9)
#define WINDOW_END 2e-9

static char why[200];

void setUp(void)
{
}
void tearDown(void)
{
}

/* Ricker wavelet of 2 GHz centred at t. */
static double ricker(double t)
{
    double a = M_PI * 2e9 * t;
    return (1.0 - 2.0 * a * a) * exp(-a * a);
}

/* Coupling pulse centred at `delay`, amplitude `amp`, on a DC offset, with a
 * stronger echo after the window and a little deterministic noise. */
static void fill(struct uwb_scan *s, double delay, double amp)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(s, K, S, err, sizeof err));
    s->sample_interval_s = DT;
    s->t0_s = T0;
    uint64_t state = 12345;
    for (int k = 0; k < K; k++) {
        s->antenna_y_m[k] = 0.03 * k;
        for (int i = 0; i < S; i++) {
            double t = T0 + i * DT;
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            double noise = ((double)(state >> 11) / 9007199254740992.0 - 0.5) * 0.004;
            s->data[k * S + i] =
                (float)(0.3 + amp * ricker(t - delay) + 3.0 * amp * ricker(t - 3e-9) + noise);
        }
    }
}

static double arrival_of(double delay, double amp)
{
    struct uwb_scan s = {0};
    fill(&s, delay, amp);
    double a = 0;
    int rc = uwb_direct_coupling_arrival(&s, WINDOW_END, &a, why, sizeof why);
    uwb_scan_free(&s);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, why);
    return a;
}

static void test_arrival_is_the_leading_edge_before_the_peak(void)
{
    double a = arrival_of(0.2e-9, 1.0);
    /* The leading half-height of the Ricker's main lobe is ~72 ps before its centre. */
    TEST_ASSERT_TRUE(a < 0.2e-9 && a > 0.2e-9 - 120e-12);
}

static void test_arrival_follows_a_delay_to_a_fraction_of_a_sample(void)
{
    double a0 = arrival_of(0.2e-9, 1.0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 25e-12, arrival_of(0.225e-9, 1.0) - a0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 3e-12, arrival_of(0.203e-9, 1.0) - a0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, -40e-12, arrival_of(0.16e-9, 1.0) - a0);
}

static void test_amplitude_does_not_move_the_arrival(void)
{
    double a0 = arrival_of(0.2e-9, 1.0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, arrival_of(0.2e-9, 4.0) - a0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, arrival_of(0.2e-9, 0.25) - a0);
}

static void test_unusable_windows_are_reported(void)
{
    struct uwb_scan s = {0};
    fill(&s, 0.2e-9, 1.0);
    double a;
    TEST_ASSERT_EQUAL_INT(-1, uwb_direct_coupling_arrival(&s, T0 + 3 * DT, &a, why, sizeof why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, "holds"), why);
    TEST_ASSERT_EQUAL_INT(-1, uwb_direct_coupling_arrival(&s, -5e-9, &a, why, sizeof why));
    /* A record that starts at the pulse's peak cannot show its leading edge. */
    s.t0_s = 0.2e-9 - 0.5 * DT;
    for (int k = 0; k < K; k++)
        for (int i = 0; i < S; i++)
            s.data[k * S + i] = (float)ricker(s.t0_s + i * DT - 0.2e-9);
    TEST_ASSERT_EQUAL_INT(-1, uwb_direct_coupling_arrival(&s, s.t0_s + 2e-9, &a, why, sizeof why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, "starts inside"), why);
    memset(s.data, 0, sizeof(float) * K * S);
    TEST_ASSERT_EQUAL_INT(-1, uwb_direct_coupling_arrival(&s, WINDOW_END, &a, why, sizeof why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, "no signal"), why);
    uwb_scan_free(&s);
}

/* Simulated scans of the default tank scene: clutter, window echo and
 * noise, a fresh noise draw each. */
static void test_simulated_scans_agree_from_seed_to_seed(void)
{
    struct sim_scene scene;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&scene));
    char err[256];
    /* Only the start of the record and a few positions: the simulation is slow under qemu. */
    TEST_ASSERT_EQUAL_INT(0, sim_scene_set(&scene, "samples", "300", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_set(&scene, "positions", "5", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_set(&scene, "position_step_m", "0.1", err, sizeof err));
    double first = 0;
    for (uint64_t seed = 1; seed <= 3; seed++) {
        struct uwb_scan s;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&scene, seed, &s, err, sizeof err), err);
        double a;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_direct_coupling_arrival(&s, WINDOW_END, &a, why, sizeof why),
                                      why);
        uwb_scan_free(&s);
        TEST_ASSERT_TRUE(a > T0 && a < 0.5e-9);
        if (seed == 1)
            first = a;
        else
            TEST_ASSERT_DOUBLE_WITHIN(3e-12, first, a);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_arrival_is_the_leading_edge_before_the_peak);
    RUN_TEST(test_arrival_follows_a_delay_to_a_fraction_of_a_sample);
    RUN_TEST(test_amplitude_does_not_move_the_arrival);
    RUN_TEST(test_unusable_windows_are_reported);
    RUN_TEST(test_simulated_scans_agree_from_seed_to_seed);
    return UNITY_END();
}
