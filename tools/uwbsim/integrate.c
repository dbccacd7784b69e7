/* One antenna position: every lit surface element and every edge piece,
 * weighted and deposited on the fine time grid (see engine.h for the model). */
#include <math.h>

#include "engine_internal.h"

void sim_deposit(const struct sim_engine *e, double *acc, double tau, double amp)
{
    double x = (tau - e->grid_t0) / e->dt;
    if (!(x >= 0) || x >= e->nfft - 1)
        return;
    int i = (int)x;
    double f = x - i;
    acc[i] += amp * (1.0 - f);
    acc[i + 1] += amp * f;
}

static void integrate_edges(struct sim_engine *e, const double tx[3], const double rx[3], const double txl[3],
                            const double rxl[3], double tx_gap, double rx_gap)
{
    double tx_app = sim_window_apparent(e, tx_gap), rx_app = sim_window_apparent(e, rx_gap);
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
        double phip = sim_wedge_angle(ed, u1), phi = sim_wedge_angle(ed, u2);
        if (phip > wedge || phi > wedge)
            continue; /* looking at it from inside the metal */
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
        double s1 = r1 - tx_app / cz1, s2 = r2 - rx_app / cz2;
        double amp = sim_fringe(phi, phip, ed->wedge_n, soft) * ed->length;
        amp *= e->mode2d ? 1.0 / sqrt(s1 * s2) : 1.0 / (s1 * s2);
        if (e->beam_n > 0)
            amp *= exp(e->beam_n * log(cz1 * cz2));
        double tau = (r1 + r2) * e->inv_v;
        if (e->has_window)
            tau += sim_window_delay(e, tx_gap, cz1) + sim_window_delay(e, rx_gap, cz2);
        if (g->has_barrier) {
            amp *= sim_barrier_leg(e, tx, p, r1, &tau);
            amp *= sim_barrier_leg(e, rx, p, r2, &tau);
        }
        sim_deposit(e, e->acc_edge, tau, amp);
    }
}

void sim_integrate_surfaces(struct sim_engine *e, double y_ref, unsigned parts)
{
    const struct sim_scene *s = &e->scene;
    const struct sim_geometry *g = &e->geo;
    double tx[3] = {0.0, y_ref + s->tx_dy_m, s->tx_dz_m};
    double rx[3] = {0.0, y_ref + s->rx_dy_m, s->rx_dz_m};
    double txl[3], rxl[3];
    sim_geometry_to_local(g, tx, txl);
    sim_geometry_to_local(g, rx, rxl);
    double tx_gap = fmax(0.0, s->window_gap_m - tx[2]), rx_gap = fmax(0.0, s->window_gap_m - rx[2]);
    double tx_app = sim_window_apparent(e, tx_gap), rx_app = sim_window_apparent(e, rx_gap);
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
        /* spreading from the apparent source: the window's layers make it look
         * nearer (or the air gap farther) by sum t (1 - n_oil/n) per leg */
        double s1 = r1, s2 = r2;
        if (e->has_window) {
            s1 -= tx_app / cz1;
            s2 -= rx_app / cz2;
        }
        double amp = el->refl * el->area;
        amp *= mode2d ? 1.0 / sqrt(s1 * s2) : 1.0 / (s1 * s2);
        if (e->beam_n > 0)
            amp *= exp(e->beam_n * log(cz1 * cz2));
        /* Kirchhoff kernel: obliquity times (i k + 1/R) in 3-D; the 1/R part
         * shares the edges' kernel (no time derivative). 2-D keeps the
         * far-field Hankel form (its next term is only 3/(8 k R)). */
        double obl = -0.5 * (c1 + c2);
        double near = mode2d ? 0.0 : -0.5 * (c1 / r1 + c2 / r2);
        double tau = (r1 + r2) * inv_v;
        if (e->has_window)
            tau += sim_window_delay(e, tx_gap, cz1) + sim_window_delay(e, rx_gap, cz2);
        if (el->kind != SIM_ELEM_PLAIN) {
            double f = sim_gap_lit(e, el, txl);
            if (f > 0)
                f = fmin(f, sim_gap_lit(e, el, rxl));
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
            amp *= sim_barrier_leg(e, tx, p, r1, &tau);
            amp *= sim_barrier_leg(e, rx, p, r2, &tau);
        }
        sim_deposit(e, e->acc, tau, amp * obl);
        if (near != 0)
            sim_deposit(e, e->acc_edge, tau, amp * near);
        if (el->refl2 != 0) {
            /* thin layer's back face: optical path 2 n t cos(theta_t) later */
            double no = e->n_oil, nb = g->barrier_n;
            double extra =
                g->barrier_thickness *
                (sqrt(nb * nb - no * no * (1 - c1 * c1)) + sqrt(nb * nb - no * no * (1 - c2 * c2))) / C0;
            double back = el->refl2 / el->refl;
            sim_deposit(e, e->acc, tau + extra, amp * obl * back);
            if (near != 0)
                sim_deposit(e, e->acc_edge, tau + extra, amp * near * back);
        }
    }
    if ((parts & SIM_PART_WINDING) && g->edge_count > 0)
        integrate_edges(e, tx, rx, txl, rxl, tx_gap, rx_gap);
}
