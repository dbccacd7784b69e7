/* The digitiser: trigger jitter, gain drift, noise, ADC, stacking. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_internal.h"

/* One pulse's receiver noise, sigma rms per sample, into noise[0..samples).
 * White up to Nyquist, or (noise_bandwidth_hz > 0) white noise through a
 * brick-wall low-pass on the engine's FFT grid, scaled so the per-sample rms
 * is still sigma: what a receiver front end of that bandwidth shows. */
static void pulse_noise(struct sim_engine *e, struct sim_rng *rng, double sigma, double *noise)
{
    const struct sim_scene *s = &e->scene;
    double nyquist = 0.5 / e->dt;
    if (s->noise_bandwidth_hz <= 0 || s->noise_bandwidth_hz >= nyquist) {
        for (int i = 0; i < s->samples; i++)
            noise[i] = sigma * sim_rng_normal(rng);
        return;
    }
    int n = e->nfft, nh = n / 2;
    int kmax = (int)floor(s->noise_bandwidth_hz / nyquist * nh);
    /* kept bins 1..kmax of nh carry that share of white noise's power */
    double white = sigma * sqrt((double)nh / (kmax > 0 ? kmax : 1));
    for (int i = 0; i < n; i++)
        e->rbuf[i] = (float)(white * sim_rng_normal(rng));
    fftwf_execute(e->r2c);
    for (int k = 0; k <= nh; k++)
        if (k == 0 || k > kmax)
            e->cbuf[k] = 0;
    fftwf_execute(e->c2r);
    for (int i = 0; i < s->samples; i++)
        noise[i] = e->rbuf[i] / n;
}

void sim_acq_init(struct sim_acq *acq, uint64_t seed)
{
    sim_rng_seed(&acq->rng, seed);
    acq->drift_db = 0.0;
}

int sim_engine_acquire(struct sim_engine *e, double y_ref, int stack, struct sim_acq *acq, float *out,
                       char *err, size_t errlen)
{
    const struct sim_scene *s = &e->scene;
    if (stack <= 0)
        stack = s->stack;
    double sigma = 0.0;
    if (s->noise) {
        double peak = sim_engine_peak_echo(e);
        if (peak < 0) {
            snprintf(err, errlen, "acquire: out of memory");
            return -1;
        }
        if (!(peak > 0)) {
            snprintf(err, errlen,
                     "snr_db: the winding returns nothing inside the record, so noise has no reference");
            return -1;
        }
        sigma = peak * pow(10.0, -s->snr_db / 20.0);
    }
    /* Draw order is fixed (jitter, drift, then the noise of each pulse): the
     * same seed and calls give the same numbers. */
    double shift = s->jitter_s > 0 ? s->jitter_s * sim_rng_normal(&acq->rng) : 0.0;
    double gain = pow(10.0, acq->drift_db / 20.0);
    if (s->drift_db > 0)
        acq->drift_db += s->drift_db * sim_rng_normal(&acq->rng);

    double *clean = malloc((size_t)s->samples * 3 * sizeof *clean);
    if (!clean) {
        snprintf(err, errlen, "acquire: out of memory");
        return -1;
    }
    double *sum = clean + s->samples, *noise = sum + s->samples;
    sim_engine_clean_trace(e, y_ref, SIM_PART_ALL, shift, clean);
    memset(sum, 0, (size_t)s->samples * sizeof *sum);
    double lsb = 0, code_min = 0, code_max = 0;
    if (s->adc_bits > 0) {
        lsb = 2.0 * s->adc_full_scale_v / ldexp(1.0, s->adc_bits);
        code_max = ldexp(1.0, s->adc_bits - 1) - 1;
        code_min = -ldexp(1.0, s->adc_bits - 1);
    }
    for (int p = 0; p < stack; p++) {
        if (sigma > 0)
            pulse_noise(e, &acq->rng, sigma, noise);
        for (int i = 0; i < s->samples; i++) {
            double v = clean[i] * gain;
            if (sigma > 0)
                v += noise[i];
            if (lsb > 0) {
                double code = nearbyint(v / lsb);
                v = fmin(fmax(code, code_min), code_max) * lsb;
            }
            sum[i] += v;
        }
    }
    for (int i = 0; i < s->samples; i++)
        out[i] = (float)(sum[i] / stack);
    free(clean);
    return 0;
}
