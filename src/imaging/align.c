/* Trigger jitter and gain drift, measured on the direct coupling.
 *
 * The direct coupling from Tx to Rx (and the window's echoes) arrive before
 * anything in the tank can reply, and they are the same at every antenna
 * position. A trace whose trigger fired a few picoseconds late, or whose
 * gain drifted, shows it there first. That matters far more than its size
 * suggests: near an edge the winding is seen at a grazing angle, where a
 * timing error dt moves the imaged edge by v dt / (2 sin theta), several
 * times the range error. Each trace is therefore shifted and scaled so its
 * early part matches the median of all of them. */
#include "uwb/condition.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "select.h"
#include "trace_spectrum.h"

#define MIN_CORRELATION 0.9 /* a trace whose early part does not look like the rest is left alone */
#define MAX_GAIN_DB 3.0     /* larger gain changes are not drift: left alone */
#define PASSES 2            /* the second reference is built from aligned traces */

/* The median trace over the early window, faded out over its last
 * `fade` samples. Only the reference is windowed: each trace is read past
 * the window's end, so a shifted trace is compared whole and the cut does
 * not pull the estimate toward zero lag. */
static void median_reference(const struct uwb_scan *s, int n_win, int fade, float *column, double *ref)
{
    for (int t = 0; t < n_win; t++) {
        for (int k = 0; k < s->positions; k++)
            column[k] = s->data[(size_t)k * s->samples + t];
        double w = 1.0;
        if (t >= n_win - fade) {
            double c = cos(0.5 * M_PI * (t - (n_win - fade) + 1) / (fade + 1));
            w = c * c;
        }
        ref[t] = w * uwb_median_float(column, (size_t)s->positions);
    }
}

/* Lag (samples, > 0 when the trace is late) maximising the correlation of
 * the trace's early window with the reference, refined with a parabola;
 * also the normalised correlation at the best integer lag. */
static double best_lag(const float *tr, int samples, const double *ref, int n_win, int max_lag, double *ncc)
{
    double best = -INFINITY, c_prev = 0.0, c_next = 0.0;
    int best_l = 0;
    double e_ref = 0.0, e_tr = 0.0;
    for (int t = 0; t < n_win; t++) {
        e_ref += ref[t] * ref[t];
        e_tr += (double)tr[t] * tr[t] * (ref[t] != 0.0);
    }
    double *c = malloc((size_t)(2 * max_lag + 1) * sizeof *c);
    if (!c) {
        *ncc = 0.0;
        return 0.0;
    }
    for (int l = -max_lag; l <= max_lag; l++) {
        double sum = 0.0;
        for (int t = 0; t < n_win; t++) {
            int u = t + l;
            if (u >= 0 && u < samples)
                sum += (double)tr[u] * ref[t];
        }
        c[l + max_lag] = sum;
        if (sum > best) {
            best = sum;
            best_l = l;
        }
    }
    *ncc = e_ref > 0.0 && e_tr > 0.0 ? best / sqrt(e_ref * e_tr) : 0.0;
    double lag = best_l;
    if (best_l > -max_lag && best_l < max_lag) {
        c_prev = c[best_l - 1 + max_lag];
        c_next = c[best_l + 1 + max_lag];
        double denom = c_prev - 2.0 * best + c_next;
        if (denom < 0.0)
            lag += 0.5 * (c_prev - c_next) / denom;
    }
    free(c);
    return lag;
}

struct correction {
    const double *lag, *gain;
};

static int uncorrected(void *ctx, int k)
{
    const struct correction *c = ctx;
    return c->lag[k] == 0.0 && c->gain[k] == 1.0;
}

/* Advance trace k by lag[k] samples (band-limited shift: a phase ramp) and
 * divide it by gain[k]. */
static void shift_and_scale(void *ctx, int k, fftwf_complex *spec, int n, double df_hz)
{
    const struct correction *corr = ctx;
    (void)df_hz;
    int nh = n / 2 + 1;
    for (int i = 0; i < nh; i++) {
        double phase = 2.0 * M_PI * i * corr->lag[k] / n, scale = 1.0 / (corr->gain[k] * n);
        double c = cos(phase) * scale, sn = sin(phase) * scale;
        double re = spec[i][0], im = spec[i][1];
        spec[i][0] = (float)(re * c - im * sn);
        spec[i][1] = (float)(re * sn + im * c);
    }
    /* Nyquist bin of an even-length transform must stay real. */
    if (n % 2 == 0)
        spec[nh - 1][1] = 0.0f;
}

int uwb_align_to_coupling(struct uwb_scan *s, double window_end_s, double t0_s, double period_s,
                          struct uwb_alignment *report, char *err, size_t errlen)
{
    memset(report, 0, sizeof *report);
    double dt = s->sample_interval_s;
    int n_win = (int)floor((window_end_s - t0_s) / dt);
    if (n_win > s->samples)
        n_win = s->samples;
    int max_lag = (int)ceil(0.25 * period_s / dt);
    if (s->positions < 3 || n_win < 4 * max_lag || max_lag < 1)
        return 0; /* the record starts too late to see the coupling: nothing to align on */
    float *column = malloc((size_t)s->positions * sizeof *column);
    double *ref = malloc((size_t)n_win * sizeof *ref);
    double *lag = calloc((size_t)s->positions, sizeof *lag);
    double *gain = malloc((size_t)s->positions * sizeof *gain);
    if (!column || !ref || !lag || !gain) {
        free(column);
        free(ref);
        free(lag);
        free(gain);
        snprintf(err, errlen, "alignment: out of memory");
        return -1;
    }
    int rc = 0;
    for (int pass = 0; pass < PASSES && rc == 0; pass++) {
        median_reference(s, n_win, (int)ceil(period_s / dt), column, ref);
        double e_ref = 0.0;
        for (int t = 0; t < n_win; t++)
            e_ref += ref[t] * ref[t];
        if (!(e_ref > 0.0))
            break;
        report->aligned = 0;
        for (int k = 0; k < s->positions; k++) {
            const float *tr = s->data + (size_t)k * s->samples;
            double ncc;
            lag[k] = best_lag(tr, s->samples, ref, n_win, max_lag, &ncc);
            gain[k] = 1.0;
            if (ncc < MIN_CORRELATION) {
                lag[k] = 0.0;
                continue;
            }
            /* Gain from the projection of the (shifted) trace on the reference. */
            double proj = 0.0;
            int whole = (int)lround(lag[k]);
            for (int t = 0; t < n_win; t++) {
                int u = t + whole;
                if (u >= 0 && u < s->samples)
                    proj += (double)tr[u] * ref[t];
            }
            double g = proj / e_ref;
            if (g > pow(10.0, -MAX_GAIN_DB / 20.0) && g < pow(10.0, MAX_GAIN_DB / 20.0))
                gain[k] = g;
            report->aligned++;
        }
        struct correction corr = {lag, gain};
        rc = uwb_filter_traces_in_spectrum(s, uncorrected, shift_and_scale, &corr, "alignment", err, errlen);
        if (pass == 0)
            for (int k = 0; k < s->positions; k++) {
                report->max_shift_s = fmax(report->max_shift_s, fabs(lag[k]) * dt);
                report->max_gain_db = fmax(report->max_gain_db, fabs(20.0 * log10(gain[k])));
            }
    }
    free(column);
    free(ref);
    free(lag);
    free(gain);
    return rc;
}
