#include "uwb/condition.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fft_plans.h"
#include "imaging_internal.h"
#include "select.h"
#include "trace_spectrum.h"

void uwb_condition_defaults(struct uwb_condition_options *opt)
{
    opt->remove_static = 1;
    opt->static_end_fraction = 0.25;
    opt->highpass_ratio = 0.15;
    opt->lowpass_ratio = 2.0;
    opt->gate_range_m = 0.1;
    opt->align_coupling = 1;
}

int uwb_dominant_frequency(const struct uwb_scan *scan, double *hz, char *err, size_t errlen)
{
    int S = scan->samples, nh = S / 2 + 1;
    *hz = 0.0;
    if (S < 2 || scan->positions < 1 || !(scan->sample_interval_s > 0.0)) {
        snprintf(err, errlen, "dominant frequency: a scan of %d positions x %d samples has no spectrum",
                 scan->positions, S);
        return -1;
    }
    float *in = fftwf_alloc_real((size_t)S);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)nh);
    double *power = calloc((size_t)nh, sizeof *power);
    if (!in || !spec || !power) {
        fftwf_free(in);
        fftwf_free(spec);
        free(power);
        snprintf(err, errlen, "dominant frequency: out of memory for traces of %d samples", S);
        return -1;
    }
    fftwf_plan p = uwb_fft_plan_acquire(FFT_R2C, S);
    if (!p) {
        fftwf_free(in);
        fftwf_free(spec);
        free(power);
        snprintf(err, errlen, "dominant frequency: out of memory for a transform of %d samples", S);
        return -1;
    }
    for (int k = 0; k < scan->positions; k++) {
        const float *tr = scan->data + (size_t)k * S;
        double mean = 0.0;
        for (int s = 0; s < S; s++)
            mean += tr[s];
        mean /= S;
        for (int s = 0; s < S; s++)
            in[s] = (float)(tr[s] - mean);
        fftwf_execute_dft_r2c(p, in, spec);
        /* Each trace's spectrum as a share of its own power: a gain that
         * drifts from position to position must not move the peak. On the
         * full-wave family's s04, whose spectrum is a comb with two highest
         * bins within 0.3 % of each other, 2 % rms of drift moved it from
         * 1.45 to 2.45 GHz in some draws, and the figure by 0.8 mm. */
        double total = 0.0;
        for (int i = 0; i < nh; i++)
            total += (double)spec[i][0] * spec[i][0] + (double)spec[i][1] * spec[i][1];
        if (!(total > 0.0))
            continue;
        for (int i = 0; i < nh; i++)
            power[i] += ((double)spec[i][0] * spec[i][0] + (double)spec[i][1] * spec[i][1]) / total;
    }
    uwb_fft_plan_release(p);
    int best = 1;
    for (int i = 1; i < nh; i++)
        if (power[i] > power[best])
            best = i;
    *hz = best / (S * scan->sample_interval_s);
    fftwf_free(in);
    fftwf_free(spec);
    free(power);
    return 0;
}

/* Keep the pulse's band only: a raised-cosine high-pass removes DC and
 * wander below low_hz, a raised-cosine low-pass from high_hz to 1.5 high_hz
 * removes the receiver noise above the band. A digitiser samples far above
 * the pulse's band, and the out-of-band noise would otherwise pass straight
 * through migration into the image. */
static double band_gain(double f, double low_hz, double high_hz)
{
    double g = 1.0;
    if (f <= low_hz)
        return 0.0;
    if (f < 2.0 * low_hz)
        g = 0.5 - 0.5 * cos(M_PI * (f - low_hz) / low_hz);
    if (high_hz > 0.0 && f >= high_hz) {
        if (f >= 1.5 * high_hz)
            return 0.0;
        g *= 0.5 + 0.5 * cos(M_PI * (f - high_hz) / (0.5 * high_hz));
    }
    return g;
}

struct band {
    double low_hz, high_hz;
};

static void apply_band(void *ctx, int k, fftwf_complex *spec, int n, double df_hz)
{
    const struct band *b = ctx;
    (void)k;
    for (int i = 0; i < n / 2 + 1; i++) {
        double gain = band_gain(i * df_hz, b->low_hz, b->high_hz);
        spec[i][0] *= (float)(gain / n);
        spec[i][1] *= (float)(gain / n);
    }
}

static int bandpass(struct uwb_scan *s, double low_hz, double high_hz, char *err, size_t errlen)
{
    struct band b = {low_hz, high_hz};
    return uwb_filter_traces_in_spectrum(s, NULL, apply_band, &b, "conditioning", err, errlen);
}

/* Static clutter (direct coupling, tank wall, barriers and core legs that
 * run past the aperture) is the same trace at every position; the winding's
 * echo is not. The reference at each sample is the median over the positions
 * that cannot hear the winding at that moment: those whose winding window
 * excludes it, or, before the winding is located, the positions at both ends
 * of the travel. A mean over all positions would subtract part of the flat
 * face itself, which returns at one delay wherever it is faced. */
static int positions_quiet_at(const struct uwb_scan *s, const struct uwb_geometry *g,
                              const struct uwb_target_window *w, double end_fraction, double period_s, int t,
                              int *quiet)
{
    int K = s->positions, n = 0;
    if (!w) {
        int per_end = (int)lround(K * end_fraction);
        if (per_end < 2)
            per_end = 2;
        if (2 * per_end > K)
            return 0;
        for (int j = 0; j < per_end; j++) {
            quiet[n++] = j;
            quiet[n++] = K - 1 - j;
        }
        return n;
    }
    double time = g->t0_s + t * g->dt_s;
    for (int k = 0; k < K; k++) {
        double ya = s->antenna_y_m[k];
        double y_near = ya < w->y_lo_m ? w->y_lo_m : ya > w->y_hi_m ? w->y_hi_m : ya;
        double t_first = uwb_two_way_delay(g, y_near - ya, w->z_near_m) - 2.0 * period_s;
        double t_last = fmax(uwb_two_way_delay(g, w->y_lo_m - ya, w->z_far_m),
                             uwb_two_way_delay(g, w->y_hi_m - ya, w->z_far_m)) +
                        2.0 * period_s;
        if (time < t_first || time > t_last)
            quiet[n++] = k;
    }
    return n;
}

double uwb_condition_band_gain(const struct uwb_condition_options *opt, double dominant_hz, double f_hz)
{
    return band_gain(f_hz, opt->highpass_ratio * dominant_hz, opt->lowpass_ratio * dominant_hz);
}

static int remove_static(struct uwb_scan *s, const struct uwb_geometry *g, const struct uwb_target_window *w,
                         double end_fraction, double period_s, char *err, size_t errlen)
{
    int K = s->positions, S = s->samples;
    int *quiet = malloc((size_t)K * sizeof *quiet);
    float *column = malloc((size_t)K * sizeof *column);
    float *reference = calloc((size_t)S, sizeof *reference);
    if (!quiet || !column || !reference) {
        free(quiet);
        free(column);
        free(reference);
        snprintf(err, errlen, "conditioning: out of memory");
        return -1;
    }
    for (int t = 0; t < S; t++) {
        int n = positions_quiet_at(s, g, w, end_fraction, period_s, t, quiet);
        if (n < 2)
            continue; /* every position may hear the winding: leave it be */
        for (int j = 0; j < n; j++)
            column[j] = s->data[(size_t)quiet[j] * S + t];
        reference[t] = uwb_median_float(column, (size_t)n);
    }
    for (int k = 0; k < K; k++)
        for (int t = 0; t < S; t++)
            s->data[(size_t)k * S + t] -= reference[t];
    free(quiet);
    free(column);
    free(reference);
    return 0;
}

/* Blank what arrives before a reply from gate_range could, with a one-period
 * raised-cosine ramp so the cut itself does not ring. */
static void gate_early(struct uwb_scan *s, const struct uwb_geometry *g, double gate_range_m, double period_s)
{
    double t_open = uwb_two_way_delay(g, 0.0, gate_range_m) - period_s;
    for (int t = 0; t < s->samples; t++) {
        double time = g->t0_s + t * g->dt_s, gain;
        if (time <= t_open - period_s)
            gain = 0.0;
        else if (time >= t_open)
            gain = 1.0;
        else
            gain = 0.5 - 0.5 * cos(M_PI * (time - (t_open - period_s)) / period_s);
        if (gain < 1.0)
            for (int k = 0; k < s->positions; k++)
                s->data[(size_t)k * s->samples + t] *= (float)gain;
    }
}

int uwb_condition_prepare(const struct uwb_scan *in, const struct uwb_geometry *g,
                          const struct uwb_condition_options *opt, double dominant_hz, struct uwb_scan *out,
                          char *err, size_t errlen)
{
    if (uwb_scan_copy(out, in, err, errlen) != 0)
        return -1;
    double nyquist = 0.5 / in->sample_interval_s;
    if (!(dominant_hz > 0.0) || dominant_hz >= nyquist) {
        snprintf(err, errlen, "conditioning: no usable signal spectrum (dominant frequency %.3g Hz)",
                 dominant_hz);
        uwb_scan_free(out);
        return -1;
    }
    struct uwb_alignment alignment;
    double period = 1.0 / dominant_hz;
    /* Nothing in the tank replies before the gate range: up to there the
     * traces hold the coupling and the window alone. */
    double coupling_end = uwb_two_way_delay(g, 0.0, opt->gate_range_m);
    if (bandpass(out, opt->highpass_ratio * dominant_hz, opt->lowpass_ratio * dominant_hz, err, errlen) !=
            0 ||
        (opt->align_coupling &&
         uwb_align_to_coupling(out, coupling_end, g->t0_s, period, &alignment, err, errlen) != 0)) {
        uwb_scan_free(out);
        return -1;
    }
    return 0;
}

int uwb_condition_finish(const struct uwb_scan *prepared, const struct uwb_geometry *g,
                         const struct uwb_condition_options *opt, double dominant_hz,
                         const struct uwb_target_window *winding, struct uwb_scan *out, char *err,
                         size_t errlen)
{
    if (uwb_scan_copy(out, prepared, err, errlen) != 0)
        return -1;
    if (opt->remove_static &&
        remove_static(out, g, winding, opt->static_end_fraction, 1.0 / dominant_hz, err, errlen) != 0) {
        uwb_scan_free(out);
        return -1;
    }
    gate_early(out, g, opt->gate_range_m, 1.0 / dominant_hz);
    return 0;
}

int uwb_condition(const struct uwb_scan *in, const struct uwb_geometry *g,
                  const struct uwb_condition_options *opt, double dominant_hz,
                  const struct uwb_target_window *winding, struct uwb_scan *out, char *err, size_t errlen)
{
    struct uwb_scan prepared = {0};
    if (uwb_condition_prepare(in, g, opt, dominant_hz, &prepared, err, errlen) != 0)
        return -1;
    int rc = uwb_condition_finish(&prepared, g, opt, dominant_hz, winding, out, err, errlen);
    uwb_scan_free(&prepared);
    return rc;
}

double uwb_noise_sigma(const struct uwb_scan *scan, int first_sample)
{
    if (first_sample < 0)
        first_sample = 0;
    if (first_sample >= scan->samples)
        return 0.0;
    size_t per = (size_t)(scan->samples - first_sample);
    size_t n = (size_t)scan->positions * per;
    if (n == 0)
        return 0.0;
    float *d = malloc(n * sizeof *d);
    if (!d)
        return 0.0;
    size_t m = 0;
    for (int k = 0; k < scan->positions; k++) {
        const float *tr = scan->data + (size_t)k * scan->samples;
        for (int s = first_sample; s < scan->samples; s++)
            d[m++] = fabsf(tr[s]);
    }
    double mad = uwb_median_float(d, m);
    free(d);
    return mad / 0.6745;
}

int uwb_condition_first_open_sample(const struct uwb_scan *scan, const struct uwb_geometry *g,
                                    const struct uwb_condition_options *opt, double dominant_hz)
{
    double t_open = uwb_two_way_delay(g, 0.0, opt->gate_range_m);
    (void)dominant_hz;
    int s = (int)ceil((t_open - g->t0_s) / g->dt_s);
    if (s < 0)
        s = 0;
    return s < scan->samples ? s : scan->samples;
}
