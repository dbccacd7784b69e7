#include "uwb/geometry.h"

#include <math.h>

void uwb_geometry_from_scan(struct uwb_geometry *g, const struct uwb_scan *scan, double time_zero_offset_s)
{
    double eps = scan->eps_r >= 1.0 ? scan->eps_r : 1.0;
    g->velocity_m_s = UWB_SPEED_OF_LIGHT / sqrt(eps);
    g->tx_dy = scan->tx_m[0];
    g->tx_dz = scan->tx_m[1];
    g->rx_dy = scan->rx_m[0];
    g->rx_dz = scan->rx_m[1];
    g->t0_s = scan->t0_s + time_zero_offset_s;
    g->dt_s = scan->sample_interval_s;
}

double uwb_two_way_delay(const struct uwb_geometry *g, double dy, double z)
{
    /* Plain square roots, as the delay table's: hypot's guard against
     * overflow is not needed at metre scale and costs several times more. */
    double ty = dy - g->tx_dy, tz = z - g->tx_dz, ry = dy - g->rx_dy, rz = z - g->rx_dz;
    double r_tx = sqrt(ty * ty + tz * tz);
    double r_rx = sqrt(ry * ry + rz * rz);
    return (r_tx + r_rx) / g->velocity_m_s;
}
