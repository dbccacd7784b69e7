#include "engine.h"

#include <complex.h>
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pulse.h"

#define C0 299792458.0

struct sim_engine {
    struct sim_scene scene;
    struct sim_geometry geo;
    int mode2d;
    double n_oil, inv_v;            /* inv_v: s/m in the oil */
    double beam_n;                  /* pattern cos^n; 0: isotropic */
    double lambda_c;                /* wavelength in the oil at the centre frequency */
    /* tank window, seen from antennas at z = 0 */
    int has_window;
    double win_gap, win_t, n_win;
    double win_T2;                  /* two-way transmission through its interfaces */
    double bar_T;                   /* one pass through the barrier */
    /* time grid and FFT */
    int nfft, pad, samples;
    double dt, grid_t0;             /* buffer index i is time grid_t0 + i dt */
    double *acc, *acc_edge;
    double complex *spec;
    float *rbuf;
    fftwf_complex *cbuf;
    fftwf_plan r2c, c2r;
    double complex *surface_kernel; /* operator x pulse x PO constant / N / grid smoothing */
    double complex *edge_kernel;    /* the same for the edges' fringe term */
    double complex *static_direct;  /* direct coupling + window echoes, / N */
    double complex *static_clutter; /* far wall, / N */
    double peak_echo;
};

static int next_pow2(int n)
{
    int p = 256;
    while (p < n)
        p *= 2;
    return p;
}

static double omega_k(const struct sim_engine *e, int k)
{
    return 2.0 * M_PI * k / (e->nfft * e->dt);
}

/* (i w)^a on the FFT's frequency grid (FFTW's forward sign is e^{-iwt}, so a
 * time derivative multiplies by +iw); the principal branch makes the
 * fractional derivative causal. */
static double complex frac_derivative(double w, double a)
{
    if (a == 0)
        return 1.0;
    if (w <= 0)
        return 0.0;
    return pow(w, a) * cexp(I * M_PI * a / 2.0);
}

/* 2-D direct coupling: exact line-source field over its far-field form,
 * H0(2)(kd) / (sqrt(2/(pi kd)) e^{-i(kd - pi/4)}); tends to 1 for kd >> 1. */
static double complex near_field_2d(double kd)
{
    if (kd <= 0)
        return 0.0;
    double complex h02 = j0(kd) - I * y0(kd);
    double complex far = sqrt(2.0 / (M_PI * kd)) * cexp(-I * (kd - M_PI / 4.0));
    return h02 / far;
}

/* Specular echo off a stack of flat layers parallel to the wall, Tx and Rx
 * `offset` apart: ray parameter found by bisection so the lateral travel
 * matches. Returns delay, unfolded path length and the cosine of the ray's
 * angle in the first layer (for the antenna pattern). */
static void layered_echo(const double *thick, const double *n, int nl, double offset,
                         double *delay, double *length, double *cos_first)
{
    double pmax = 1e300;
    for (int i = 0; i < nl; i++)
        if (thick[i] > 0 && n[i] < pmax)
            pmax = n[i];
    double lo = 0.0, hi = pmax * (1.0 - 1e-12);
    for (int it = 0; it < 200 && offset > 0; it++) {
        double p = 0.5 * (lo + hi), x = 0.0;
        for (int i = 0; i < nl; i++)
            if (thick[i] > 0)
                x += 2.0 * thick[i] * p / sqrt(n[i] * n[i] - p * p);
        if (x < offset)
            lo = p;
        else
            hi = p;
    }
    double p = offset > 0 ? 0.5 * (lo + hi) : 0.0;
    *delay = *length = 0.0;
    *cos_first = 1.0;
    int first = 1;
    for (int i = 0; i < nl; i++) {
        if (thick[i] <= 0)
            continue;
        double c = sqrt(1.0 - (p / n[i]) * (p / n[i]));
        if (first)
            *cos_first = c;
        first = 0;
        *delay += 2.0 * thick[i] * n[i] / (C0 * c);
        *length += 2.0 * thick[i] / c;
    }
}

static double pattern(const struct sim_engine *e, double cos_theta)
{
    if (e->beam_n <= 0)
        return 1.0;
    if (cos_theta <= 0)
        return 0.0;
    return exp(e->beam_n * log(cos_theta));
}

/* Add one static return, amplitude amp at delay tau, with the pulse's shape
 * (image sources and direct coupling need no surface operator). */
static void add_static(struct sim_engine *e, double complex *dst, const double complex *F,
                       double amp, double tau, double nf_distance)
{
    int nh = e->nfft / 2;
    for (int k = 1; k < nh; k++) {
        double w = omega_k(e, k);
        double complex v = amp * F[k] * cexp(-I * w * (tau - e->grid_t0)) / e->nfft;
        if (nf_distance > 0)
            v *= near_field_2d(w * nf_distance / C0);
        dst[k] += v;
    }
}

static void build_statics(struct sim_engine *e, const double complex *F)
{
    const struct sim_scene *s = &e->scene;
    double dy = s->rx_dy_m - s->tx_dy_m, dz = s->rx_dz_m - s->tx_dz_m;
    double d = sqrt(dy * dy + dz * dz);
    double offset = fabs(dy);
    double zant = 0.5 * (s->tx_dz_m + s->rx_dz_m);
    double gap = fmax(0.0, s->window_gap_m - zant);

    if (s->coupling_gain > 0 && d > 0) {
        double spread = e->mode2d ? sqrt(d) : d;
        add_static(e, e->static_direct, F, s->coupling_gain / spread, d / C0, e->mode2d ? d : 0.0);
    }
    double n_air = 1.0, n_w = sqrt(s->window_eps_r), n_o = e->n_oil;
    double thick[3] = {gap, s->window_thickness_m, 0.0};
    double idx[3] = {n_air, n_w, n_o};
    double delay, len, cf;
    if (s->window_echo) {
        /* outer face: air into the window (or straight into the oil) */
        if (gap > 0) {
            double n2 = s->window_thickness_m > 0 ? n_w : n_o;
            double g = (n_air - n2) / (n_air + n2);
            layered_echo(thick, idx, 1, offset, &delay, &len, &cf);
            double p = pattern(e, cf);
            add_static(e, e->static_direct, F, g * p * p / (e->mode2d ? sqrt(len) : len), delay, 0);
        }
        if (s->window_thickness_m > 0) {
            double g = (n_w - n_o) / (n_w + n_o);
            if (gap > 0) {
                double ga = (n_air - n_w) / (n_air + n_w);
                g *= 1.0 - ga * ga;
            }
            layered_echo(thick, idx, 2, offset, &delay, &len, &cf);
            double p = pattern(e, cf);
            add_static(e, e->static_direct, F, g * p * p / (e->mode2d ? sqrt(len) : len), delay, 0);
        }
    }
    if (s->clutter && s->far_wall) {
        thick[2] = s->far_wall_z_m - s->window_gap_m - s->window_thickness_m;
        layered_echo(thick, idx, 3, offset, &delay, &len, &cf);
        double p = pattern(e, cf);
        double g = -s->far_wall_reflectivity * e->win_T2;
        add_static(e, e->static_clutter, F, g * p * p / (e->mode2d ? sqrt(len) : len), delay, 0);
    }
}

/* Two-way amplitude transmission through the interfaces between the antennas
 * and the oil: each crossed interface contributes t12 t21 = 1 - r^2. */
static double window_transmission(const struct sim_scene *s, double n_oil)
{
    double media[3];
    int m = 0;
    if (s->window_gap_m > 0)
        media[m++] = 1.0;
    if (s->window_thickness_m > 0)
        media[m++] = sqrt(s->window_eps_r);
    media[m++] = n_oil;
    double t = 1.0;
    for (int i = 0; i + 1 < m; i++) {
        double r = (media[i] - media[i + 1]) / (media[i] + media[i + 1]);
        t *= 1.0 - r * r;
    }
    return t;
}

/* Extra one-way delay through the air gap and window for a ray leaving the
 * antenna at direction cosine cz to the wall normal (straight-ray geometry in
 * oil, plane-wave phase through each layer: sum t (sqrt(n^2 - p^2) - n_o cz)). */
static double window_delay(const struct sim_engine *e, double gap, double cz)
{
    double no = e->n_oil, nocz = no * cz;
    double p2 = no * no * (1.0 - cz * cz);
    double air = 1.0 - p2;
    double d = 0.0;
    if (gap > 0)
        d += gap * ((air > 0 ? sqrt(air) : 0.0) - nocz);
    d += e->win_t * (sqrt(e->n_win * e->n_win - p2) - nocz);
    return d / C0;
}

/* A ray from antenna a to a point p behind the barrier: if it passes through
 * the barrier, add the barrier's extra delay and return its transmission. */
static double barrier_leg(const struct sim_engine *e, const double a[3], const double p[3],
                          double r, double *tau)
{
    const struct sim_geometry *g = &e->geo;
    double s, cpsi;
    if (e->mode2d) {
        double dz = p[2] - a[2];
        if (dz <= 0)
            return 1.0;
        s = (g->barrier_front_z - a[2]) / dz;
        if (s < 0 || s > 1)
            return 1.0;
        cpsi = dz / r;
    } else {
        double ax = a[0], az = a[2] - g->barrier_axis_z, dx = p[0] - a[0], dz = p[2] - a[2];
        double dd = dx * dx + dz * dz, ad = ax * dx + az * dz;
        double rb = g->barrier_outer_r;
        double disc = ad * ad - dd * (ax * ax + az * az - rb * rb);
        if (disc <= 0 || dd <= 0)
            return 1.0;
        s = (-ad - sqrt(disc)) / dd;
        if (s < 0 || s > 1)
            return 1.0;
        double qx = ax + s * dx, qz = az + s * dz;
        cpsi = fabs(dx * qx + dz * qz) / (rb * r);
    }
    double yq = a[1] + s * (p[1] - a[1]);
    if (yq < g->barrier_y_min || yq > g->barrier_y_max)
        return 1.0;
    double no = e->n_oil, nb = g->barrier_n;
    double p2 = no * no * (1.0 - cpsi * cpsi);
    *tau += g->barrier_thickness * (sqrt(nb * nb - p2) - no * cpsi) / C0;
    return e->bar_T;
}

/* Fraction of a gap-face element lit through the gap's mouth, seen from
 * antenna a (stack frame). */
static double gap_lit(const struct sim_engine *e, const struct sim_element *el, const double a[3])
{
    const double *p = el->lpos;
    double rise = el->kind == SIM_ELEM_GAP_UP ? a[1] - p[1] : p[1] - a[1];
    if (rise <= 0)
        return 0.0;
    double horiz, lnear, lfar;
    if (e->mode2d) {
        horiz = p[2] - a[2];
        lnear = el->depth0;
        lfar = el->depth1;
    } else {
        double hx = a[0] - p[0], hz = a[2] - p[2];
        horiz = sqrt(hx * hx + hz * hz);
        double ux = hx / horiz, uz = hz / horiz;
        double pu = p[0] * ux + p[2] * uz, pp = p[0] * p[0] + p[2] * p[2];
        double R = e->geo.radius;
        double disc = pu * pu - pp + R * R;
        double len = -pu + sqrt(disc > 0 ? disc : 0.0);
        double dc = 0.5 * (el->depth0 + el->depth1);
        lnear = len * el->depth0 / dc;
        lfar = len * el->depth1 / dc;
    }
    if (horiz <= 0)
        return 0.0;
    double lit = el->gap * horiz / rise;       /* depth the ray reaches before leaving the gap's height */
    double f = (lit - lnear) / (lfar - lnear);
    return f < 0 ? 0.0 : (f > 1 ? 1.0 : f);
}

static void deposit_into(const struct sim_engine *e, double *acc, double tau, double amp)
{
    double x = (tau - e->grid_t0) / e->dt;
    if (!(x >= 0) || x >= e->nfft - 1)
        return;
    int i = (int)x;
    double f = x - i;
    acc[i] += amp * (1.0 - f);
    acc[i + 1] += amp * f;
}

static void deposit(struct sim_engine *e, double tau, double amp)
{
    deposit_into(e, e->acc, tau, amp);
}

/* PTD fringe coefficient of a metal wedge (exterior angle n pi): Keller's
 * exact diffraction coefficient minus the one physical optics already
 * produces from the two faces' ends, both in units of e^{-i pi/4}/sqrt(2 pi k).
 * phi: direction to Rx, phip: to Tx, from face A. Soft = E along the edge. */
static double fringe_at(double phi, double phip, double n, int soft, int *near_singular)
{
    const double tiny = 1e-6;
    double cn = cos(M_PI / n), sn = sin(M_PI / n);
    double d1 = cn - cos((phi - phip) / n), d2 = cn - cos((phi + phip) / n);
    if (fabs(d1) < tiny || fabs(d2) < tiny)
        *near_singular = 1;
    double gtd = (sn / n) * (1.0 / d1 + (soft ? -1.0 : 1.0) / d2);
    double po = 0.0;
    /* face A: lit and seen when both directions are on its outer side */
    if (sin(phi) > 0 && sin(phip) > 0) {
        double den = cos(phi) + cos(phip);
        if (fabs(den) < tiny)
            *near_singular = 1;
        po += 0.5 * (sin(phi) + sin(phip)) / den;      /* G = -1 folded in */
    }
    double b = n * M_PI;
    if (sin(b - phi) > 0 && sin(b - phip) > 0) {
        double den = cos(b - phi) + cos(b - phip);
        if (fabs(den) < tiny)
            *near_singular = 1;
        po += 0.5 * (sin(b - phi) + sin(b - phip)) / den;
    }
    return gtd - po;
}

static double fringe(double phi, double phip, double n, int soft)
{
    int singular = 0;
    double f = fringe_at(phi, phip, n, soft, &singular);
    if (!singular)
        return f;
    /* on a reflection boundary both terms blow up and their difference stays
     * finite: take it as the mean of two nearby, symmetric evaluations */
    const double eps = 1e-4;
    int dummy = 0;
    return 0.5 * (fringe_at(phi + eps, phip + eps, n, soft, &dummy) +
                  fringe_at(phi - eps, phip - eps, n, soft, &dummy));
}

/* Angle of direction u around the edge, from face A through the outside. */
static double wedge_angle(const struct sim_edge *ed, const double u[3])
{
    const double *t = ed->tangent;
    double ut = u[0] * t[0] + u[1] * t[1] + u[2] * t[2];
    double p[3] = {u[0] - ut * t[0], u[1] - ut * t[1], u[2] - ut * t[2]};
    double x = p[0] * ed->s_a[0] + p[1] * ed->s_a[1] + p[2] * ed->s_a[2];
    double y = p[0] * ed->n_a[0] + p[1] * ed->n_a[1] + p[2] * ed->n_a[2];
    double a = atan2(y, x);
    return a < 0 ? a + 2.0 * M_PI : a;
}

static void integrate_edges(struct sim_engine *e, const double tx[3], const double rx[3],
                            const double txl[3], const double rxl[3], double tx_gap, double rx_gap)
{
    const struct sim_geometry *g = &e->geo;
    int soft = e->scene.polarisation == SIM_POL_PARALLEL;
    for (size_t i = 0; i < g->edge_count; i++) {
        const struct sim_edge *ed = &g->edges[i];
        const double *p = ed->pos;
        double u1[3] = {tx[0] - p[0], tx[1] - p[1], tx[2] - p[2]};
        double u2[3] = {rx[0] - p[0], rx[1] - p[1], rx[2] - p[2]};
        double r1 = sqrt(u1[0] * u1[0] + u1[1] * u1[1] + u1[2] * u1[2]);
        double r2 = sqrt(u2[0] * u2[0] + u2[1] * u2[1] + u2[2] * u2[2]);
        for (int k = 0; k < 3; k++) {
            u1[k] /= r1;
            u2[k] /= r2;
        }
        double cz1 = -u1[2], cz2 = -u2[2];
        if (cz1 <= 1e-3 || cz2 <= 1e-3)
            continue;
        double wedge = ed->wedge_n * M_PI;
        double phip = wedge_angle(ed, u1), phi = wedge_angle(ed, u2);
        if (phip > wedge || phi > wedge)
            continue;           /* looking at it from inside the metal */
        if (!e->mode2d) {
            /* hidden behind the stack (the back of the circle)? test a point a
             * hair toward each antenna so the edge itself does not count */
            double q1[3], q2[3];
            for (int k = 0; k < 3; k++) {
                double d1 = txl[k] - ed->lpos[k], d2 = rxl[k] - ed->lpos[k];
                q1[k] = ed->lpos[k] + 1e-6 * d1 / r1;
                q2[k] = ed->lpos[k] + 1e-6 * d2 / r2;
            }
            if (sim_geometry_blocked(g, txl, q1) || sim_geometry_blocked(g, rxl, q2))
                continue;
        }
        double amp = fringe(phi, phip, ed->wedge_n, soft) * ed->length;
        amp *= e->mode2d ? 1.0 / sqrt(r1 * r2) : 1.0 / (r1 * r2);
        if (e->beam_n > 0)
            amp *= exp(e->beam_n * log(cz1 * cz2));
        double tau = (r1 + r2) * e->inv_v;
        if (e->has_window)
            tau += window_delay(e, tx_gap, cz1) + window_delay(e, rx_gap, cz2);
        if (g->has_barrier) {
            amp *= barrier_leg(e, tx, p, r1, &tau);
            amp *= barrier_leg(e, rx, p, r2, &tau);
        }
        deposit_into(e, e->acc_edge, tau, amp);
    }
}

static void integrate_surfaces(struct sim_engine *e, double y_ref, unsigned parts)
{
    const struct sim_scene *s = &e->scene;
    const struct sim_geometry *g = &e->geo;
    double tx[3] = {0.0, y_ref + s->tx_dy_m, s->tx_dz_m};
    double rx[3] = {0.0, y_ref + s->rx_dy_m, s->rx_dz_m};
    double txl[3], rxl[3];
    sim_geometry_to_local(g, tx, txl);
    sim_geometry_to_local(g, rx, rxl);
    double tx_gap = fmax(0.0, s->window_gap_m - tx[2]), rx_gap = fmax(0.0, s->window_gap_m - rx[2]);
    int mode2d = e->mode2d;
    double inv_v = e->inv_v;

    for (size_t i = 0; i < g->count; i++) {
        const struct sim_element *el = &g->el[i];
        if (!(el->part & parts))
            continue;
        const double *p = el->pos, *n = el->nrm;
        double d1[3] = {p[0] - tx[0], p[1] - tx[1], p[2] - tx[2]};
        double r1 = sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
        double c1 = (n[0] * d1[0] + n[1] * d1[1] + n[2] * d1[2]) / r1;
        if (c1 >= 0)
            continue;
        double d2[3] = {p[0] - rx[0], p[1] - rx[1], p[2] - rx[2]};
        double r2 = sqrt(d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]);
        double c2 = (n[0] * d2[0] + n[1] * d2[1] + n[2] * d2[2]) / r2;
        if (c2 >= 0)
            continue;
        double cz1 = d1[2] / r1, cz2 = d2[2] / r2;
        if (cz1 <= 1e-3 || cz2 <= 1e-3)
            continue;
        double amp = el->refl * el->area * (-0.5 * (c1 + c2));
        amp *= mode2d ? 1.0 / sqrt(r1 * r2) : 1.0 / (r1 * r2);
        if (e->beam_n > 0)
            amp *= exp(e->beam_n * log(cz1 * cz2));
        double tau = (r1 + r2) * inv_v;
        if (e->has_window)
            tau += window_delay(e, tx_gap, cz1) + window_delay(e, rx_gap, cz2);
        if (el->kind != SIM_ELEM_PLAIN) {
            double f = gap_lit(e, el, txl);
            if (f > 0)
                f = fmin(f, gap_lit(e, el, rxl));
            if (f <= 0)
                continue;
            amp *= f;
        }
        if (el->shadowable) {
            double w = sim_geometry_shadow_weight(g, txl, el->lpos, e->lambda_c);
            if (w > 0)
                w *= sim_geometry_shadow_weight(g, rxl, el->lpos, e->lambda_c);
            if (w <= 0)
                continue;
            amp *= w;
        }
        if (el->behind_barrier) {
            amp *= barrier_leg(e, tx, p, r1, &tau);
            amp *= barrier_leg(e, rx, p, r2, &tau);
        }
        deposit(e, tau, amp);
        if (el->refl2 != 0) {
            /* thin layer's back face: optical path 2 n t cos(theta_t) later */
            double no = e->n_oil, nb = g->barrier_n;
            double extra = g->barrier_thickness *
                           (sqrt(nb * nb - no * no * (1 - c1 * c1)) + sqrt(nb * nb - no * no * (1 - c2 * c2))) / C0;
            deposit(e, tau + extra, amp * el->refl2 / el->refl);
        }
    }
    if ((parts & SIM_PART_WINDING) && g->edge_count > 0)
        integrate_edges(e, tx, rx, txl, rxl, tx_gap, rx_gap);
}

void sim_engine_clean_trace(struct sim_engine *e, double y_ref, unsigned parts, double shift_s, double *out)
{
    int nh = e->nfft / 2;
    fftwf_complex *c = e->cbuf;
    double complex *spec = e->spec;
    memset(spec, 0, ((size_t)nh + 1) * sizeof *spec);
    if (parts & (SIM_PART_WINDING | SIM_PART_CLUTTER)) {
        memset(e->acc, 0, (size_t)e->nfft * sizeof *e->acc);
        memset(e->acc_edge, 0, (size_t)e->nfft * sizeof *e->acc_edge);
        integrate_surfaces(e, y_ref, parts);
        for (int i = 0; i < e->nfft; i++)
            e->rbuf[i] = (float)e->acc[i];
        fftwf_execute(e->r2c);
        for (int k = 0; k <= nh; k++)
            spec[k] += (crealf(c[k]) + I * cimagf(c[k])) * e->surface_kernel[k];
        if ((parts & SIM_PART_WINDING) && e->geo.edge_count > 0) {
            for (int i = 0; i < e->nfft; i++)
                e->rbuf[i] = (float)e->acc_edge[i];
            fftwf_execute(e->r2c);
            for (int k = 0; k <= nh; k++)
                spec[k] += (crealf(c[k]) + I * cimagf(c[k])) * e->edge_kernel[k];
        }
    }
    for (int k = 0; k <= nh; k++) {
        double complex v = spec[k];
        if (parts & SIM_PART_DIRECT)
            v += e->static_direct[k];
        if (parts & SIM_PART_CLUTTER)
            v += e->static_clutter[k];
        if (shift_s != 0)
            v *= cexp(-I * omega_k(e, k) * shift_s);
        c[k] = (float)creal(v) + I * (float)cimag(v);
    }
    fftwf_execute(e->c2r);
    for (int i = 0; i < e->samples; i++)
        out[i] = e->rbuf[e->pad + i];
}

const struct sim_scene *sim_engine_scene(const struct sim_engine *e)
{
    return &e->scene;
}

size_t sim_engine_element_count(const struct sim_engine *e)
{
    return e->geo.count;
}

double sim_engine_peak_echo(const struct sim_engine *e)
{
    return e->peak_echo;
}

void sim_engine_free(struct sim_engine *e)
{
    if (!e)
        return;
    sim_geometry_free(&e->geo);
    if (e->r2c)
        fftwf_destroy_plan(e->r2c);
    if (e->c2r)
        fftwf_destroy_plan(e->c2r);
    fftwf_free(e->rbuf);
    fftwf_free(e->cbuf);
    free(e->acc);
    free(e->acc_edge);
    free(e->spec);
    free(e->edge_kernel);
    free(e->surface_kernel);
    free(e->static_direct);
    free(e->static_clutter);
    free(e);
}

/* The pulse's spectrum on the FFT grid, scaled so the incident field 1 m
 * from Tx peaks at pulse_amplitude. */
static int pulse_spectrum(struct sim_engine *e, double complex *F, char *err, size_t errlen)
{
    struct sim_pulse pulse;
    if (sim_pulse_load(&e->scene, &pulse, err, errlen) != 0)
        return -1;
    int n = e->nfft, nh = n / 2;
    for (int i = 0; i < n; i++) {
        double t = (i < nh ? i : i - n) * e->dt;   /* circular: negative times at the end */
        e->rbuf[i] = (float)sim_pulse_value(&pulse, t);
    }
    sim_pulse_free(&pulse);
    fftwf_execute(e->r2c);
    for (int k = 0; k <= nh; k++) {
        double complex sk = crealf(e->cbuf[k]) + I * cimagf(e->cbuf[k]);
        F[k] = k == nh ? 0.0 : sk * frac_derivative(omega_k(e, k), e->scene.pulse_derivative);
    }
    for (int k = 0; k <= nh; k++)
        e->cbuf[k] = (float)creal(F[k]) + I * (float)cimag(F[k]);
    fftwf_execute(e->c2r);
    double peak = 0;
    for (int i = 0; i < n; i++)
        peak = fmax(peak, fabs(e->rbuf[i] / n));
    if (!(peak > 0)) {
        snprintf(err, errlen, "pulse: the radiated pulse is zero on this time grid (sample_interval_s too coarse?)");
        return -1;
    }
    for (int k = 0; k <= nh; k++)
        F[k] *= e->scene.pulse_amplitude / peak;
    return 0;
}

int sim_engine_create(const struct sim_scene *scene, struct sim_engine **out, char *err, size_t errlen)
{
    *out = NULL;
    if (sim_scene_validate(scene, err, errlen) != 0)
        return -1;
    struct sim_engine *e = calloc(1, sizeof *e);
    if (!e) {
        snprintf(err, errlen, "engine: out of memory");
        return -1;
    }
    e->scene = *scene;
    const struct sim_scene *s = &e->scene;
    e->mode2d = s->mode == SIM_MODE_2D;
    e->n_oil = sqrt(s->eps_r);
    e->inv_v = e->n_oil / C0;
    e->lambda_c = C0 / (e->n_oil * s->centre_frequency_hz);
    if (s->beamwidth_deg > 0 && s->beamwidth_deg < 180)
        e->beam_n = log(0.5) / (2.0 * log(cos(0.5 * s->beamwidth_deg * M_PI / 180.0)));
    e->has_window = s->window_gap_m > 0 || s->window_thickness_m > 0;
    e->win_gap = s->window_gap_m;
    e->win_t = s->window_thickness_m;
    e->n_win = sqrt(s->window_eps_r);
    e->win_T2 = window_transmission(s, e->n_oil);
    {
        double nb = sqrt(s->barrier_eps_r), r = (e->n_oil - nb) / (e->n_oil + nb);
        e->bar_T = 1.0 - r * r;
    }

    if (sim_geometry_build(s, &e->geo, err, errlen) != 0) {
        sim_engine_free(e);
        return -1;
    }

    struct sim_pulse probe;
    if (sim_pulse_load(s, &probe, err, errlen) != 0) {
        sim_engine_free(e);
        return -1;
    }
    double half_span = sim_pulse_half_span_s(&probe);
    sim_pulse_free(&probe);
    e->dt = s->sample_interval_s;
    e->samples = s->samples;
    int m = (int)ceil(half_span / e->dt) + 8;
    if ((double)s->samples + 4.0 * m > 1e8) {
        snprintf(err, errlen, "pulse: %g s long at %g s per sample is too many samples", 2 * half_span, e->dt);
        sim_engine_free(e);
        return -1;
    }
    /* Room on both sides of the record for pulse tails, so the FFT's circular
     * wrap lands in padding and never in the record. */
    e->nfft = next_pow2(2 * s->samples + 4 * m);
    e->pad = (e->nfft - s->samples) / 2;
    e->grid_t0 = s->t0_s - e->pad * e->dt;

    int nh = e->nfft / 2;
    e->acc = calloc((size_t)e->nfft, sizeof *e->acc);
    e->acc_edge = calloc((size_t)e->nfft, sizeof *e->acc_edge);
    e->spec = calloc((size_t)nh + 1, sizeof *e->spec);
    e->edge_kernel = calloc((size_t)nh + 1, sizeof *e->edge_kernel);
    e->rbuf = fftwf_alloc_real((size_t)e->nfft);
    e->cbuf = fftwf_alloc_complex((size_t)nh + 1);
    e->surface_kernel = calloc((size_t)nh + 1, sizeof *e->surface_kernel);
    e->static_direct = calloc((size_t)nh + 1, sizeof *e->static_direct);
    e->static_clutter = calloc((size_t)nh + 1, sizeof *e->static_clutter);
    double complex *F = calloc((size_t)nh + 1, sizeof *F);
    if (!e->acc || !e->acc_edge || !e->spec || !e->edge_kernel || !e->rbuf || !e->cbuf || !e->surface_kernel || !e->static_direct ||
        !e->static_clutter || !F) {
        free(F);
        sim_engine_free(e);
        snprintf(err, errlen, "engine: out of memory for a %d-point FFT", e->nfft);
        return -1;
    }
    /* FFTW's planner is not thread-safe: engines must be created from one thread. */
    e->r2c = fftwf_plan_dft_r2c_1d(e->nfft, e->rbuf, e->cbuf, FFTW_ESTIMATE);
    e->c2r = fftwf_plan_dft_c2r_1d(e->nfft, e->cbuf, e->rbuf, FFTW_ESTIMATE);
    if (!e->r2c || !e->c2r) {
        free(F);
        sim_engine_free(e);
        snprintf(err, errlen, "engine: FFTW could not plan a %d-point transform", e->nfft);
        return -1;
    }
    if (pulse_spectrum(e, F, err, errlen) != 0) {
        free(F);
        sim_engine_free(e);
        return -1;
    }

    double v = C0 / e->n_oil;
    double po = e->mode2d ? 1.0 / sqrt(2.0 * M_PI * v) : 1.0 / (2.0 * M_PI * v);
    double op_order = e->mode2d ? 0.5 : 1.0;
    /* edges: the surface integral's end-point carries one 1/(i w) less (3-D:
     * u = d F / (2 pi R1 R2) per metre of edge; 2-D: d sqrt(v / 2 pi) (iw)^-1/2 F) */
    double edge_const = e->mode2d ? sqrt(v / (2.0 * M_PI)) : 1.0 / (2.0 * M_PI);
    for (int k = 1; k < nh; k++) {
        /* linear deposit = sampling after a triangle filter: divide its sinc^2 out */
        double x = M_PI * k / e->nfft;
        double sinc = sin(x) / x;
        double complex common = F[k] * e->win_T2 / (e->nfft * sinc * sinc);
        double w = omega_k(e, k);
        e->surface_kernel[k] = common * frac_derivative(w, op_order) * po;
        e->edge_kernel[k] = common * (e->mode2d ? 1.0 / frac_derivative(w, 0.5) : 1.0) * edge_const;
    }
    build_statics(e, F);
    free(F);

    /* The SNR's reference: the noiseless winding echo's peak over the scan. */
    double *trace = malloc((size_t)s->samples * sizeof *trace);
    if (!trace) {
        sim_engine_free(e);
        snprintf(err, errlen, "engine: out of memory");
        return -1;
    }
    for (int k = 0; k < s->positions; k++) {
        sim_engine_clean_trace(e, sim_scene_antenna_y_m(s, k), SIM_PART_WINDING, 0.0, trace);
        for (int i = 0; i < s->samples; i++)
            e->peak_echo = fmax(e->peak_echo, fabs(trace[i]));
    }
    free(trace);
    *out = e;
    return 0;
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
        if (!(e->peak_echo > 0)) {
            snprintf(err, errlen, "snr_db: the winding returns nothing inside the record, so noise has no reference");
            return -1;
        }
        sigma = e->peak_echo * pow(10.0, -s->snr_db / 20.0);
    }
    /* Draw order is fixed (jitter, drift, then the noise of each pulse): the
     * same seed and calls give the same numbers. */
    double shift = s->jitter_s > 0 ? s->jitter_s * sim_rng_normal(&acq->rng) : 0.0;
    double gain = pow(10.0, acq->drift_db / 20.0);
    if (s->drift_db > 0)
        acq->drift_db += s->drift_db * sim_rng_normal(&acq->rng);

    double *clean = malloc((size_t)s->samples * 2 * sizeof *clean);
    if (!clean) {
        snprintf(err, errlen, "acquire: out of memory");
        return -1;
    }
    double *sum = clean + s->samples;
    sim_engine_clean_trace(e, y_ref, SIM_PART_ALL, shift, clean);
    memset(sum, 0, (size_t)s->samples * sizeof *sum);
    double lsb = 0, code_min = 0, code_max = 0;
    if (s->adc_bits > 0) {
        lsb = 2.0 * s->adc_full_scale_v / ldexp(1.0, s->adc_bits);
        code_max = ldexp(1.0, s->adc_bits - 1) - 1;
        code_min = -ldexp(1.0, s->adc_bits - 1);
    }
    for (int p = 0; p < stack; p++) {
        for (int i = 0; i < s->samples; i++) {
            double v = clean[i] * gain;
            if (sigma > 0)
                v += sigma * sim_rng_normal(&acq->rng);
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
