/* The envelope along range: the magnitude of each row's analytic signal as
 * the zero-padded transform defines it (what the uncertainty's adjoint,
 * src/imaging/pair_uncertainty.c, differentiates), and of a pulse its
 * smooth envelope. */
#include <math.h>
#include <stdlib.h>

#include "unity.h"
#include "uwb/envelope.h"
#include "uwb/image.h"

void setUp(void)
{
}
void tearDown(void)
{
}

/* The definition, in double by a direct sum: a row of nz zero-padded to n
 * (a power of two >= 2 nz); Hilbert transform y_i = sum_s h(i - s) x_s
 * with h(m) = (2/n) sum_{k=1}^{n/2-1} sin(2 pi k m / n). */
static double reference_envelope(const double *x, int nz, int i)
{
    int n = 2;
    while (n < 2 * nz)
        n *= 2;
    double y = 0.0;
    for (int s = 0; s < nz; s++) {
        double h = 0.0;
        for (int k = 1; k < n / 2; k++)
            h += sin(2.0 * M_PI * k * (i - s) / n);
        y += 2.0 / n * h * x[s];
    }
    return sqrt(x[i] * x[i] + y * y);
}

static void test_rows_match_the_padded_transforms_definition(void)
{
    struct uwb_image img = {0};
    char err[256];
    const int ny = 3, nz = 37; /* padded to 128 */
    TEST_ASSERT_EQUAL_INT(0, uwb_image_alloc(&img, ny, nz, err, sizeof err));
    double *x = malloc((size_t)ny * nz * sizeof *x);
    TEST_ASSERT_NOT_NULL(x);
    unsigned state = 12345u;
    double peak = 0.0;
    for (int i = 0; i < ny * nz; i++) {
        state = state * 1103515245u + 12345u;
        x[i] = ((double)(state >> 8) / (double)(1u << 24) - 0.5) * (1 + i % 5);
        img.pix[i] = (float)x[i];
        x[i] = img.pix[i];
        peak = fmax(peak, fabs(x[i]));
    }
    TEST_ASSERT_EQUAL_INT(0, uwb_envelope_along_z(&img, err, sizeof err));
    for (int iy = 0; iy < ny; iy++)
        for (int iz = 0; iz < nz; iz++) {
            double want = reference_envelope(x + (size_t)iy * nz, nz, iz);
            TEST_ASSERT_DOUBLE_WITHIN(1e-5 * peak, want, img.pix[(size_t)iy * nz + iz]);
        }
    free(x);
    uwb_image_free(&img);
}

/* A Gaussian-windowed carrier, far from the row's ends: its envelope is
 * the window (to the carrier's few cycles per window, a percent). */
static void test_a_pulse_gives_its_window(void)
{
    struct uwb_image img = {0};
    char err[256];
    const int nz = 400;
    TEST_ASSERT_EQUAL_INT(0, uwb_image_alloc(&img, 1, nz, err, sizeof err));
    const double centre = 200.0, width = 30.0, cycles_per_sample = 0.1;
    for (int i = 0; i < nz; i++) {
        double u = (i - centre) / width;
        img.pix[i] = (float)(exp(-0.5 * u * u) * cos(2.0 * M_PI * cycles_per_sample * (i - centre) + 0.3));
    }
    TEST_ASSERT_EQUAL_INT(0, uwb_envelope_along_z(&img, err, sizeof err));
    for (int i = 100; i <= 300; i++) {
        double u = (i - centre) / width;
        TEST_ASSERT_DOUBLE_WITHIN(0.01, exp(-0.5 * u * u), img.pix[i]);
    }
    uwb_image_free(&img);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_rows_match_the_padded_transforms_definition);
    RUN_TEST(test_a_pulse_gives_its_window);
    return UNITY_END();
}
