/* Returns that are the same at every position: the direct Tx-Rx coupling,
 * the window's own echoes and the far wall. Built once, as spectra. */
#include <math.h>

#include "engine_internal.h"

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
static void layered_echo(const double *thick, const double *n, int nl, double offset, double *delay,
                         double *length, double *cos_first)
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

/* Add one static return, amplitude amp at delay tau, with the pulse's shape
 * (image sources and direct coupling need no surface operator). */
static void add_static(struct sim_engine *e, double complex *dst, const double complex *F, double amp,
                       double tau, double nf_distance)
{
    int nh = e->nfft / 2;
    for (int k = 1; k < nh; k++) {
        double w = sim_omega_k(e, k);
        double complex v = amp * F[k] * cexp(-I * w * (tau - e->grid_t0)) / e->nfft;
        if (nf_distance > 0)
            v *= near_field_2d(w * nf_distance / C0);
        dst[k] += v;
    }
}

void sim_build_statics(struct sim_engine *e, const double complex *F)
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
            double p = sim_pattern(e, cf);
            add_static(e, e->static_direct, F, g * p * p / (e->mode2d ? sqrt(len) : len), delay, 0);
        }
        if (s->window_thickness_m > 0) {
            double g = (n_w - n_o) / (n_w + n_o);
            if (gap > 0) {
                double ga = (n_air - n_w) / (n_air + n_w);
                g *= 1.0 - ga * ga;
            }
            layered_echo(thick, idx, 2, offset, &delay, &len, &cf);
            double p = sim_pattern(e, cf);
            add_static(e, e->static_direct, F, g * p * p / (e->mode2d ? sqrt(len) : len), delay, 0);
        }
    }
    if (s->clutter && s->far_wall) {
        thick[2] = s->far_wall_z_m - s->window_gap_m - s->window_thickness_m;
        layered_echo(thick, idx, 3, offset, &delay, &len, &cf);
        double p = sim_pattern(e, cf);
        double g = -s->far_wall_reflectivity * e->win_T2;
        add_static(e, e->static_clutter, F, g * p * p / (e->mode2d ? sqrt(len) : len), delay, 0);
    }
}
