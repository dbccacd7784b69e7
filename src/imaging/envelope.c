#include "uwb/envelope.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fft_plans.h"
#include "side_reflector.h"

int uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen)
{
    /* Pad to at least twice the row so the circular transform does not fold
     * the far end of the range window onto the near end, and on to a power
     * of two: FFTW is several times slower on lengths with large prime
     * factors (2 x 501 = 2 x 3 x 167), and this runs on every image row. */
    int n = uwb_fft_padded_length(2 * img->nz);
    int nh = n / 2 + 1;
    int rc = -1;
    fftwf_plan fwd = NULL, inv = NULL;
    float *row = fftwf_alloc_real((size_t)n);
    fftwf_complex *half = fftwf_alloc_complex((size_t)nh);
    if (!row || !half) {
        snprintf(err, errlen, "envelope: out of memory for rows of %d", img->nz);
        goto done;
    }
    fwd = uwb_fft_plan_acquire(FFT_R2C, n);
    inv = uwb_fft_plan_acquire(FFT_C2R, n);
    if (!fwd || !inv) {
        snprintf(err, errlen, "envelope: out of memory for transforms of %d", n);
        goto done;
    }
    /* The analytic signal's real part is the row itself; its imaginary
     * part, the Hilbert transform, is real too: -i times the positive
     * frequencies (DC and Nyquist dropped), back through a real inverse
     * transform at half the cost of a complex one. */
    float scale = 1.0f / (float)n;
    for (int iy = 0; iy < img->ny; iy++) {
        float *pix = img->pix + (size_t)iy * img->nz;
        memcpy(row, pix, (size_t)img->nz * sizeof *row);
        memset(row + img->nz, 0, (size_t)(n - img->nz) * sizeof *row);
        fftwf_execute_dft_r2c(fwd, row, half);
        half[0][0] = half[0][1] = 0.0f;
        half[nh - 1][0] = half[nh - 1][1] = 0.0f;
        for (int i = 1; i < nh - 1; i++) {
            float re = half[i][0];
            half[i][0] = half[i][1];
            half[i][1] = -re;
        }
        fftwf_execute_dft_c2r(inv, half, row);
        /* hypotf's own way (glibc): the float pair's squares summed in double. */
        for (int iz = 0; iz < img->nz; iz++) {
            double re = pix[iz], im = (double)row[iz] * scale;
            pix[iz] = (float)sqrt(re * re + im * im);
        }
    }
    rc = 0;
done:
    uwb_fft_plan_release(fwd);
    uwb_fft_plan_release(inv);
    fftwf_free(row);
    fftwf_free(half);
    return rc;
}

int uwb_envelope_of_traces(const struct uwb_scan *scan, float *env, char *err, size_t errlen)
{
    struct uwb_scan quadrature = {0};
    if (uwb_quadrature_scan(scan, &quadrature, err, errlen) != 0)
        return -1;
    size_t n = (size_t)scan->positions * (size_t)scan->samples;
    for (size_t i = 0; i < n; i++) {
        double re = scan->data[i], im = quadrature.data[i];
        env[i] = (float)sqrt(re * re + im * im);
    }
    uwb_scan_free(&quadrature);
    return 0;
}
