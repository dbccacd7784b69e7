/* The face's intensity along y and where it starts and stops. */
#include "imaging_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The range of a row's brightest pixel between lo and hi, sub-pixel (a
 * parabola through it and its neighbours when both lie inside). */
static double row_peak_range(const struct uwb_image *img, int iy, int lo, int hi)
{
    const float *row = img->pix + (size_t)iy * img->nz;
    int best = lo;
    for (int iz = lo + 1; iz <= hi; iz++)
        if (row[iz] > row[best])
            best = iz;
    double offset = 0.0;
    if (best > lo && best < hi) {
        double before = row[best - 1], at = row[best], after = row[best + 1];
        double den = before - 2.0 * at + after;
        if (den < 0.0)
            offset = 0.5 * (before - after) / den;
        if (fabs(offset) > 0.5)
            offset = 0.0;
    }
    return img->z0_m + (best + offset) * img->dz_m;
}

int uwb_face_profile_measure(const struct uwb_image *img, double z_face_m, double half_width_m,
                             struct uwb_face_profile *p, struct uwb_face_profile *range, char *err,
                             size_t errlen)
{
    int lo = (int)floor((z_face_m - half_width_m - img->z0_m) / img->dz_m);
    int hi = (int)ceil((z_face_m + half_width_m - img->z0_m) / img->dz_m);
    if (lo < 0)
        lo = 0;
    if (hi > img->nz - 1)
        hi = img->nz - 1;
    if (lo > hi) {
        snprintf(err, errlen, "face range %.3f m is outside the image", z_face_m);
        return -1;
    }
    p->value = malloc((size_t)img->ny * sizeof *p->value);
    if (!p->value) {
        snprintf(err, errlen, "out of memory for the face profile");
        return -1;
    }
    if (range) {
        range->value = malloc((size_t)img->ny * sizeof *range->value);
        if (!range->value) {
            free(p->value);
            p->value = NULL;
            snprintf(err, errlen, "out of memory for the face's range profile");
            return -1;
        }
        range->n = img->ny;
        range->y0_m = img->y0_m;
        range->dy_m = img->dy_m;
    }
    p->n = img->ny;
    p->y0_m = img->y0_m;
    p->dy_m = img->dy_m;
    for (int iy = 0; iy < img->ny; iy++) {
        float best = 0.0f;
        for (int iz = lo; iz <= hi; iz++) {
            float v = img->pix[(size_t)iy * img->nz + iz];
            if (v > best)
                best = v;
        }
        /* Samples near the float range (the format allows any finite value)
         * overflow the image; a face made of infinities has no edges. */
        if (!isfinite(best)) {
            snprintf(err, errlen,
                     "the image of the face overflows single precision at y = %.3f m: the scan's "
                     "samples are too large to image",
                     img->y0_m + iy * img->dy_m);
            free(p->value);
            p->value = NULL;
            p->n = 0;
            if (range) {
                free(range->value);
                range->value = NULL;
                range->n = 0;
            }
            return -1;
        }
        p->value[iy] = best;
        if (range)
            range->value[iy] = (float)row_peak_range(img, iy, lo, hi);
    }
    return 0;
}

void uwb_profile_edges(const struct uwb_face_profile *p, double fraction, struct profile_edges *e)
{
    uwb_profile_edges_within(p, fraction, 0.0, 0.0, e);
}

void uwb_profile_edges_within(const struct uwb_face_profile *p, double fraction, double lo_m, double hi_m,
                              struct profile_edges *e)
{
    int ip = -1;
    if (lo_m < hi_m)
        for (int i = 0; i < p->n; i++) {
            double y = p->y0_m + i * p->dy_m;
            if (y >= lo_m && y <= hi_m && (ip < 0 || p->value[i] > p->value[ip]))
                ip = i;
        }
    if (ip < 0) {
        ip = 0;
        for (int i = 1; i < p->n; i++)
            if (p->value[i] > p->value[ip])
                ip = i;
    }
    double level = fraction * p->value[ip];
    e->peak = p->value[ip];
    e->peak_y_m = p->y0_m + ip * p->dy_m;
    e->ok = 0;

    int a = ip;
    while (a > 0 && p->value[a - 1] >= level)
        a--;
    int b = ip;
    while (b < p->n - 1 && p->value[b + 1] >= level)
        b++;
    if (a == 0 || b == p->n - 1)
        return;
    /* Crossing between samples a-1 (below) and a (at or above). */
    double below = p->value[a - 1], above = p->value[a];
    e->lower_m = p->y0_m + (a - 1 + (level - below) / (above - below)) * p->dy_m;
    e->slope_lower = (above - below) / p->dy_m;
    above = p->value[b];
    below = p->value[b + 1];
    e->upper_m = p->y0_m + (b + (above - level) / (above - below)) * p->dy_m;
    e->slope_upper = (above - below) / p->dy_m;
    e->ok = 1;
}

/* The profile interpolated with Catmull-Rom weights w about pixel i (the
 * four values from i - 1, clamped at the profile's ends). */
static double interpolated(const struct uwb_face_profile *p, int i, const double w[4])
{
    const float *v = p->value;
    if (i >= 1 && i + 2 <= p->n - 1)
        return w[0] * v[i - 1] + w[1] * v[i] + w[2] * v[i + 1] + w[3] * v[i + 2];
    double sum = 0.0;
    for (int j = 0; j < 4; j++) {
        int k = i - 1 + j;
        sum += w[j] * v[k < 0 ? 0 : k > p->n - 1 ? p->n - 1 : k];
    }
    return sum;
}

/* The asymmetry's offsets u = (k + 1/2) dy, k = 0 .. terms - 1, up to
 * half_span: counted, not accumulated, the same in the sum and its slope. */
static int asymmetry_terms(const struct uwb_face_profile *p, double half_span)
{
    return (int)floor(half_span / p->dy_m + 0.5);
}

static double asymmetry(const struct uwb_face_profile *p, double c, double half_span)
{
    /* c + u and c - u move by whole pixels from one term to the next, so
     * each side's interpolation weights are the same for every term: the
     * search calls this some thousand times a pass. */
    double xa = (c + 0.5 * p->dy_m - p->y0_m) / p->dy_m, xb = (c - 0.5 * p->dy_m - p->y0_m) / p->dy_m;
    int ia = (int)floor(xa), ib = (int)floor(xb);
    double wa[4], wb[4], slope_weights[4];
    uwb_catmull_rom_weights(xa - ia, wa, slope_weights);
    uwb_catmull_rom_weights(xb - ib, wb, slope_weights);
    double sum = 0.0;
    int terms = asymmetry_terms(p, half_span);
    for (int k = 0; k < terms; k++) {
        double d = interpolated(p, ia + k, wa) - interpolated(p, ib - k, wb);
        sum += d * d;
    }
    return sum;
}

double uwb_profile_symmetry_centre(const struct uwb_face_profile *p, double guess_m, double half_span_m,
                                   double search_m)
{
    double step = 0.25 * p->dy_m;
    int n = (int)ceil(search_m / step);
    double best_c = guess_m, best = INFINITY, prev = 0, next = 0;
    for (int i = -n; i <= n; i++) {
        double c = guess_m + i * step;
        double s = asymmetry(p, c, half_span_m);
        if (s < best) {
            best = s;
            best_c = c;
        }
    }
    /* Refine with a parabola through the best and its neighbours. */
    prev = asymmetry(p, best_c - step, half_span_m);
    next = asymmetry(p, best_c + step, half_span_m);
    double denom = prev - 2.0 * best + next;
    if (denom > 0.0) {
        double off = 0.5 * (prev - next) / denom;
        if (fabs(off) <= 1.0)
            best_c += off * step;
    }
    return best_c;
}

/* Catmull-Rom weights of the four values profile_at reads at x (in
 * pixels), and of its slope per pixel; idx gets their (clamped) indices. */
static void profile_weights(const struct uwb_face_profile *p, double y, int idx[4], double w[4], double dw[4])
{
    double x = (y - p->y0_m) / p->dy_m;
    int i = (int)floor(x);
    double t = x - i;
    for (int j = 0; j < 4; j++) {
        int k = i - 1 + j;
        idx[j] = k < 0 ? 0 : k > p->n - 1 ? p->n - 1 : k;
    }
    uwb_catmull_rom_weights(t, w, dw);
}

/* dA/dc of the asymmetry at c (per metre), and when grad is not NULL its
 * derivative with each profile value added to grad times scale. */
static double asymmetry_slope(const struct uwb_face_profile *p, double c, double half_span, double *grad,
                              double scale)
{
    double slope = 0.0;
    int terms = asymmetry_terms(p, half_span);
    for (int k = 0; k < terms; k++) {
        double u = (k + 0.5) * p->dy_m;
        int ia[4], ib[4];
        double wa[4], dwa[4], wb[4], dwb[4], pa = 0, pb = 0, sa = 0, sb = 0;
        profile_weights(p, c + u, ia, wa, dwa);
        profile_weights(p, c - u, ib, wb, dwb);
        for (int j = 0; j < 4; j++) {
            pa += wa[j] * p->value[ia[j]];
            pb += wb[j] * p->value[ib[j]];
            sa += dwa[j] * p->value[ia[j]] / p->dy_m;
            sb += dwb[j] * p->value[ib[j]] / p->dy_m;
        }
        double d = pa - pb, ds = sa - sb;
        slope += 2.0 * d * ds;
        if (!grad)
            continue;
        for (int j = 0; j < 4; j++) {
            grad[ia[j]] += scale * 2.0 * (wa[j] * ds + d * dwa[j] / p->dy_m);
            grad[ib[j]] -= scale * 2.0 * (wb[j] * ds + d * dwb[j] / p->dy_m);
        }
    }
    return slope;
}

int uwb_profile_symmetry_centre_gradient(const struct uwb_face_profile *p, double c_m, double half_span_m,
                                         double *grad)
{
    double eps = 0.01 * p->dy_m;
    double curvature = (asymmetry_slope(p, c_m + eps, half_span_m, NULL, 0.0) -
                        asymmetry_slope(p, c_m - eps, half_span_m, NULL, 0.0)) /
                       (2.0 * eps);
    if (!(curvature > 0.0))
        return -1;
    asymmetry_slope(p, c_m, half_span_m, grad, -1.0 / curvature);
    return 0;
}
