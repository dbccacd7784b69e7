/* The traces' filters in the frequency domain (src/imaging/trace_spectrum.c):
 * transformed at a fast length with zeros after the record, so a filter's
 * circular wrap does not fold the record's end onto its start. */
#include "unity.h"

#include <math.h>
#include <string.h>

#include "imaging/fft_plans.h"
#include "imaging/side_reflector.h"
#include "uwb/scan.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static void test_padded_length_is_the_next_power_of_two(void)
{
    TEST_ASSERT_EQUAL_INT(2048, uwb_fft_padded_length(1697)); /* the paper scans' prime length */
    TEST_ASSERT_EQUAL_INT(4096, uwb_fft_padded_length(2333)); /* the family's */
    TEST_ASSERT_EQUAL_INT(1024, uwb_fft_padded_length(936));  /* the 3-D scans' */
    TEST_ASSERT_EQUAL_INT(2048, uwb_fft_padded_length(2048));
    TEST_ASSERT_EQUAL_INT(2, uwb_fft_padded_length(1));
    for (int n = 2; n < 5000; n += 37) {
        int m = uwb_fft_padded_length(n);
        TEST_ASSERT_TRUE(m >= n && m < 2 * n);
        TEST_ASSERT_EQUAL_INT(0, m & (m - 1));
    }
}

/* An echo 20 samples before the record's end: its quadrature (a Hilbert
 * transform, whose kernel falls off only as 1/t) must not reappear at the
 * record's start, 20 samples away around a circular transform of the
 * record's own length. */
static void test_a_late_echo_does_not_wrap_onto_the_start(void)
{
    struct uwb_scan in = {0}, q = {0};
    char err[256];
    const int S = 1697; /* prime: no transform length divides it */
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&in, 1, S, err, sizeof err));
    in.sample_interval_s = 10e-12;
    in.antenna_y_m[0] = 0.0;
    double centre = S - 20.0, period = 24.0; /* samples */
    for (int s = 0; s < S; s++) {
        double t = (s - centre) / period;
        in.data[s] = (float)(cos(2.0 * M_PI * t) * exp(-4.0 * t * t));
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_quadrature_scan(&in, &q, err, sizeof err), err);
    double peak = 0.0, start = 0.0;
    for (int s = 0; s < S; s++) {
        double v = fabs(q.data[s]);
        if (s >= S - 60 && v > peak)
            peak = v;
        if (s < 60 && v > start)
            start = v;
    }
    TEST_ASSERT_TRUE(peak > 0.3);
    TEST_ASSERT_TRUE_MESSAGE(start < 0.005 * peak, "the echo's quadrature wrapped onto the record's start");
    uwb_scan_free(&q);
    uwb_scan_free(&in);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_padded_length_is_the_next_power_of_two);
    RUN_TEST(test_a_late_echo_does_not_wrap_onto_the_start);
    return UNITY_END();
}
