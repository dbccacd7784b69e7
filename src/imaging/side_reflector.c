/* A clamping plate level with the face images into the winding's range cell,
 * and its blob leans the winding's shoulder toward it: the centre reads
 * several millimetres off at large shifts, because the winding moves and the
 * plate does not. The winding's face row is mirror symmetric about its centre
 * (the aperture is tapered symmetric about it); the plate's is not. So the
 * row's antisymmetric part, I(c+u) - I(c-u), is the plate's image minus its
 * mirror, and fitting it with the image of one point echo, built from the
 * face's own echo, finds where the plate is and how strong. Its echo is then
 * taken out of the traces, and the face is measured again. */
#include "side_reflector.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "trace_spectrum.h"

#define ECHO_HALF_PERIODS 1.5 /* the echo model: +-1.5 periods of the face echo */
#define ROW_HALF_SPAN_M 0.3   /* the antisymmetric part is compared this far out */
#define ROW_STEP_M 0.001
#define CLEAR_OF_EDGE_M 0.02 /* a reflector starts this far beyond the winding's end */
#define COARSE_STEP_M 0.003
#define FINE_STEP_M 0.0005
#define MIN_EXPLAINED 0.25    /* below this share of the asymmetry, leave the traces be */
#define MIN_RELATIVE_PEAK 0.1 /* ...or below -20 dB of the face: noise, not a plate */
/* A point's echo falls off as a line scatterer's (R^-1.5, the plate's edge
 * runs along x) times the antennas' obliquity. */
#define SPREADING_POWER 1.5
#define OBLIQUITY_POWER 2.0

static void hilbert_spectrum(void *ctx, int k, fftwf_complex *spec, int n, double df_hz)
{
    (void)ctx;
    (void)k;
    (void)df_hz;
    for (int i = 0; i < n / 2 + 1; i++) {
        float *bin = (float *)&spec[i]; /* complex.h makes fftwf_complex a C99 complex here */
        float re = bin[0], im = bin[1];
        int edge = i == 0 || (n % 2 == 0 && i == n / 2);
        bin[0] = edge ? 0.0f : im / (float)n;
        bin[1] = edge ? 0.0f : -re / (float)n;
    }
}

int uwb_quadrature_scan(const struct uwb_scan *in, struct uwb_scan *out, char *err, size_t errlen)
{
    if (uwb_scan_copy(out, in, err, errlen) != 0)
        return -1;
    if (uwb_filter_traces_in_spectrum(out, NULL, hilbert_spectrum, NULL, "quadrature", err, errlen) != 0) {
        uwb_scan_free(out);
        return -1;
    }
    return 0;
}

/* Linear interpolation of v[0..n-1] at fractional index x (zero outside). */
static double sample_at(const float *v, int n, double x)
{
    if (!(x >= 0.0 && x < n - 1))
        return 0.0;
    int i = (int)x;
    double f = x - i;
    return v[i] + (v[i + 1] - v[i]) * f;
}

/* A trace at a delay in seconds. */
static double trace_at(const float *tr, int n, const struct uwb_geometry *g, double delay_s)
{
    return sample_at(tr, n, (delay_s - g->t0_s) / g->dt_s);
}

/* The echo model and its quadrature partner, s seconds after the echo's
 * delay (linear interpolation, zero outside), times a, added to *re and
 * *im: the index is found once for both, and no complex value is made on
 * the way, as point_asymmetry calls it some hundred thousand times a pass. */
static inline void add_echo_at(const struct side_reflector *r, double dt, double s, double a, double *re,
                               double *im)
{
    double x = (s - r->lead_s) / dt;
    if (!(x >= 0.0 && x < r->len - 1))
        return;
    int i = (int)x;
    double f = x - i;
    const float *e = r->echo + i, *q = r->quadrature + i;
    *re += a * (e[0] + (e[1] - e[0]) * f);
    *im += a * (q[0] + (q[1] - q[0]) * f);
}

static double complex echo_at(const struct side_reflector *r, double dt, double s)
{
    double re = 0.0, im = 0.0;
    add_echo_at(r, dt, s, 1.0, &re, &im);
    return re + I * im;
}

static double point_amplitude(double dy, double z)
{
    return pow(z / hypot(dy, z), SPREADING_POWER + OBLIQUITY_POWER);
}

static int cut_echo(const struct uwb_scan *s, const struct uwb_scan *q, const struct uwb_geometry *g,
                    double centre_m, double z_face, double period_s, struct side_reflector *r)
{
    int kc = 0;
    for (int k = 1; k < s->positions; k++)
        if (fabs(s->antenna_y_m[k] - centre_m) < fabs(s->antenna_y_m[kc] - centre_m))
            kc = k;
    double t_echo = uwb_two_way_delay(g, 0.0, z_face);
    r->lead_s = -ECHO_HALF_PERIODS * period_s;
    r->len = (int)ceil(2.0 * ECHO_HALF_PERIODS * period_s / g->dt_s) + 1;
    r->echo = malloc((size_t)r->len * sizeof *r->echo);
    r->quadrature = malloc((size_t)r->len * sizeof *r->quadrature);
    if (!r->echo || !r->quadrature)
        return -1;
    const float *d = s->data + (size_t)kc * s->samples, *h = q->data + (size_t)kc * s->samples;
    double ramp = 0.5 * period_s;
    for (int i = 0; i < r->len; i++) {
        double t = r->lead_s + i * g->dt_s;
        double from_end = ECHO_HALF_PERIODS * period_s - fabs(t);
        double w = from_end >= ramp ? 1.0 : from_end <= 0.0 ? 0.0 : 0.5 - 0.5 * cos(M_PI * from_end / ramp);
        r->echo[i] = (float)(w * trace_at(d, s->samples, g, t_echo + t));
        r->quadrature[i] = (float)(w * trace_at(h, s->samples, g, t_echo + t));
    }
    return 0;
}

/* Antisymmetric part of a point echo's face-row image, at the sampled u. */
static void point_asymmetry(const struct side_reflector *r, const struct uwb_scan *s, const double *weight,
                            const struct uwb_geometry *g, const double *tau_up, const double *tau_down,
                            int nu, double yp, double z, double complex *b)
{
    memset(b, 0, (size_t)nu * sizeof *b);
    for (int k = 0; k < s->positions; k++) {
        if (weight[k] == 0.0)
            continue;
        double dy = yp - s->antenna_y_m[k];
        double tp = uwb_two_way_delay(g, dy, z);
        double a = weight[k] * point_amplitude(dy, z);
        const double *up = tau_up + (size_t)k * nu, *down = tau_down + (size_t)k * nu;
        for (int iu = 0; iu < nu; iu++) {
            double re = 0.0, im = 0.0;
            add_echo_at(r, g->dt_s, up[iu] - tp, a, &re, &im);
            add_echo_at(r, g->dt_s, down[iu] - tp, -a, &re, &im);
            b[iu] += re + I * im;
        }
    }
}

struct fit {
    double score, y;
    double complex amp;
    double explained;
};

static void try_position(const struct side_reflector *r, const struct uwb_scan *s, const double *weight,
                         const struct uwb_geometry *g, const double *tau_up, const double *tau_down,
                         const double complex *a, double a_energy, int nu, double yp, double z,
                         double complex *b, struct fit *best)
{
    point_asymmetry(r, s, weight, g, tau_up, tau_down, nu, yp, z, b);
    double bb = 0.0;
    double complex ba = 0.0;
    for (int iu = 0; iu < nu; iu++) {
        bb += creal(b[iu] * conj(b[iu]));
        ba += conj(b[iu]) * a[iu];
    }
    if (!(bb > 0.0))
        return;
    double score = creal(ba * conj(ba)) / bb;
    if (score > best->score) {
        best->score = score;
        best->y = yp;
        best->amp = ba / bb;
        best->explained = a_energy > 0.0 ? score / a_energy : 0.0;
    }
}

int uwb_side_reflector_find(const struct uwb_scan *s, const struct uwb_scan *q, const double *weight,
                            const struct uwb_geometry *g, double z_face, double centre, double half_height,
                            double dominant_hz, double near_y_m, struct side_reflector *r, char *err,
                            size_t errlen)
{
    memset(r, 0, sizeof *r);
    int K = s->positions, nu = (int)floor(ROW_HALF_SPAN_M / ROW_STEP_M);
    double *tau_up = malloc((size_t)K * nu * sizeof *tau_up);
    double *tau_down = malloc((size_t)K * nu * sizeof *tau_down);
    double complex *a = calloc((size_t)nu, sizeof *a);
    double complex *b = malloc((size_t)nu * sizeof *b);
    double complex *row_up = calloc((size_t)nu, sizeof *row_up);
    double complex *row_down = calloc((size_t)nu, sizeof *row_down);
    if (!tau_up || !tau_down || !a || !b || !row_up || !row_down ||
        cut_echo(s, q, g, centre, z_face, 1.0 / dominant_hz, r) != 0) {
        free(tau_up);
        free(tau_down);
        free(a);
        free(b);
        free(row_up);
        free(row_down);
        uwb_side_reflector_free(r);
        snprintf(err, errlen, "side reflector: out of memory");
        return -1;
    }
    /* The face row's antisymmetric part about the centre. */
    for (int k = 0; k < K; k++) {
        const float *d = s->data + (size_t)k * s->samples, *h = q->data + (size_t)k * s->samples;
        for (int iu = 0; iu < nu; iu++) {
            double u = (iu + 0.5) * ROW_STEP_M;
            double tu = uwb_two_way_delay(g, centre + u - s->antenna_y_m[k], z_face);
            double td = uwb_two_way_delay(g, centre - u - s->antenna_y_m[k], z_face);
            tau_up[(size_t)k * nu + iu] = tu;
            tau_down[(size_t)k * nu + iu] = td;
            if (weight[k] == 0.0)
                continue;
            double complex up = trace_at(d, s->samples, g, tu) + I * trace_at(h, s->samples, g, tu);
            double complex down = trace_at(d, s->samples, g, td) + I * trace_at(h, s->samples, g, td);
            row_up[iu] += weight[k] * up;
            row_down[iu] += weight[k] * down;
        }
    }
    /* The antisymmetric part alone cannot tell a reflector from its mirror
     * image with the sign flipped: look on the side where the row beyond the
     * winding's end is stronger. */
    double from = half_height + CLEAR_OF_EDGE_M, to = ROW_HALF_SPAN_M - CLEAR_OF_EDGE_M;
    double a_energy = 0.0, beyond_up = 0.0, beyond_down = 0.0;
    for (int iu = 0; iu < nu; iu++) {
        a[iu] = row_up[iu] - row_down[iu];
        a_energy += creal(a[iu] * conj(a[iu]));
        if ((iu + 0.5) * ROW_STEP_M >= from) {
            beyond_up += creal(row_up[iu] * conj(row_up[iu]));
            beyond_down += creal(row_down[iu] * conj(row_down[iu]));
        }
    }
    int side = beyond_up >= beyond_down ? 1 : -1;
    free(row_up);
    free(row_down);
    /* The face row at the centre, to judge the reflector's strength by. */
    double complex face = 0.0;
    for (int k = 0; k < K; k++) {
        const float *d = s->data + (size_t)k * s->samples, *h = q->data + (size_t)k * s->samples;
        double t = uwb_two_way_delay(g, centre - s->antenna_y_m[k], z_face);
        face += weight[k] * (trace_at(d, s->samples, g, t) + I * trace_at(h, s->samples, g, t));
    }

    /* Where to look: beyond that end of the winding, or near where the
     * previous pass found it (the plate stays put while the centre settles). */
    struct fit best = {0};
    if (isnan(near_y_m)) {
        /* Offsets from, from + step, ... up to to: counted, not accumulated. */
        int coarse = to >= from ? (int)floor((to - from) / COARSE_STEP_M + 1e-9) + 1 : 0;
        for (int k = 0; k < coarse; k++)
            try_position(r, s, weight, g, tau_up, tau_down, a, a_energy, nu,
                         centre + side * (from + k * COARSE_STEP_M), z_face, b, &best);
    } else {
        best.y = near_y_m;
        best.score = 1.0; /* only marks "have a start"; scores below replace it */
    }
    if (best.score > 0.0) {
        double y0 = best.y;
        best.score = 0.0;
        int fine = (int)lround(2.0 * COARSE_STEP_M / FINE_STEP_M); /* one coarse step each side */
        for (int k = 0; k <= fine; k++) {
            double y = y0 - COARSE_STEP_M + k * FINE_STEP_M;
            if (fabs(y - centre) >= from)
                try_position(r, s, weight, g, tau_up, tau_down, a, a_energy, nu, y, z_face, b, &best);
        }
    }
    /* Its image's peak: the antisymmetric part's, where the mirror term is small. */
    double peak = 0.0;
    if (best.score > 0.0) {
        point_asymmetry(r, s, weight, g, tau_up, tau_down, nu, best.y, z_face, b);
        for (int iu = 0; iu < nu; iu++)
            peak = fmax(peak, cabs(best.amp * b[iu]));
    }
    free(tau_up);
    free(tau_down);
    free(a);
    free(b);
    r->relative_peak = cabs(face) > 0.0 ? peak / cabs(face) : 0.0;
    r->y_m = best.y;
    r->z_m = z_face;
    r->amp = best.amp;
    r->explained = best.explained;
    r->found = best.score > 0.0 && best.explained >= MIN_EXPLAINED && r->relative_peak >= MIN_RELATIVE_PEAK;
    return 0;
}

void uwb_side_reflector_remove(const struct side_reflector *r, const struct uwb_geometry *g,
                               struct uwb_scan *s)
{
    if (!r->found)
        return;
    for (int k = 0; k < s->positions; k++) {
        double dy = r->y_m - s->antenna_y_m[k];
        double tp = uwb_two_way_delay(g, dy, r->z_m);
        double amp = point_amplitude(dy, r->z_m);
        float *tr = s->data + (size_t)k * s->samples;
        int first = (int)floor((tp + r->lead_s - g->t0_s) / g->dt_s);
        int last = (int)ceil((tp + r->lead_s + r->len * g->dt_s - g->t0_s) / g->dt_s);
        if (first < 0)
            first = 0;
        if (last > s->samples - 1)
            last = s->samples - 1;
        /* The real signal whose analytic partner is amp * echo. */
        for (int i = first; i <= last; i++) {
            double complex e = echo_at(r, g->dt_s, g->t0_s + i * g->dt_s - tp);
            tr[i] -= (float)(amp * creal(r->amp * e));
        }
    }
}

void uwb_side_reflector_free(struct side_reflector *r)
{
    free(r->echo);
    free(r->quadrature);
    r->echo = r->quadrature = NULL;
}
