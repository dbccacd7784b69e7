#include "trace_spectrum.h"

#include <stdio.h>
#include <string.h>

int uwb_filter_traces_in_spectrum(struct uwb_scan *s, int (*skip)(void *ctx, int k),
                              trace_spectrum_fn filter, void *ctx, const char *what,
                              char *err, size_t errlen)
{
    int S = s->samples, nh = S / 2 + 1;
    float *buf = fftwf_alloc_real((size_t)S);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)nh);
    if (!buf || !spec) {
        fftwf_free(buf);
        fftwf_free(spec);
        snprintf(err, errlen, "%s: out of memory", what);
        return -1;
    }
    fftwf_plan fwd = fftwf_plan_dft_r2c_1d(S, buf, spec, FFTW_ESTIMATE);
    fftwf_plan inv = fftwf_plan_dft_c2r_1d(S, spec, buf, FFTW_ESTIMATE);
    double df = 1.0 / (S * s->sample_interval_s);
    for (int k = 0; k < s->positions; k++) {
        if (skip && skip(ctx, k))
            continue;
        float *tr = s->data + (size_t)k * S;
        memcpy(buf, tr, (size_t)S * sizeof *buf);
        fftwf_execute(fwd);
        filter(ctx, k, spec, S, df);
        fftwf_execute(inv);
        memcpy(tr, buf, (size_t)S * sizeof *buf);
    }
    fftwf_destroy_plan(fwd);
    fftwf_destroy_plan(inv);
    fftwf_free(buf);
    fftwf_free(spec);
    return 0;
}
