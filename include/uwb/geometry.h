/* Bistatic geometry of a scan: where the phase centres are, how fast the
 * wave travels, and the two-way delay to a point. */
#ifndef UWB_GEOMETRY_H
#define UWB_GEOMETRY_H

#include "uwb/scan.h"

#define UWB_SPEED_OF_LIGHT 299792458.0

struct uwb_geometry {
    double velocity_m_s; /* c / sqrt(eps_r) */
    double tx_dy, tx_dz; /* phase centres relative to the reference point */
    double rx_dy, rx_dz;
    double t0_s; /* header t0 plus any calibration offset */
    double dt_s;
};

void uwb_geometry_from_scan(struct uwb_geometry *g, const struct uwb_scan *scan, double time_zero_offset_s);

/* Two-way delay (s) from Tx to (dy, z) and back to Rx, where dy is the
 * point's height above the antenna reference point. */
double uwb_two_way_delay(const struct uwb_geometry *g, double dy, double z);

#endif
