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

#define FIT_STEP_M 0.001          /* the profiles' own pixel */
#define COARSE_STEP_M 0.0001
#define FINE_STEP_M 0.00001
#define FIT_SEARCH_M 0.005        /* around the centres' difference */

/* The squared envelope at y (Catmull-Rom between pixels, 0 outside). */
static double energy_at(const struct uwb_face_profile *p, double y)
{
    double x = (y - p->y0_m) / p->dy_m;
    int i = (int)floor(x);
    if (i < 1 || i > p->n - 3)
        return 0.0;
    double t = x - i, v[4];
    for (int j = 0; j < 4; j++) {
        double e = p->value[i - 1 + j];
        v[j] = e * e;
    }
    return v[1] + 0.5 * t * (v[2] - v[0] +
                             t * (2.0 * v[0] - 5.0 * v[1] + 4.0 * v[2] - v[3] +
                                  t * (3.0 * (v[1] - v[2]) + v[3] - v[0])));
}

/* Residual of cur(y + d) against g * base(y) over the span, g by least squares. */
static double misfit(const struct uwb_face_profile *cur, const struct uwb_face_profile *base,
                     double centre_m, double half_span_m, double d)
{
    double cc = 0.0, cb = 0.0, bb = 0.0;
    for (double u = -half_span_m; u <= half_span_m + 1e-12; u += FIT_STEP_M) {
        double c = energy_at(cur, centre_m + d + u), b = energy_at(base, centre_m + u);
        cc += c * c;
        cb += c * b;
        bb += b * b;
    }
    return bb > 0.0 ? cc - cb * cb / bb : cc;
}

double uwb_profile_shift_fit(const struct uwb_face_profile *cur, const struct uwb_face_profile *base,
                         double base_centre_m, double half_span_m, double guess_m)
{
    double best_d = guess_m, best = INFINITY;
    int n = (int)ceil(FIT_SEARCH_M / COARSE_STEP_M);
    for (int i = -n; i <= n; i++) {
        double d = guess_m + i * COARSE_STEP_M, r = misfit(cur, base, base_centre_m, half_span_m, d);
        if (r < best) {
            best = r;
            best_d = d;
        }
    }
    double centre = best_d;
    for (int i = -10; i <= 10; i++) {
        double d = centre + i * FINE_STEP_M, r = misfit(cur, base, base_centre_m, half_span_m, d);
        if (r < best) {
            best = r;
            best_d = d;
        }
    }
    double prev = misfit(cur, base, base_centre_m, half_span_m, best_d - FINE_STEP_M);
    double next = misfit(cur, base, base_centre_m, half_span_m, best_d + FINE_STEP_M);
    double den = prev - 2.0 * best + next;
    if (den > 0.0) {
        double off = 0.5 * (prev - next) / den;
        if (fabs(off) <= 1.0)
            best_d += off * FINE_STEP_M;
    }
    return best_d;
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

int uwb_measure_shift(const struct uwb_analysis *cur, const struct uwb_analysis *base,
                      double *shift_m, char *err, size_t errlen)
{
    if (!cur->edges.found || !base->edges.found || !cur->profile.value || !base->profile.value) {
        snprintf(err, errlen, "shift: the winding is not established in both scans");
        return -1;
    }
    *shift_m = uwb_analysis_shift(&cur->profile, &base->profile, base,
                              cur->edges.center_m - base->edges.center_m);
    return 0;
}
