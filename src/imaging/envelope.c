#include "uwb/envelope.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fft_plans.h"

int uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen)
{
    /* Pad to at least twice the row so the circular transform does not fold
     * the far end of the range window onto the near end, and on to a power
     * of two: FFTW is several times slower on lengths with large prime
     * factors (2 x 501 = 2 x 3 x 167), and this runs on every image row. */
    int n = 2;
    while (n < 2 * img->nz)
        n *= 2;
    int nh = n / 2 + 1;
    float *row = fftwf_alloc_real((size_t)n);
    fftwf_complex *half = fftwf_alloc_complex((size_t)nh);
    fftwf_complex *full = fftwf_alloc_complex((size_t)n);
    if (!row || !half || !full) {
        fftwf_free(row);
        fftwf_free(half);
        fftwf_free(full);
        snprintf(err, errlen, "envelope: out of memory for rows of %d", img->nz);
        return -1;
    }
    fftwf_plan fwd = uwb_fft_plan_acquire(FFT_R2C, n),
               inv = uwb_fft_plan_acquire(FFT_C2C_BACKWARD_IN_PLACE, n);
    if (!fwd || !inv) {
        uwb_fft_plan_release(fwd);
        uwb_fft_plan_release(inv);
        fftwf_free(row);
        fftwf_free(half);
        fftwf_free(full);
        snprintf(err, errlen, "envelope: out of memory for transforms of %d", n);
        return -1;
    }
    for (int iy = 0; iy < img->ny; iy++) {
        float *pix = img->pix + (size_t)iy * img->nz;
        memcpy(row, pix, (size_t)img->nz * sizeof *row);
        memset(row + img->nz, 0, (size_t)(n - img->nz) * sizeof *row);
        fftwf_execute_dft_r2c(fwd, row, half);
        /* Analytic signal: keep DC and Nyquist, double positive, drop negative. */
        memset(full + nh, 0, (size_t)(n - nh) * sizeof *full);
        full[0][0] = half[0][0];
        full[0][1] = half[0][1];
        for (int i = 1; i < nh - 1; i++) {
            full[i][0] = 2.0f * half[i][0];
            full[i][1] = 2.0f * half[i][1];
        }
        full[nh - 1][0] = half[nh - 1][0];
        full[nh - 1][1] = half[nh - 1][1];
        fftwf_execute_dft(inv, full, full);
        for (int iz = 0; iz < img->nz; iz++)
            pix[iz] = hypotf(full[iz][0], full[iz][1]) / (float)n;
    }
    uwb_fft_plan_release(fwd);
    uwb_fft_plan_release(inv);
    fftwf_free(row);
    fftwf_free(half);
    fftwf_free(full);
    return 0;
}
