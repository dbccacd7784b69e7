#include "uwb/condition.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "select.h"

void uwb_condition_defaults(struct uwb_condition_options *opt)
{
    opt->remove_static = 1;
    opt->static_end_fraction = 0.25;
    opt->highpass_ratio = 0.15;
    opt->gate_range_m = 0.1;
}

double uwb_dominant_frequency(const struct uwb_scan *scan)
{
    int S = scan->samples, nh = S / 2 + 1;
    float *in = fftwf_alloc_real((size_t)S);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)nh);
    double *power = calloc((size_t)nh, sizeof *power);
    double f_best = 0.0;
    if (in && spec && power) {
        fftwf_plan p = fftwf_plan_dft_r2c_1d(S, in, spec, FFTW_ESTIMATE);
        for (int k = 0; k < scan->positions; k++) {
            const float *tr = scan->data + (size_t)k * S;
            double mean = 0.0;
            for (int s = 0; s < S; s++)
                mean += tr[s];
            mean /= S;
            for (int s = 0; s < S; s++)
                in[s] = (float)(tr[s] - mean);
            fftwf_execute(p);
            for (int i = 0; i < nh; i++)
                power[i] += (double)spec[i][0] * spec[i][0] + (double)spec[i][1] * spec[i][1];
        }
        fftwf_destroy_plan(p);
        int best = 1;
        for (int i = 1; i < nh; i++)
            if (power[i] > power[best])
                best = i;
        f_best = best / (S * scan->sample_interval_s);
    }
    fftwf_free(in);
    fftwf_free(spec);
    free(power);
    return f_best;
}

/* Remove DC and wander below the cut-off with a raised-cosine high-pass. */
static int highpass(struct uwb_scan *s, double cutoff_hz, char *err, size_t errlen)
{
    int S = s->samples, nh = S / 2 + 1;
    float *buf = fftwf_alloc_real((size_t)S);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)nh);
    if (!buf || !spec) {
        fftwf_free(buf);
        fftwf_free(spec);
        snprintf(err, errlen, "conditioning: out of memory");
        return -1;
    }
    fftwf_plan fwd = fftwf_plan_dft_r2c_1d(S, buf, spec, FFTW_ESTIMATE);
    fftwf_plan inv = fftwf_plan_dft_c2r_1d(S, spec, buf, FFTW_ESTIMATE);
    double df = 1.0 / (S * s->sample_interval_s);
    for (int k = 0; k < s->positions; k++) {
        float *tr = s->data + (size_t)k * S;
        memcpy(buf, tr, (size_t)S * sizeof *buf);
        fftwf_execute(fwd);
        for (int i = 0; i < nh; i++) {
            double f = i * df, gain;
            if (f <= cutoff_hz)
                gain = 0.0;
            else if (f >= 2.0 * cutoff_hz)
                gain = 1.0;
            else
                gain = 0.5 - 0.5 * cos(M_PI * (f - cutoff_hz) / cutoff_hz);
            spec[i][0] *= (float)(gain / S);
            spec[i][1] *= (float)(gain / S);
        }
        fftwf_execute(inv);
        memcpy(tr, buf, (size_t)S * sizeof *buf);
    }
    fftwf_destroy_plan(fwd);
    fftwf_destroy_plan(inv);
    fftwf_free(buf);
    fftwf_free(spec);
    return 0;
}

/* Static clutter (direct coupling, tank wall, barriers and core legs that
 * run past the aperture) is the same trace at every position; the winding's
 * echo is not. The reference at each sample is the median over the positions
 * that cannot hear the winding at that moment: those whose winding window
 * excludes it, or, before the winding is located, the positions at both ends
 * of the travel. A mean over all positions would subtract part of the flat
 * face itself, which returns at one delay wherever it is faced. */
static int positions_quiet_at(const struct uwb_scan *s, const struct uwb_geometry *g,
                              const struct uwb_target_window *w, double end_fraction,
                              double period_s, int t, int *quiet)
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
                             uwb_two_way_delay(g, w->y_hi_m - ya, w->z_far_m)) + 2.0 * period_s;
        if (time < t_first || time > t_last)
            quiet[n++] = k;
    }
    return n;
}

static int remove_static(struct uwb_scan *s, const struct uwb_geometry *g,
                         const struct uwb_target_window *w, double end_fraction,
                         double period_s, char *err, size_t errlen)
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
            continue;   /* every position may hear the winding: leave it be */
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
static void gate_early(struct uwb_scan *s, const struct uwb_geometry *g,
                       double gate_range_m, double period_s)
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

int uwb_condition(const struct uwb_scan *in, const struct uwb_geometry *g,
                  const struct uwb_condition_options *opt, double dominant_hz,
                  const struct uwb_target_window *winding, struct uwb_scan *out,
                  char *err, size_t errlen)
{
    if (uwb_scan_copy(out, in, err, errlen) != 0)
        return -1;
    double nyquist = 0.5 / in->sample_interval_s;
    if (!(dominant_hz > 0.0) || dominant_hz >= nyquist) {
        snprintf(err, errlen, "conditioning: no usable signal spectrum (dominant frequency %.3g Hz)", dominant_hz);
        uwb_scan_free(out);
        return -1;
    }
    if (highpass(out, opt->highpass_ratio * dominant_hz, err, errlen) != 0 ||
        (opt->remove_static && remove_static(out, g, winding, opt->static_end_fraction,
                                             1.0 / dominant_hz, err, errlen) != 0)) {
        uwb_scan_free(out);
        return -1;
    }
    gate_early(out, g, opt->gate_range_m, 1.0 / dominant_hz);
    return 0;
}

double uwb_noise_sigma(const struct uwb_scan *scan)
{
    size_t n = (size_t)scan->positions * (scan->samples - 1);
    if (n == 0)
        return 0.0;
    float *d = malloc(n * sizeof *d);
    if (!d)
        return 0.0;
    size_t m = 0;
    for (int k = 0; k < scan->positions; k++) {
        const float *tr = scan->data + (size_t)k * scan->samples;
        for (int s = 0; s + 1 < scan->samples; s++)
            d[m++] = fabsf(tr[s + 1] - tr[s]);
    }
    double mad = uwb_median_float(d, m);
    free(d);
    return mad / (0.6745 * sqrt(2.0));
}
