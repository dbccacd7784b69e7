#include "trace_spectrum.h"

#include "fft_plans.h"

#include <stdio.h>
#include <string.h>

/* 1 but in tests (uwb_trace_spectrum_set_padding_factor). */
static int padding_factor = 1;

void uwb_trace_spectrum_set_padding_factor(int factor)
{
    padding_factor = factor >= 1 && factor <= 16 ? factor : 1;
}

int uwb_trace_spectrum_length(int samples)
{
    return uwb_fft_padded_length(2 * samples) * padding_factor;
}

int uwb_filter_traces_in_spectrum(struct uwb_scan *s, int (*skip)(void *ctx, int k), trace_spectrum_fn filter,
                                  void *ctx, const char *what, char *err, size_t errlen)
{
    int S = s->samples, n = uwb_trace_spectrum_length(S), nh = n / 2 + 1;
    int rc = -1;
    fftwf_plan fwd = NULL, inv = NULL;
    float *buf = fftwf_alloc_real((size_t)n);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)nh);
    if (!buf || !spec) {
        snprintf(err, errlen, "%s: out of memory", what);
        goto done;
    }
    fwd = uwb_fft_plan_acquire(FFT_R2C, n);
    inv = uwb_fft_plan_acquire(FFT_C2R, n);
    if (!fwd || !inv) {
        snprintf(err, errlen, "%s: out of memory for a transform of %d samples", what, S);
        goto done;
    }
    double df = 1.0 / (n * s->sample_interval_s);
    for (int k = 0; k < s->positions; k++) {
        if (skip && skip(ctx, k))
            continue;
        float *tr = s->data + (size_t)k * S;
        memcpy(buf, tr, (size_t)S * sizeof *buf);
        memset(buf + S, 0, (size_t)(n - S) * sizeof *buf);
        fftwf_execute_dft_r2c(fwd, buf, spec);
        filter(ctx, k, spec, n, df);
        fftwf_execute_dft_c2r(inv, spec, buf);
        memcpy(tr, buf, (size_t)S * sizeof *buf);
    }
    rc = 0;
done:
    uwb_fft_plan_release(fwd);
    uwb_fft_plan_release(inv);
    fftwf_free(buf);
    fftwf_free(spec);
    return rc;
}
