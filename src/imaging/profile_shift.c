/* The displacement as the shift that best maps the baseline's face profile
 * onto the current one (least squares on the face energy, the squared
 * envelope, with a free gain).
 *
 * Why not the difference of the two profiles' centres: each centre is read
 * on its own scan, where the static scene (window edges, a clamping plate, a
 * core leg's echoes crossing the face's delay) images into the face row
 * beside the winding's own image and leans each shoulder by an amount that
 * changes as the winding moves past it: on the full-wave tank scans a pure
 * shift of the whole scene read 29.94 mm for 30, the real +30 mm scan 31.29.
 * Compared with each other, the two profiles share that static image at the
 * same heights; it enters the fit only through how it differs from its own
 * shifted copy, and on the energy the static part's share is the square of
 * its share of the envelope. */
#include "imaging_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define FIT_STEP_M 0.001 /* the profiles' own pixel */
#define COARSE_STEP_M 0.0001
#define FINE_STEP_M 0.00001
#define FIT_SEARCH_M 0.005 /* around the centres' difference */

/* A profile's squared envelope, computed once per fit: the search below
 * evaluates it at some 40 000 points. */
struct energy {
    int n;
    double y0_m, dy_m;
    double *value;
};

static int energy_of(const struct uwb_face_profile *p, struct energy *e)
{
    e->n = p->n;
    e->y0_m = p->y0_m;
    e->dy_m = p->dy_m;
    e->value = malloc((size_t)(p->n > 0 ? p->n : 1) * sizeof *e->value);
    if (!e->value)
        return -1;
    for (int i = 0; i < p->n; i++)
        e->value[i] = (double)p->value[i] * p->value[i];
    return 0;
}

/* The squared envelope at y (Catmull-Rom between pixels, 0 outside). */
static double energy_at(const struct energy *p, double y)
{
    double x = (y - p->y0_m) / p->dy_m;
    int i = (int)floor(x);
    if (i < 1 || i > p->n - 3)
        return 0.0;
    double t = x - i;
    const double *v = p->value + i - 1;
    return v[1] +
           0.5 * t *
               (v[2] - v[0] +
                t * (2.0 * v[0] - 5.0 * v[1] + 4.0 * v[2] - v[3] + t * (3.0 * (v[1] - v[2]) + v[3] - v[0])));
}

/* The baseline's side of the fit does not move with the shift tried: its
 * energies over the span, and their sum of squares, once per fit. */
struct span {
    int n;
    double centre_m, half_m;
    double skip_lo_m, skip_hi_m; /* baseline rows the fit leaves out (lo >= hi: none) */
    double *base;                /* g * base(y) is fitted to these */
    double bb;
};

static double span_offset(const struct span *s, int k)
{
    return -s->half_m + k * FIT_STEP_M;
}

/* Whether point k of the span lies in the rows left out. */
static int skipped(const struct span *s, int k)
{
    double y = s->centre_m + span_offset(s, k);
    return s->skip_lo_m < s->skip_hi_m && y >= s->skip_lo_m && y <= s->skip_hi_m;
}

static int span_of(const struct energy *base, double centre_m, double half_span_m, double skip_lo_m,
                   double skip_hi_m, struct span *s)
{
    s->n = 0;
    s->skip_lo_m = skip_lo_m;
    s->skip_hi_m = skip_hi_m;
    s->centre_m = centre_m;
    s->half_m = half_span_m;
    s->bb = 0.0;
    /* Points u = -half + k FIT_STEP_M up to +half (1e-12: the end itself
     * counts despite rounding); loops count k and compute u, never
     * accumulate it. */
    s->n = half_span_m >= 0.0 ? (int)floor((2.0 * half_span_m + 1e-12) / FIT_STEP_M) + 1 : 0;
    s->base = malloc((size_t)(s->n > 0 ? s->n : 1) * sizeof *s->base);
    if (!s->base)
        return -1;
    for (int k = 0; k < s->n; k++) {
        double b = skipped(s, k) ? 0.0 : energy_at(base, centre_m + span_offset(s, k));
        s->base[k] = b;
        s->bb += b * b;
    }
    return 0;
}

/* Residual of cur(y + d) against g * base(y) over the span, g by least squares. */
static double misfit(const struct energy *cur, const struct span *s, double d)
{
    double cc = 0.0, cb = 0.0;
    for (int k = 0; k < s->n; k++) {
        if (skipped(s, k))
            continue;
        double c = energy_at(cur, s->centre_m + d + span_offset(s, k)), b = s->base[k];
        cc += c * c;
        cb += c * b;
    }
    return s->bb > 0.0 ? cc - cb * cb / s->bb : cc;
}

/* What the fit and its gradient both work on, acquired all or none and
 * freed in one place. */
struct fit_inputs {
    struct energy cur, base;
    struct span span;
};

static void fit_inputs_free(struct fit_inputs *f)
{
    free(f->cur.value);
    free(f->base.value);
    free(f->span.base);
}

static int fit_inputs_of(const struct uwb_face_profile *cur_profile,
                         const struct uwb_face_profile *base_profile, double base_centre_m,
                         double half_span_m, double skip_lo_m, double skip_hi_m, struct fit_inputs *f)
{
    *f = (struct fit_inputs){0};
    if (energy_of(cur_profile, &f->cur) != 0 || energy_of(base_profile, &f->base) != 0 ||
        span_of(&f->base, base_centre_m, half_span_m, skip_lo_m, skip_hi_m, &f->span) != 0) {
        fit_inputs_free(f);
        return -1;
    }
    return 0;
}

/* The fit, and whether its best lies inside the search (*interior): a best
 * on the search's edge is no minimum of the misfit, only where the search
 * stopped. */
static double shift_fit(const struct uwb_face_profile *cur_profile,
                        const struct uwb_face_profile *base_profile, double base_centre_m, double half_span_m,
                        double skip_lo_m, double skip_hi_m, double guess_m, int *interior)
{
    struct fit_inputs f;
    if (fit_inputs_of(cur_profile, base_profile, base_centre_m, half_span_m, skip_lo_m, skip_hi_m, &f) != 0)
        return NAN;
    double best_d = guess_m, best = INFINITY;
    int n = (int)ceil(FIT_SEARCH_M / COARSE_STEP_M), best_i = 0;
    for (int i = -n; i <= n; i++) {
        double d = guess_m + i * COARSE_STEP_M, r = misfit(&f.cur, &f.span, d);
        if (r < best) {
            best = r;
            best_d = d;
            best_i = i;
        }
    }
    *interior = best_i > -n && best_i < n;
    double centre = best_d;
    for (int i = -10; i <= 10; i++) {
        double d = centre + i * FINE_STEP_M, r = misfit(&f.cur, &f.span, d);
        if (r < best) {
            best = r;
            best_d = d;
        }
    }
    double prev = misfit(&f.cur, &f.span, best_d - FINE_STEP_M);
    double next = misfit(&f.cur, &f.span, best_d + FINE_STEP_M);
    double den = prev - 2.0 * best + next;
    if (den > 0.0) {
        double off = 0.5 * (prev - next) / den;
        if (fabs(off) <= 1.0)
            best_d += off * FINE_STEP_M;
    }
    fit_inputs_free(&f);
    return best_d;
}

double uwb_profile_shift_fit(const struct uwb_face_profile *cur_profile,
                             const struct uwb_face_profile *base_profile, double base_centre_m,
                             double half_span_m, double guess_m)
{
    int interior;
    return shift_fit(cur_profile, base_profile, base_centre_m, half_span_m, 0.0, 0.0, guess_m, &interior);
}

/* The fit compares the profiles over the baseline's winding, edge to edge
 * at half its peak: beyond, the winding's image falls off and the static
 * scene's share of the row grows. */
double uwb_analysis_shift(const struct uwb_face_profile *cur, const struct uwb_face_profile *base,
                          const struct uwb_analysis *base_analysis, double guess_m)
{
    return uwb_profile_shift_fit(cur, base, base_analysis->edges.center_m,
                                 0.5 * base_analysis->edges.height_m, guess_m);
}

int uwb_measure_shift(const struct uwb_analysis *cur, const struct uwb_analysis *base, double *shift_m,
                      char *err, size_t errlen)
{
    return uwb_measure_shift_skipping(cur, base, 0.0, 0.0, shift_m, err, errlen);
}

int uwb_measure_shift_skipping(const struct uwb_analysis *cur, const struct uwb_analysis *base,
                               double skip_lo_m, double skip_hi_m, double *shift_m, char *err, size_t errlen)
{
    if (!cur->edges.found || !base->edges.found || !cur->profile.value || !base->profile.value) {
        snprintf(err, errlen, "shift: the winding is not established in both scans");
        return -1;
    }
    double guess = cur->edges.center_m - base->edges.center_m;
    int interior;
    *shift_m = shift_fit(&cur->profile, &base->profile, base->edges.center_m, 0.5 * base->edges.height_m,
                         skip_lo_m, skip_hi_m, guess, &interior);
    if (isnan(*shift_m)) {
        snprintf(err, errlen, "shift: out of memory for the profiles' fit");
        return -1;
    }
    if (!interior) {
        snprintf(err, errlen,
                 "no shift within %.0f mm of the centres' difference (%+.2f mm) maps the baseline's face "
                 "profile onto this scan's: the fit ran to the edge of its search at %+.2f mm",
                 FIT_SEARCH_M * 1e3, guess * 1e3, *shift_m * 1e3);
        return 1;
    }
    return 0;
}

/* Each shoulder's fit spans this fraction of the winding's height either
 * side of the baseline's edge: past the half-peak crossing into the
 * floor, and in to a quarter of the face, where the other shoulder has no
 * say. */
#define SHOULDER_HALF_SPAN 0.25

int uwb_measure_shoulder_shifts(const struct uwb_analysis *cur, const struct uwb_analysis *base,
                                double *lower_m, double *upper_m, char *err, size_t errlen)
{
    if (!cur->edges.found || !base->edges.found || !cur->profile.value || !base->profile.value) {
        snprintf(err, errlen, "shoulder shifts: the winding is not established in both scans");
        return -1;
    }
    double half = SHOULDER_HALF_SPAN * base->edges.height_m;
    *lower_m = uwb_profile_shift_fit(&cur->profile, &base->profile, base->edges.lower_m, half,
                                     cur->edges.lower_m - base->edges.lower_m);
    *upper_m = uwb_profile_shift_fit(&cur->profile, &base->profile, base->edges.upper_m, half,
                                     cur->edges.upper_m - base->edges.upper_m);
    if (isnan(*lower_m) || isnan(*upper_m)) {
        snprintf(err, errlen, "shoulder shifts: out of memory for the profiles' fit");
        return -1;
    }
    return 0;
}

/* ---- the fit's sensitivity to each profile value -------------------------- */

/* Where y falls among a profile's pixels: the first of the four it reads,
 * or -1 where energy_at reads 0. */
static int cell_of(const struct energy *p, double y, double *t)
{
    double x = (y - p->y0_m) / p->dy_m;
    int i = (int)floor(x);
    if (i < 1 || i > p->n - 3)
        return -1;
    *t = x - i;
    return i - 1;
}

struct misfit_sums {
    double cc1, cb, c1b; /* sum c c', sum c b, sum c' b */
};

static struct misfit_sums sums_at(const struct energy *cur, const struct span *s, double d)
{
    struct misfit_sums m = {0};
    for (int k = 0; k < s->n; k++) {
        double t, w[4], dw[4], c = 0.0, c1 = 0.0;
        int i = cell_of(cur, s->centre_m + d + span_offset(s, k), &t);
        if (i >= 0) {
            uwb_catmull_rom_weights(t, w, dw);
            for (int j = 0; j < 4; j++) {
                c += w[j] * cur->value[i + j];
                c1 += dw[j] * cur->value[i + j] / cur->dy_m;
            }
        }
        m.cc1 += c * c1;
        m.cb += c * s->base[k];
        m.c1b += c1 * s->base[k];
    }
    return m;
}

/* d/dd of the misfit (gain eliminated): zero at the fit's optimum. */
static double misfit_slope(const struct misfit_sums *m, double bb)
{
    return 2.0 * m->cc1 - (bb > 0.0 ? 2.0 * m->cb * m->c1b / bb : 0.0);
}

int uwb_profile_shift_gradient(const struct uwb_face_profile *cur_profile,
                               const struct uwb_face_profile *base_profile, double base_centre_m,
                               double half_span_m, double d_m, double *grad_cur, double *grad_base)
{
    struct fit_inputs f;
    if (fit_inputs_of(cur_profile, base_profile, base_centre_m, half_span_m, 0.0, 0.0, &f) != 0)
        return -1;
    /* The slope's own change with d over the fit's finest step, as the
     * fit's parabola through its neighbours reads the curvature. */
    struct misfit_sums lo = sums_at(&f.cur, &f.span, d_m - FINE_STEP_M);
    struct misfit_sums hi = sums_at(&f.cur, &f.span, d_m + FINE_STEP_M);
    double curvature = (misfit_slope(&hi, f.span.bb) - misfit_slope(&lo, f.span.bb)) / (2.0 * FINE_STEP_M);
    struct misfit_sums m = sums_at(&f.cur, &f.span, d_m);
    int rc = curvature > 0.0 && f.span.bb > 0.0 ? 0 : -1;
    if (grad_cur)
        for (int i = 0; i < cur_profile->n; i++)
            grad_cur[i] = 0.0;
    if (grad_base)
        for (int i = 0; i < base_profile->n; i++)
            grad_base[i] = 0.0;
    for (int k = 0; rc == 0 && k < f.span.n; k++) {
        double u = span_offset(&f.span, k);
        double t, w[4], dw[4], c = 0.0, c1 = 0.0, b = f.span.base[k];
        int i = cell_of(&f.cur, base_centre_m + d_m + u, &t);
        if (i >= 0) {
            uwb_catmull_rom_weights(t, w, dw);
            for (int j = 0; j < 4; j++) {
                c += w[j] * f.cur.value[i + j];
                c1 += dw[j] * f.cur.value[i + j] / f.cur.dy_m;
            }
            /* dF/de for the current's energies this point reads. */
            for (int j = 0; grad_cur && j < 4; j++) {
                double dc = w[j], dc1 = dw[j] / f.cur.dy_m;
                double dF = 2.0 * (dc * c1 + c * dc1) - 2.0 * (dc * b * m.c1b + m.cb * dc1 * b) / f.span.bb;
                grad_cur[i + j] += -dF / curvature;
            }
        }
        if (!grad_base)
            continue;
        /* dF/db at this point, then back to the baseline's energies. */
        double dFdb =
            -2.0 * (c * m.c1b + m.cb * c1) / f.span.bb + 4.0 * m.cb * m.c1b * b / (f.span.bb * f.span.bb);
        int ib = cell_of(&f.base, base_centre_m + u, &t);
        if (ib >= 0) {
            uwb_catmull_rom_weights(t, w, dw);
            for (int j = 0; j < 4; j++)
                grad_base[ib + j] += -dFdb * w[j] / curvature;
        }
    }
    /* From energies (squared envelope) to the profile's envelope values. */
    for (int i = 0; grad_cur && i < cur_profile->n; i++)
        grad_cur[i] *= 2.0 * cur_profile->value[i];
    for (int i = 0; grad_base && i < base_profile->n; i++)
        grad_base[i] *= 2.0 * base_profile->value[i];
    fit_inputs_free(&f);
    return rc;
}
