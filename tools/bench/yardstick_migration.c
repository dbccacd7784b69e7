/* The yardstick our migration is measured against: delay-and-sum written
 * the obvious way, in double precision. For every pixel and every trace the
 * two-way path Tx -> pixel -> Rx comes from two square roots, the delay is
 * turned into a fractional sample position and the trace is interpolated
 * linearly there. Same conventions as the library (delays outside the
 * record add nothing), so its image is the accuracy reference too. */
#include "bench.h"

#include <math.h>

void yardstick_migrate(const struct uwb_scan *scan, const struct uwb_geometry *g, int ny, int nz, double y0_m,
                       double dy_m, double z0_m, double dz_m, double *out)
{
    int S = scan->samples;
    for (int iy = 0; iy < ny; iy++) {
        double y = y0_m + iy * dy_m;
        for (int iz = 0; iz < nz; iz++) {
            double z = z0_m + iz * dz_m, sum = 0.0;
            for (int k = 0; k < scan->positions; k++) {
                double dy = y - scan->antenna_y_m[k];
                double tx_y = dy - g->tx_dy, tx_z = z - g->tx_dz;
                double rx_y = dy - g->rx_dy, rx_z = z - g->rx_dz;
                double path = sqrt(tx_y * tx_y + tx_z * tx_z) + sqrt(rx_y * rx_y + rx_z * rx_z);
                double f = (path / g->velocity_m_s - g->t0_s) / g->dt_s;
                if (!(f >= 0.0) || f >= (double)(S - 1))
                    continue;
                int i = (int)f;
                double w = f - i;
                const float *trace = scan->data + (size_t)k * S;
                sum += (1.0 - w) * trace[i] + w * trace[i + 1];
            }
            out[(size_t)iy * nz + iz] = sum;
        }
    }
}
