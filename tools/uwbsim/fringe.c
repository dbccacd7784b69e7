/* The physical theory of diffraction's fringe term for a metal wedge. */
#include <math.h>

#include "engine_internal.h"

/* PTD fringe coefficient of a metal wedge (exterior angle n pi): Keller's
 * exact diffraction coefficient minus the one physical optics already
 * produces from the two faces' ends, both in units of e^{-i pi/4}/sqrt(2 pi k).
 * phi: direction to Rx, phip: to Tx, from face A. Soft = E along the edge
 * (Dirichlet), otherwise E across it. */
static double fringe_at(double phi, double phip, double n, int soft, int *near_singular)
{
    const double tiny = 1e-6;
    double cn = cos(M_PI / n), sn = sin(M_PI / n);
    double d1 = cn - cos((phi - phip) / n), d2 = cn - cos((phi + phip) / n);
    if (fabs(d1) < tiny || fabs(d2) < tiny)
        *near_singular = 1;
    /* Keller: D = (sin(pi/n)/n) [1/d1 -+ 1/d2] for the field along the edge.
     * Our trace is E: for E along the edge (soft) that is D_s itself; for E
     * across it the field along the edge is H, whose plate reflection is +1
     * where E's is -1, so E diffracts with -D_h. Either way the reflection
     * boundary term (1/d2) then matches physical optics' and cancels in
     * the fringe. */
    double gtd = soft ? (sn / n) * (1.0 / d1 - 1.0 / d2) : -(sn / n) * (1.0 / d1 + 1.0 / d2);
    double po = 0.0;
    /* face A: lit and seen when both directions are on its outer side */
    if (sin(phi) > 0 && sin(phip) > 0) {
        double den = cos(phi) + cos(phip);
        if (fabs(den) < tiny)
            *near_singular = 1;
        po += 0.5 * (sin(phi) + sin(phip)) / den; /* G = -1 folded in */
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

double sim_fringe(double phi, double phip, double n, int soft)
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
double sim_wedge_angle(const struct sim_edge *ed, const double u[3])
{
    const double *t = ed->tangent;
    double ut = u[0] * t[0] + u[1] * t[1] + u[2] * t[2];
    double p[3] = {u[0] - ut * t[0], u[1] - ut * t[1], u[2] - ut * t[2]};
    double x = p[0] * ed->s_a[0] + p[1] * ed->s_a[1] + p[2] * ed->s_a[2];
    double y = p[0] * ed->n_a[0] + p[1] * ed->n_a[1] + p[2] * ed->n_a[2];
    double a = atan2(y, x);
    return a < 0 ? a + 2.0 * M_PI : a;
}
