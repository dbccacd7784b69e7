/* The evaluation's answer to "what sigma would N pulses per position give":
 * the noise part falls as 1/sqrt(N), the rest stays, and the pulses it
 * names for a sigma give that sigma back. */
#include "unity.h"

#include <math.h>
#include <string.h>

#include "uwb/evaluate.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static struct uwb_verdict verdict(double uncertainty_m, double noise_m)
{
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    v.uncertainty_m = uncertainty_m;
    v.current.sigma_center_noise_m = noise_m;
    return v;
}

/* All noise: four times the pulses halve sigma, sixteen quarter it. */
static void test_noise_alone_falls_as_one_over_root_pulses(void)
{
    struct uwb_verdict v = verdict(0.002, 0.002);
    struct uwb_pulse_sigma m;
    TEST_ASSERT_EQUAL_INT(0, uwb_pulse_sigma_from_verdict(&v, 4, &m));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.002, uwb_pulse_sigma_at(&m, 4));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.001, uwb_pulse_sigma_at(&m, 16));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.0005, uwb_pulse_sigma_at(&m, 64));
}

/* 1.2 mm of which 1.0 mm is noise: the other 0.66 mm stays however many
 * pulses are averaged. */
static void test_the_part_that_is_not_noise_stays(void)
{
    struct uwb_verdict v = verdict(0.0012, 0.0010);
    struct uwb_pulse_sigma m;
    TEST_ASSERT_EQUAL_INT(0, uwb_pulse_sigma_from_verdict(&v, 4, &m));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.0012, uwb_pulse_sigma_at(&m, 4));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, sqrt(0.44e-6 + 0.5e-6), uwb_pulse_sigma_at(&m, 8));
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, sqrt(0.44e-6), uwb_pulse_sigma_at(&m, 1e12));
    /* No noise term given: all of it is taken as noise. */
    v = verdict(0.0012, 0);
    TEST_ASSERT_EQUAL_INT(0, uwb_pulse_sigma_from_verdict(&v, 4, &m));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.0006, uwb_pulse_sigma_at(&m, 16));
    v = verdict(0, 0);
    TEST_ASSERT_EQUAL_INT(-1, uwb_pulse_sigma_from_verdict(&v, 4, &m));
}

/* The pulses named for a sigma give that sigma back; under what does not
 * average down, none can. */
static void test_pulses_for_a_sigma_give_it_back(void)
{
    struct uwb_verdict v = verdict(0.0012, 0.0010);
    struct uwb_pulse_sigma m;
    TEST_ASSERT_EQUAL_INT(0, uwb_pulse_sigma_from_verdict(&v, 4, &m));
    double pulses = 0;
    TEST_ASSERT_EQUAL_INT(0, uwb_pulse_sigma_pulses_for(&m, 0.001, &pulses));
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 4.0 / 0.56, pulses); /* 1.0^2 x 4 / (1.0^2 - 0.44) */
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.001, uwb_pulse_sigma_at(&m, pulses));
    TEST_ASSERT_EQUAL_INT(-1, uwb_pulse_sigma_pulses_for(&m, 0.0006, &pulses)); /* 0.36 < 0.44 */
}

/* sigma^2 = 0.5 + 4 / pulses (mm^2) seen at 4 and 8 pulses: the fit finds
 * both parts; a sigma that rose with the pulses fits nothing. */
static void test_a_fit_through_two_measurements_finds_both_parts(void)
{
    double s4 = sqrt(0.5 + 4.0 / 4) * 1e-3, s8 = sqrt(0.5 + 4.0 / 8) * 1e-3;
    struct uwb_pulse_sigma m;
    TEST_ASSERT_EQUAL_INT(0, uwb_pulse_sigma_fit(s4, 4, s8, 8, &m));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.5e-6, m.fixed_m2);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 4e-6, m.scaling_m2);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, sqrt(0.5 + 4.0 / 32) * 1e-3, uwb_pulse_sigma_at(&m, 32));
    TEST_ASSERT_EQUAL_INT(-1, uwb_pulse_sigma_fit(s8, 4, s4, 8, &m));
    TEST_ASSERT_EQUAL_INT(-1, uwb_pulse_sigma_fit(s4, 8, s8, 8, &m));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_noise_alone_falls_as_one_over_root_pulses);
    RUN_TEST(test_the_part_that_is_not_noise_stays);
    RUN_TEST(test_pulses_for_a_sigma_give_it_back);
    RUN_TEST(test_a_fit_through_two_measurements_finds_both_parts);
    return UNITY_END();
}
