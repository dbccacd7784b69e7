/* The rig checked against the baseline through the static scene (see
 * uwb/rig_check.h). On the conditioned traces (what is the same at every
 * position already taken out), before the winding can reply: the envelope
 * of each trace, less its mean over the positions, is what varies with
 * height in the static scene; the baseline's is slid along y onto the
 * current one. In the data, not the image: a migrated image of a truncated
 * aperture carries artefacts tied to the scan's own y, which read as "not
 * moved" whatever the rig did. */
#include "uwb/rig_check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/envelope.h"
#include "uwb/geometry.h"

#define NEAR_M 0.10          /* conditioning blanks replies from nearer than this */
#define WINDING_REACH_M 0.06 /* the winding may be this far from the baseline's (and the search's reach) */
#define SHIFT_STEP_M 0.0005  /* the search's grid, refined by a parabola */
#define MIN_SAMPLES 500      /* fewer before the winding replies: nothing to check */
#define MIN_STRUCTURE 4.0    /* the static scene's height-varying power over the noise's, at least */
/* The window before the winding also holds the winding's own sidelobes and
 * what conditioning leaves of it, which move with it: -57...-77 dB under its
 * peak power on the simulated tank at 20-60 dB of SNR, -65 dB on the paper's
 * pair in air; a real static scene lies at -26...-37 dB. */
#define MIN_BELOW_WINDING_DB (-45.0)
#define MIN_SIMILARITY 0.5 /* below, the static scene is not the baseline's */
#define SIGMAS 5.0         /* a shift this many sigma off zero is the rig's */
#define MIN_SHIFT_M 0.003  /* and never less: the fit's floor on noiseless scans */

struct bscan {
    int k, s;
    float *env; /* k * s: envelope, less its mean over positions */
    char *use;  /* k * s: before the winding and after the blanking */
    const double *y;
    double dy; /* position step (uniform) */
};

/* Leaves b empty, so that freeing it again (the caller's cleanup after a
 * failed static_bscan) does nothing. */
static void bscan_free(struct bscan *b)
{
    free(b->env);
    free(b->use);
    b->env = NULL;
    b->use = NULL;
}

/* The envelope of each conditioned trace, masked to the static scene: after
 * the blanking and before the earliest reply the baseline's winding, moved
 * by up to WINDING_REACH_M, could send (less two periods). */
static int static_bscan(const struct uwb_analysis *a, const struct uwb_scan *s,
                        const struct uwb_analysis *baseline, struct bscan *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    float *env = malloc((size_t)s->positions * (size_t)s->samples * sizeof *env);
    if (!env) {
        snprintf(err, errlen, "rig check: out of memory for %d x %d envelopes", s->positions, s->samples);
        return -1;
    }
    if (uwb_envelope_of_traces(s, env, err, errlen) != 0) {
        free(env);
        return -1;
    }
    out->k = s->positions;
    out->s = s->samples;
    out->env = env;
    out->y = s->antenna_y_m;
    out->dy =
        s->positions > 1 ? (s->antenna_y_m[s->positions - 1] - s->antenna_y_m[0]) / (s->positions - 1) : 0;
    out->use = calloc((size_t)out->k * (size_t)out->s, 1);
    if (!out->use) {
        bscan_free(out);
        snprintf(err, errlen, "rig check: out of memory");
        return -1;
    }
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, s, 0.0);
    const struct uwb_edges *e = &baseline->edges;
    double periods = a->dominant_hz > 0 ? 2.0 / a->dominant_hz : 1e-9;
    for (int k = 0; k < out->k; k++) {
        double lo = e->lower_m - WINDING_REACH_M, hi = e->upper_m + WINDING_REACH_M;
        double nearest = s->antenna_y_m[k] < lo ? lo : s->antenna_y_m[k] > hi ? hi : s->antenna_y_m[k];
        double t_end = uwb_two_way_delay(&g, nearest - s->antenna_y_m[k], e->face_z_m) - periods;
        double t_start = uwb_two_way_delay(&g, 0.0, NEAR_M);
        for (int i = 0; i < out->s; i++) {
            double t = s->t0_s + i * s->sample_interval_s;
            out->use[(size_t)k * out->s + i] = t >= t_start && t < t_end;
        }
    }
    /* What is the same at every position carries no height. */
    for (int i = 0; i < out->s; i++) {
        double sum = 0;
        for (int k = 0; k < out->k; k++)
            sum += out->env[(size_t)k * out->s + i];
        for (int k = 0; k < out->k; k++)
            out->env[(size_t)k * out->s + i] -= (float)(sum / out->k);
    }
    return 0;
}

/* The baseline's envelope at height y (between positions, linearly) and
 * sample i; 0 with *ok = 0 outside its positions or its static mask. */
static double at_height(const struct bscan *b, double y, int i, int *ok)
{
    double f = (y - b->y[0]) / b->dy;
    int k = (int)floor(f);
    *ok = 0;
    if (k < 0 || k > b->k - 1 || (k == b->k - 1 && f > k))
        return 0;
    if (k == b->k - 1)
        k--, f = k + 1;
    f -= k;
    size_t lo = (size_t)k * b->s + i, hi = lo + b->s;
    if (!b->use[lo] || !b->use[hi])
        return 0;
    *ok = 1;
    return (1 - f) * b->env[lo] + f * b->env[hi];
}

/* Normalised correlation of the current B-scan with the baseline's read
 * `shift` higher; with the least-squares residual (free gain), the
 * baseline's squared slope along y and the count, for the shift's sigma. */
static double correlation(const struct bscan *c, const struct bscan *b, double shift, double *residual,
                          double *slope2, long *count, double *energy_c, double *energy_b)
{
    double cb = 0, cc = 0, bb = 0, ss = 0, h = 0.25 * b->dy;
    long n = 0;
    for (int k = 0; k < c->k; k++)
        for (int i = 0; i < c->s; i++) {
            if (!c->use[(size_t)k * c->s + i])
                continue;
            int ok, up_ok, down_ok;
            double bv = at_height(b, c->y[k] + shift, i, &ok);
            if (!ok)
                continue;
            double cv = c->env[(size_t)k * c->s + i];
            cb += cv * bv;
            cc += cv * cv;
            bb += bv * bv;
            double up = at_height(b, c->y[k] + shift + h, i, &up_ok);
            double down = at_height(b, c->y[k] + shift - h, i, &down_ok);
            if (up_ok && down_ok)
                ss += (up - down) * (up - down) / (4 * h * h);
            n++;
        }
    double gain = bb > 0 ? cb / bb : 0;
    if (residual)
        *residual = cc - gain * cb;
    if (energy_c)
        *energy_c = n ? cc / n : 0;
    if (energy_b)
        *energy_b = n ? bb / n : 0;
    if (slope2)
        *slope2 = ss * gain * gain;
    if (count)
        *count = n;
    return cc > 0 && bb > 0 ? cb / sqrt(cc * bb) : 0.0;
}

static void describe(struct uwb_rig_check *out, const double *displacement_m)
{
    char winding[64] = "";
    if (displacement_m)
        snprintf(winding, sizeof winding, " (the winding read %+.1f mm)", *displacement_m * 1e3);
    if (out->similarity < MIN_SIMILARITY)
        snprintf(out->why, sizeof out->why,
                 "rig geometry changed: the static scene in front of the winding is not the baseline's "
                 "(similarity %.2f at best, there %+.1f mm): home switch or steps_per_mm?",
                 out->similarity, out->shift_m * 1e3);
    else
        snprintf(out->why, sizeof out->why,
                 "rig geometry changed: the static scene moved %+.1f mm (sigma %.2f mm) against the "
                 "baseline%s: home switch or steps_per_mm?",
                 out->shift_m * 1e3, out->sigma_m * 1e3, winding);
}

int uwb_rig_check(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                  const double *displacement_m, struct uwb_rig_check *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    /* Both scans conditioned alike: around their own windings when the
     * current one's was found, else both as the face search saw them (the
     * static reference from the travel's ends). A scale error can smear
     * the winding past finding, which is when the check matters most;
     * mixing the two conditionings would read a rig fault in any scan (a
     * static scene 0.13 alike on an unmoved tank scan). */
    const struct uwb_scan *cs = &current->conditioned, *bs = &baseline->conditioned;
    if (!cs->data) {
        cs = &current->searched;
        bs = &baseline->searched;
    }
    if (!baseline->edges.found || !cs->data || !bs->data || cs->positions != bs->positions ||
        cs->samples != bs->samples || cs->positions < 3) {
        snprintf(out->why, sizeof out->why, "no winding in the baseline, or scans of different shapes");
        return 0;
    }
    struct bscan c = {0}, b = {0};
    double *r_at = NULL;
    int rc = -1;
    if (static_bscan(current, cs, baseline, &c, err, errlen) != 0 ||
        static_bscan(baseline, bs, baseline, &b, err, errlen) != 0)
        goto done;
    rc = 0; /* from here on, a rig that cannot be checked is no error */
    long n = 0;
    correlation(&c, &b, 0.0, NULL, NULL, &n, &out->structure_current, &out->structure_baseline);
    if (n < MIN_SAMPLES || !(b.dy > 0)) {
        snprintf(out->why, sizeof out->why,
                 "%ld samples before the winding replies: too few to check the rig", n);
        goto done;
    }
    /* Mean squares of the height-varying static scene, in units of the
     * noise's: under STRUCTURE in both, nothing there to check against. */
    double noise2 =
        fmax(current->noise_sigma * current->noise_sigma, baseline->noise_sigma * baseline->noise_sigma);
    double peak = 0;
    for (size_t i = 0; i < (size_t)bs->positions * (size_t)bs->samples; i++)
        peak = fmax(peak, fabs(bs->data[i]));
    out->below_winding_db = 10 * log10(fmax(out->structure_baseline, 1e-300) / (peak * peak));
    if (noise2 > 0) {
        out->structure_current /= noise2;
        out->structure_baseline /= noise2;
    }
    if ((noise2 > 0 && out->structure_current < MIN_STRUCTURE && out->structure_baseline < MIN_STRUCTURE) ||
        out->below_winding_db < MIN_BELOW_WINDING_DB) {
        snprintf(
            out->why, sizeof out->why,
            "no static echo before the winding varies with height (%.1f and %.1f x the noise power, %.0f dB "
            "under the winding)",
            out->structure_current, out->structure_baseline, -out->below_winding_db);
        goto done;
    }
    out->checked = 1;
    int reach = (int)lround(WINDING_REACH_M / SHIFT_STEP_M);
    double best = -2;
    int best_i = 0;
    r_at = malloc((size_t)(2 * reach + 1) * sizeof *r_at);
    if (!r_at) {
        snprintf(err, errlen, "rig check: out of memory");
        rc = -1;
        goto done;
    }
    for (int i = -reach; i <= reach; i++) {
        r_at[i + reach] = correlation(&c, &b, i * SHIFT_STEP_M, NULL, NULL, NULL, NULL, NULL);
        if (r_at[i + reach] > best) {
            best = r_at[i + reach];
            best_i = i;
        }
    }
    double best_shift = best_i * SHIFT_STEP_M;
    int j = best_i + reach;
    if (j > 0 && j < 2 * reach) { /* a parabola through the peak and its neighbours */
        double l = r_at[j - 1], m = r_at[j], r = r_at[j + 1], den = l - 2 * m + r;
        if (den < 0)
            best_shift += 0.5 * (l - r) / den * SHIFT_STEP_M;
    }
    double residual = 0, slope2 = 0;
    out->similarity = correlation(&c, &b, best_shift, &residual, &slope2, &n, NULL, NULL);
    /* The current trace at y is the baseline's at y + shift: what stood at
     * y now reads that much lower. */
    out->shift_m = -best_shift;
    /* Samples are correlated over about half a period: count those cells. */
    double per_cell = current->dominant_hz > 0 ? 0.5 / current->dominant_hz / cs->sample_interval_s : 1;
    double var = n > 1 ? residual / (double)n : 0;
    out->sigma_m = slope2 > 0 ? sqrt(var * per_cell / slope2) : INFINITY;
    /* The static scene never moves: a shift of it is the rig's, whatever
     * the winding read. A home slip moves it with the winding; a scale
     * error (steps_per_mm, a pulley's pitch) by its height times the error,
     * more or less than the winding. What the winding leaves in this
     * window, and would move with it, is kept out by the level gate above. */
    int significant = fabs(out->shift_m) > SIGMAS * out->sigma_m && fabs(out->shift_m) > MIN_SHIFT_M;
    out->moved = out->similarity < MIN_SIMILARITY || significant;
    if (out->moved)
        describe(out, displacement_m);
done:
    free(r_at);
    bscan_free(&c);
    bscan_free(&b);
    return rc;
}
