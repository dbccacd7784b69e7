/* Conditioning before migration: remove DC and slow wander ("wow"), remove
 * what is the same at every antenna position (direct coupling, tank wall,
 * barriers and core legs that run past the aperture) without erasing the
 * winding's flat face, and blank what arrives before the winding can reply. */
#ifndef UWB_CONDITION_H
#define UWB_CONDITION_H

#include <stddef.h>

#include "uwb/geometry.h"
#include "uwb/scan.h"

struct uwb_condition_options {
    int remove_static;          /* subtract the static reference trace (default 1) */
    double static_end_fraction; /* before the winding is located: positions at each end that form the reference (0.25) */
    double highpass_ratio;      /* wow cut-off as a fraction of the dominant frequency (0.15) */
    double gate_range_m;        /* blank replies from nearer than this (0.1 m) */
};

void uwb_condition_defaults(struct uwb_condition_options *opt);

/* Dominant frequency (Hz) of the scan: the peak of its mean power spectrum. */
double uwb_dominant_frequency(const struct uwb_scan *scan);

/* Where the winding can be: a box in y and z. Each position hears it only
 * between the delays to the box's nearest and farthest points. */
struct uwb_target_window {
    double y_lo_m, y_hi_m;
    double z_near_m, z_far_m;
};

/* Fill `out` (a copy of `in` with conditioned data). `winding` (may be NULL
 * before the winding is located) keeps its echoes out of the static reference. */
int uwb_condition(const struct uwb_scan *in, const struct uwb_geometry *g,
                  const struct uwb_condition_options *opt, double dominant_hz,
                  const struct uwb_target_window *winding, struct uwb_scan *out,
                  char *err, size_t errlen);

/* Robust white-noise sigma of a scan's samples: median absolute first
 * difference / (0.6745 * sqrt 2); echoes occupy few samples and barely move it. */
double uwb_noise_sigma(const struct uwb_scan *scan);

#endif
