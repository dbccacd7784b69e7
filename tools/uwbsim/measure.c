#include "measure.h"

#include <complex.h>
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>

int sim_envelope(const float *x, int n, double *env)
{
    fftwf_complex *buf = fftwf_alloc_complex((size_t)n);
    if (!buf)
        return -1;
    fftwf_plan fwd = fftwf_plan_dft_1d(n, buf, buf, FFTW_FORWARD, FFTW_ESTIMATE);
    fftwf_plan inv = fftwf_plan_dft_1d(n, buf, buf, FFTW_BACKWARD, FFTW_ESTIMATE);
    if (!fwd || !inv) {
        if (fwd)
            fftwf_destroy_plan(fwd);
        if (inv)
            fftwf_destroy_plan(inv);
        fftwf_free(buf);
        return -1;
    }
    for (int i = 0; i < n; i++)
        buf[i] = x[i];
    fftwf_execute(fwd);
    /* analytic signal: keep DC (and Nyquist) once, double positive, drop negative */
    for (int k = 1; k < n; k++) {
        if (2 * k < n)
            buf[k] *= 2.0f;
        else if (2 * k > n)
            buf[k] = 0.0f;
    }
    fftwf_execute(inv);
    for (int i = 0; i < n; i++)
        env[i] = cabsf(buf[i]) / n;
    fftwf_destroy_plan(fwd);
    fftwf_destroy_plan(inv);
    fftwf_free(buf);
    return 0;
}

static double parabolic(double ym, double y0, double yp)
{
    double den = ym - 2.0 * y0 + yp;
    return den == 0 ? 0.0 : 0.5 * (ym - yp) / den;
}

double sim_envelope_peak(const float *x, int n, int i0, int i1)
{
    if (i0 < 1)
        i0 = 1;
    if (i1 > n - 1)
        i1 = n - 1;
    if (i0 >= i1)
        return -1;
    double *env = calloc((size_t)n, sizeof *env);
    if (!env || sim_envelope(x, n, env) != 0) {
        free(env);
        return -1;
    }
    int best = i0;
    for (int i = i0; i < i1; i++)
        if (env[i] > env[best])
            best = i;
    double peak = best + parabolic(env[best - 1], env[best], env[best + 1]);
    free(env);
    return peak;
}

static double xcorr_at(const float *a, const float *b, int n, int i0, int i1, int lag)
{
    double s = 0;
    for (int i = i0; i < i1; i++) {
        int j = i + lag;
        if (j >= 0 && j < n)
            s += (double)a[i] * b[j];
    }
    return s;
}

double sim_xcorr_lag(const float *a, const float *b, int n, int i0, int i1, int max_lag)
{
    int best = -max_lag;
    double bestv = -INFINITY;
    for (int lag = -max_lag; lag <= max_lag; lag++) {
        double v = xcorr_at(a, b, n, i0, i1, lag);
        if (v > bestv) {
            bestv = v;
            best = lag;
        }
    }
    if (best == -max_lag || best == max_lag)
        return best;
    return best + parabolic(xcorr_at(a, b, n, i0, i1, best - 1), bestv, xcorr_at(a, b, n, i0, i1, best + 1));
}

double sim_correlation(const float *a, const float *b, int i0, int i1)
{
    double ma = 0, mb = 0;
    int m = i1 - i0;
    for (int i = i0; i < i1; i++) {
        ma += a[i];
        mb += b[i];
    }
    ma /= m;
    mb /= m;
    double sab = 0, saa = 0, sbb = 0;
    for (int i = i0; i < i1; i++) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / sqrt(saa * sbb);
}
