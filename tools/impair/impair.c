#include "impair/impair.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/condition.h"
#include "uwb/geometry.h"
#include "uwbsim/rng.h"

#define GATE_RANGE_M 0.1
#define GATE_PERIODS 2.0

double uwb_impair_gate_s(const struct uwb_scan *scan)
{
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, scan, 0.0);
    double f;
    char err[160];
    /* No spectrum (or no memory for it): no ringing to wait out, gate at the range alone. */
    double periods = uwb_dominant_frequency(scan, &f, err, sizeof err) == 0 ? GATE_PERIODS / f : 0.0;
    return uwb_two_way_delay(&g, 0.0, GATE_RANGE_M) + periods;
}

static double reference_peak(const struct uwb_scan *scan, double gate_s)
{
    int first = (int)ceil((gate_s - scan->t0_s) / scan->sample_interval_s);
    if (first < 0)
        first = 0;
    double peak = 0.0;
    for (int k = 0; k < scan->positions; k++) {
        const float *tr = scan->data + (size_t)k * scan->samples;
        for (int i = first; i < scan->samples; i++)
            peak = fmax(peak, fabs((double)tr[i]));
    }
    return peak;
}

/* Delay every trace k by shift_s[k] seconds (a linear phase ramp on a
 * zero-padded transform: nothing wraps round from the record's end). */
static int delay_traces(struct uwb_scan *scan, const double *shift_s, char *err, size_t errlen)
{
    int n = 2 * scan->samples, nh = n / 2;
    float *buf = fftwf_alloc_real((size_t)n);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)nh + 1);
    if (!buf || !spec) {
        fftwf_free(buf);
        fftwf_free(spec);
        snprintf(err, errlen, "impair: out of memory for the jitter transform");
        return -1;
    }
    fftwf_plan fwd = fftwf_plan_dft_r2c_1d(n, buf, spec, FFTW_ESTIMATE);
    fftwf_plan inv = fftwf_plan_dft_c2r_1d(n, spec, buf, FFTW_ESTIMATE);
    for (int k = 0; k < scan->positions; k++) {
        float *tr = scan->data + (size_t)k * scan->samples;
        memcpy(buf, tr, (size_t)scan->samples * sizeof *buf);
        memset(buf + scan->samples, 0, (size_t)(n - scan->samples) * sizeof *buf);
        fftwf_execute(fwd);
        for (int i = 0; i <= nh; i++) {
            double phase = -2.0 * M_PI * i / (n * scan->sample_interval_s) * shift_s[k];
            double c = cos(phase), s = sin(phase), re = spec[i][0], im = spec[i][1];
            /* The Nyquist bin of a real signal must stay real. */
            if (i == nh) {
                spec[i][0] = (float)(re * c / n);
                spec[i][1] = 0.0f;
                continue;
            }
            spec[i][0] = (float)((re * c - im * s) / n);
            spec[i][1] = (float)((re * s + im * c) / n);
        }
        fftwf_execute(inv);
        memcpy(tr, buf, (size_t)scan->samples * sizeof *tr);
    }
    fftwf_destroy_plan(fwd);
    fftwf_destroy_plan(inv);
    fftwf_free(buf);
    fftwf_free(spec);
    return 0;
}

int uwb_impair_scan(struct uwb_scan *scan, const struct uwb_impairment *imp,
                    struct uwb_impairment_report *report, char *err, size_t errlen)
{
    struct uwb_impairment_report rep = {0};
    rep.gate_s = uwb_impair_gate_s(scan);
    rep.reference_peak = reference_peak(scan, rep.gate_s);
    if (imp->add_noise) {
        if (!(rep.reference_peak > 0.0)) {
            snprintf(err, errlen,
                     "impair: the scan is silent after %.3f ns, so the noise has no "
                     "reference",
                     rep.gate_s * 1e9);
            return -1;
        }
        rep.noise_sigma = rep.reference_peak * pow(10.0, -imp->snr_db / 20.0);
    }
    int K = scan->positions;
    double *shift = malloc((size_t)K * sizeof *shift), *gain = malloc((size_t)K * sizeof *gain);
    if (!shift || !gain) {
        free(shift);
        free(gain);
        snprintf(err, errlen, "impair: out of memory");
        return -1;
    }
    struct sim_rng rng;
    sim_rng_seed(&rng, imp->seed);
    for (int k = 0; k < K; k++) {
        double j = sim_rng_normal(&rng), r = sim_rng_normal(&rng);
        shift[k] = imp->jitter_s * j;
        gain[k] = 1.0 + imp->drift_linear * (K > 1 ? (double)k / (K - 1) : 0.0) + imp->drift_random * r;
    }
    int rc = 0;
    if (imp->jitter_s > 0.0)
        rc = delay_traces(scan, shift, err, errlen);
    for (int k = 0; k < K && rc == 0; k++) {
        float *tr = scan->data + (size_t)k * scan->samples;
        for (int i = 0; i < scan->samples; i++)
            tr[i] = (float)(tr[i] * gain[k] + rep.noise_sigma * sim_rng_normal(&rng));
    }
    free(shift);
    free(gain);
    if (report)
        *report = rep;
    return rc;
}
