/* Rays between the antennas and a scatterer: antenna pattern, the tank
 * window's and the barrier's delay and transmission, and how much of a gap
 * face a ray can reach. */
#include <math.h>

#include "engine_internal.h"

double sim_pattern(const struct sim_engine *e, double cos_theta)
{
    if (e->beam_n <= 0)
        return 1.0;
    if (cos_theta <= 0)
        return 0.0;
    return exp(e->beam_n * log(cos_theta));
}

/* Two-way amplitude transmission through the interfaces between the antennas
 * and the oil: each crossed interface contributes t12 t21 = 1 - r^2. */
double sim_window_transmission(const struct sim_scene *s, double n_oil)
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
double sim_window_delay(const struct sim_engine *e, double gap, double cz)
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

/* How much nearer the layers between antenna and oil make a source look
 * (paraxial reduced thickness): sum t (1 - n_oil / n). */
double sim_window_apparent(const struct sim_engine *e, double gap)
{
    if (!e->has_window)
        return 0.0;
    return gap * (1.0 - e->n_oil) + e->win_t * (1.0 - e->n_oil / e->n_win);
}

/* A ray from antenna a to a point p behind the barrier: if it passes through
 * the barrier, add the barrier's extra delay and return its transmission. */
double sim_barrier_leg(const struct sim_engine *e, const double a[3], const double p[3], double r,
                       double *tau)
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
double sim_gap_lit(const struct sim_engine *e, const struct sim_element *el, const double a[3])
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
        double R = el->mouth;
        double disc = pu * pu - pp + R * R;
        double len = -pu + sqrt(disc > 0 ? disc : 0.0);
        double dc = 0.5 * (el->depth0 + el->depth1);
        lnear = len * el->depth0 / dc;
        lfar = len * el->depth1 / dc;
    }
    if (horiz <= 0)
        return 0.0;
    double lit = el->gap * horiz / rise; /* depth the ray reaches before leaving the gap's height */
    double f = (lit - lnear) / (lfar - lnear);
    return f < 0 ? 0.0 : (f > 1 ? 1.0 : f);
}
