/* The precision bound (uwbsim --precision-bound): what the README's claim
 * "a single pulse at 20 dB cannot give 0.5 mm" rests on. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_support.h"
#include "unity.h"
#include "uwbsim/uwbsim.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static struct sim_bound bound_for(const char *stack)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    scene_set_or_fail(&sc, "snr_db", "20");
    scene_set_or_fail(&sc, "stack", stack);
    struct sim_bound b;
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_displacement_bound(&sc, &b, err, sizeof err), err);
    return b;
}

/* One pulse at 20 dB: even a perfect estimator's displacement scatters by
 * more than 0.5 mm (1 sigma), so "within 0.5 mm" needs stacking. */
static void test_single_pulse_at_20_db_bounds_above_half_mm(void)
{
    struct sim_bound b = bound_for("1");
    printf("20 dB, 1 pulse: noise %.4g V, bound %.3f mm one scan, %.3f mm displacement\n", b.noise_rms,
           b.single_scan_m * 1e3, b.displacement_m * 1e3);
    TEST_ASSERT_TRUE(b.displacement_m > 0.0005);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, sqrt(2.0) * b.single_scan_m, b.displacement_m);
}

/* Stacking 64 pulses divides the noise, and so the bound, by 8. */
static void test_stacking_divides_the_bound_by_root_n(void)
{
    struct sim_bound one = bound_for("1"), many = bound_for("64");
    double ratio = one.displacement_m / many.displacement_m;
    printf("bound 1 pulse / 64 pulses: %.2f\n", ratio);
    TEST_ASSERT_DOUBLE_WITHIN(0.4, 8.0, ratio);
    TEST_ASSERT_TRUE(many.displacement_m < 0.00015);
}

static void test_coloured_noise_is_refused(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    scene_set_or_fail(&sc, "noise_bandwidth_hz", "5e9");
    struct sim_bound b;
    char err[256] = "";
    TEST_ASSERT_EQUAL_INT(-1, sim_displacement_bound(&sc, &b, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "white noise"));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_single_pulse_at_20_db_bounds_above_half_mm);
    const char *p = getenv("UWB_EXEC_PREFIX");
    if (!(p && *p)) /* four more scans: minutes under qemu-user */
        RUN_TEST(test_stacking_divides_the_bound_by_root_n);
    RUN_TEST(test_coloured_noise_is_refused);
    return UNITY_END();
}
