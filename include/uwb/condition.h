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
    double static_end_fraction; /* before the winding is located: positions at each end that form the
                                   reference (0.25) */
    double highpass_ratio;      /* wow cut-off as a fraction of the dominant frequency (0.15) */
    double lowpass_ratio; /* noise cut-off: pass to this times the dominant frequency, none beyond 1.5x it
                             (2.0; 0 = off) */
    double gate_range_m;  /* blank replies from nearer than this (0.1 m) */
    int align_coupling;   /* undo trigger jitter and gain drift per trace, measured on the direct coupling (1)
                           */
};

void uwb_condition_defaults(struct uwb_condition_options *opt);

/* Dominant frequency (Hz) of the scan: the peak of its mean power spectrum,
 * each trace's spectrum taken as a share of its own power (so that no
 * trace's gain weighs in).
 * Returns 0 with *hz > 0, or -1 with err filled (no memory for the
 * transform, or a scan with no spectrum) and *hz = 0. */
int uwb_dominant_frequency(const struct uwb_scan *scan, double *hz, char *err, size_t errlen);

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
                  const struct uwb_target_window *winding, struct uwb_scan *out, char *err, size_t errlen);

/* What the alignment on the direct coupling did. */
struct uwb_alignment {
    int aligned;        /* traces shifted/scaled (others did not resemble the reference) */
    double max_shift_s; /* largest trigger shift removed */
    double max_gain_db; /* largest gain change removed */
};

/* Shift and scale each trace so that its part before window_end_s (the
 * direct coupling and the window, before anything in the tank replies)
 * matches the median of all traces. Leaves the scan untouched when that
 * part is too short or absent. */
int uwb_align_to_coupling(struct uwb_scan *scan, double window_end_s, double t0_s, double period_s,
                          struct uwb_alignment *report, char *err, size_t errlen);

/* Robust noise sigma of conditioned traces: median |sample| / 0.6745 over
 * every sample from first_sample on. Conditioning leaves zero-mean noise
 * plus echoes that fill a small part of the record, so the median is set by
 * the noise (echoes can only raise it: the estimate errs on the safe side).
 * Band-limited noise is strongly correlated between samples, so a
 * difference-based estimator would read it far too low. */
double uwb_noise_sigma(const struct uwb_scan *scan, int first_sample);

/* First sample the early-time gate leaves fully open. */
int uwb_condition_first_open_sample(const struct uwb_scan *scan, const struct uwb_geometry *g,
                                    const struct uwb_condition_options *opt, double dominant_hz);

#endif
