/* Time zero from the direct coupling: the pulse that goes straight from the
 * transmit to the receive antenna arrives first, strongly, at the same time
 * at every position. Commissioning records its arrival with the baseline;
 * a later scan whose arrival moved (a cable or an antenna changed, the
 * digitiser's delay drifted) cannot be compared with that baseline. */
#ifndef UWB_DIRECT_COUPLING_H
#define UWB_DIRECT_COUPLING_H

#include <stddef.h>

#include "uwb/scan.h"

/* The arrival is where the mean trace's magnitude first reaches this
 * fraction of its largest value in the window (the leading edge: it does
 * not depend on the pulse's amplitude). */
#define UWB_DIRECT_COUPLING_FRACTION 0.5

/* Arrival time of the direct coupling (seconds, the scan's time axis:
 * t0_s + i * sample_interval_s, interpolated between samples), looked for
 * from the first sample up to window_end_s. Returns 0, or -1 with why
 * filled when the window holds no usable arrival. Pure: reads the scan only. */
int uwb_direct_coupling_arrival(const struct uwb_scan *scan, double window_end_s, double *arrival_s,
                                char *why, size_t whylen);

#endif
