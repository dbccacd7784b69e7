#include "fft_plans.h"

#include <stddef.h>

/* Lengths one installation meets: its record length, a few envelope row
 * lengths and the noise draws' length, times two kinds. */
#define CACHED_PLANS 32

static struct {
    enum fft_kind kind;
    int n;
    fftwf_plan plan;
} cache[CACHED_PLANS];
static int cached;

static fftwf_plan make_plan(enum fft_kind kind, int n)
{
    fftwf_plan plan = NULL;
    float *real = fftwf_alloc_real((size_t)n);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)n / 2 + 1);
    if (real && spec)
        plan = kind == FFT_R2C ? fftwf_plan_dft_r2c_1d(n, real, spec, FFTW_ESTIMATE)
                               : fftwf_plan_dft_c2r_1d(n, spec, real, FFTW_ESTIMATE);
    fftwf_free(real);
    fftwf_free(spec);
    return plan;
}

fftwf_plan uwb_fft_plan_acquire(enum fft_kind kind, int n)
{
    for (int i = 0; i < cached; i++)
        if (cache[i].kind == kind && cache[i].n == n)
            return cache[i].plan;
    fftwf_plan plan = make_plan(kind, n);
    if (plan && cached < CACHED_PLANS) {
        cache[cached].kind = kind;
        cache[cached].n = n;
        cache[cached].plan = plan;
        cached++;
    }
    return plan;
}

void uwb_fft_plan_release(fftwf_plan plan)
{
    if (!plan)
        return;
    for (int i = 0; i < cached; i++)
        if (cache[i].plan == plan)
            return;
    fftwf_destroy_plan(plan);
}

int uwb_fft_padded_length(int n)
{
    int padded = 2;
    while (padded < n && padded < (1 << 29))
        padded *= 2;
    return padded;
}
