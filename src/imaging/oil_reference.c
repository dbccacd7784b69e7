/* The oil's wave speed between two scans, from the static scene in front
 * of the winding (uwb/oil_reference.h).
 *
 * Why the mean trace over the positions: the barrier, the core's flanks
 * and the tank's fittings run past the aperture, so they sum in every
 * trace alike, while the winding's echo moves along the travel; the mean
 * keeps the first and blurs the second.
 *
 * Why only in front of the face, a wavelength clear of it: the face's own
 * echo and its blur move with the winding (a bulge, a shift); what lies
 * nearer does not, and its echoes travel through the same oil.
 *
 * Why the delay is scaled by the face's range over the echoes' range: a
 * change of the oil's speed stretches every range through it alike, so
 * a delay read at the echoes' range grows in proportion at the face's
 * (the window's few millimetres of other material are left in: they
 * change the scale by well under the figure's sigma). */
#include "uwb/oil_reference.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Nearer than this the window and the direct coupling reply: no oil. */
#define NEAREST_M 0.06
/* The largest range offset looked for at the echoes: 10 mm, some 2 % of
 * the oil's speed over 0.4 m, far past any temperature's. */
#define LARGEST_OFFSET_M 0.01
/* The static echoes must carry this fraction of the energy of the face's
 * echo (-30 dB) to be read at all. */
#define LEAST_ENERGY_SHARE 1e-3
/* ...and be the same scene in both scans: their correlation at its peak. */
#define LEAST_CORRELATION 0.9
/* A sub-sample delay is read to about a tenth of a sample noiseless. */
#define DELAY_FLOOR_SAMPLES 0.1

static double *mean_trace(const struct uwb_scan *s)
{
    double *m = calloc((size_t)s->samples, sizeof *m);
    if (!m)
        return NULL;
    for (int k = 0; k < s->positions; k++)
        for (int i = 0; i < s->samples; i++)
            m[i] += s->data[(size_t)k * s->samples + i];
    for (int i = 0; i < s->samples; i++)
        m[i] /= s->positions;
    return m;
}

static double correlation_at(const double *b, const double *c, int lo, int hi, int lag, int n)
{
    double bc = 0.0, bb = 0.0, cc = 0.0;
    for (int i = lo; i <= hi; i++) {
        int j = i + lag;
        double cj = j >= 0 && j < n ? c[j] : 0.0;
        bc += b[i] * cj;
        bb += b[i] * b[i];
        cc += cj * cj;
    }
    return bb > 0.0 && cc > 0.0 ? bc / sqrt(bb * cc) : 0.0;
}

/* The delay (samples, + : the current later) of c against b over samples
 * lo..hi, lags within +-max_lag: 0, or -1 when the echoes do not match. */
static int delay_samples(const double *b, const double *c, int lo, int hi, int max_lag, int n, double *delay,
                         double *peak)
{
    int best = 0;
    double best_r = -2.0;
    for (int lag = -max_lag; lag <= max_lag; lag++) {
        double r = correlation_at(b, c, lo, hi, lag, n);
        if (r > best_r) {
            best_r = r;
            best = lag;
        }
    }
    *peak = best_r;
    if (best_r < LEAST_CORRELATION || best == -max_lag || best == max_lag)
        return -1;
    double before = correlation_at(b, c, lo, hi, best - 1, n);
    double after = correlation_at(b, c, lo, hi, best + 1, n);
    double den = before - 2.0 * best_r + after;
    double offset = den < 0.0 ? 0.5 * (before - after) / den : 0.0;
    *delay = best + (fabs(offset) <= 0.5 ? offset : 0.0);
    return 0;
}

/* The energy-weighted mean sample of b over lo..hi, and the sample that
 * splits its energy in two halves. */
static void energy_centre(const double *b, int lo, int hi, double *centre, int *median)
{
    double e = 0.0, ei = 0.0;
    for (int i = lo; i <= hi; i++) {
        e += b[i] * b[i];
        ei += i * b[i] * b[i];
    }
    *centre = e > 0.0 ? ei / e : 0.5 * (lo + hi);
    double run = 0.0;
    *median = lo;
    for (int i = lo; i <= hi && run < 0.5 * e; i++) {
        run += b[i] * b[i];
        *median = i;
    }
}

static double energy(const double *b, int lo, int hi)
{
    double e = 0.0;
    for (int i = lo; i <= hi; i++)
        e += b[i] * b[i];
    return e;
}

void uwb_oil_reference_measure(const struct uwb_scan *current, const struct uwb_scan *baseline,
                               double velocity_m_s, double face_z_m, double wavelength_m,
                               struct uwb_oil_reference *ref)
{
    memset(ref, 0, sizeof *ref);
    if (current->samples != baseline->samples || current->sample_interval_s != baseline->sample_interval_s ||
        current->t0_s != baseline->t0_s || current->samples < 8) {
        snprintf(ref->why, sizeof ref->why, "the two scans' time axes differ");
        return;
    }
    int n = baseline->samples;
    double dt = baseline->sample_interval_s, t0 = baseline->t0_s;
    /* Sample at range z: two-way at the oil's speed from the time origin. */
#define SAMPLE_AT(z) ((int)floor((2.0 * (z) / velocity_m_s - t0) / dt))
    int lo = SAMPLE_AT(NEAREST_M), hi = SAMPLE_AT(face_z_m - wavelength_m);
    int face_lo = hi + 1, face_hi = SAMPLE_AT(face_z_m + wavelength_m);
#undef SAMPLE_AT
    if (lo < 0)
        lo = 0;
    if (face_hi > n - 1)
        face_hi = n - 1;
    int max_lag = (int)ceil(2.0 * LARGEST_OFFSET_M / velocity_m_s / dt);
    if (hi - lo < 4 * max_lag || face_hi <= face_lo) {
        snprintf(ref->why, sizeof ref->why, "no oil in front of the face at %.3f m range to read", face_z_m);
        return;
    }
    double *b = mean_trace(baseline), *c = mean_trace(current);
    if (!b || !c) {
        free(b);
        free(c);
        snprintf(ref->why, sizeof ref->why, "out of memory for the static echoes");
        return;
    }
    double share = energy(b, lo, hi) / fmax(energy(b, face_lo, face_hi), 1e-300);
    double centre, delay, d1, d2, peak;
    int median;
    energy_centre(b, lo, hi, &centre, &median);
    double metres_per_sample = 0.5 * velocity_m_s * dt;
    double echo_z = (t0 / dt + centre) * metres_per_sample;
    if (share < LEAST_ENERGY_SHARE)
        snprintf(ref->why, sizeof ref->why,
                 "the static echoes in front of the face are too weak to read the oil (%.0f dB of its echo)",
                 10.0 * log10(fmax(share, 1e-30)));
    else if (delay_samples(b, c, lo, hi, max_lag, n, &delay, &peak) != 0)
        snprintf(ref->why, sizeof ref->why,
                 "the static echoes in front of the face differ between the scans (correlation %.2f)", peak);
    else if (delay_samples(b, c, lo, median, max_lag, n, &d1, &peak) != 0 ||
             delay_samples(b, c, median + 1, hi, max_lag, n, &d2, &peak) != 0)
        snprintf(ref->why, sizeof ref->why,
                 "the static echoes' near and far halves do not both match between the scans");
    else {
        /* Each half's delay scaled to the face: their split is the sigma. */
        double c1, c2;
        int m1, m2;
        energy_centre(b, lo, median, &c1, &m1);
        energy_centre(b, median + 1, hi, &c2, &m2);
        double z1 = (t0 / dt + c1) * metres_per_sample, z2 = (t0 / dt + c2) * metres_per_sample;
        double scale = face_z_m / echo_z;
        double a1 = -d1 * metres_per_sample * face_z_m / z1, a2 = -d2 * metres_per_sample * face_z_m / z2;
        ref->measured = 1;
        ref->echo_range_m = echo_z;
        ref->face_offset_m = -delay * metres_per_sample * scale;
        ref->sigma_m = hypot(0.5 * fabs(a1 - a2), DELAY_FLOOR_SAMPLES * metres_per_sample * scale);
    }
    free(b);
    free(c);
}
