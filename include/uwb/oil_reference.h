/* The oil's wave speed between two scans, read from the static scene in
 * front of the winding (src/imaging/oil_reference.c): what a change of the
 * oil alone (its temperature) would move the face's range by. It is the
 * radial profile's absolute reference: a change over half the face leaves
 * no majority of unchanged rows to tell it from its complement, while the
 * oil's own offset says which rows did not move. */
#ifndef UWB_OIL_REFERENCE_H
#define UWB_OIL_REFERENCE_H

#include <stddef.h>

#include "uwb/scan.h"

struct uwb_oil_reference {
    int measured;         /* 0: see why */
    double face_offset_m; /* baseline range less this scan's at the face, from the oil alone (+: nearer) */
    double sigma_m;       /* its 1-sigma */
    double echo_range_m;  /* where the static echoes it was read from lie (their energy's centre) */
    char why[160];
};

/* Compare the static echoes of the two raw scans (their mean trace over
 * the positions) between near_m and face_z_m less a wavelength (the face's
 * own echo and its blur moved), ranges at velocity_m_s, and scale the
 * delay found to the face's range. Fills *ref; never fails otherwise. */
void uwb_oil_reference_measure(const struct uwb_scan *current, const struct uwb_scan *baseline,
                               double velocity_m_s, double face_z_m, double wavelength_m,
                               struct uwb_oil_reference *ref);

#endif
