/* A noisy copy of a recorded scan, for judging the uncertainty over many
 * independent copies: white noise, per-position timing jitter and amplitude
 * drift along the aperture, all from one seeded stream. */
#ifndef UWB_IMPAIR_H
#define UWB_IMPAIR_H

#include <stddef.h>
#include <stdint.h>

#include "uwb/scan.h"

struct uwb_impairment {
    int add_noise;       /* 0: no white noise (snr_db unused) */
    double snr_db;       /* noise rms this far below the reference peak */
    double jitter_s;     /* rms of each position's time shift */
    double drift_linear; /* gain rises by this from the first position to the last */
    double drift_random; /* rms of each position's random gain offset */
    uint64_t seed;
};

/* What was applied (for messages and the header comment). */
struct uwb_impairment_report {
    double gate_s;         /* echoes counted from this time on */
    double reference_peak; /* largest |sample| from gate_s on, over every position */
    double noise_sigma;    /* rms of the added noise per sample */
};

/* Start of the echoes after the direct coupling: the two-way delay (the
 * scan's own Tx/Rx offsets and eps_r) to a point 0.1 m straight ahead of the
 * antenna reference point, plus two periods of the scan's dominant
 * frequency (the peak of its mean power spectrum). */
double uwb_impair_gate_s(const struct uwb_scan *scan);

/* Impair `scan` in place. Per position k (in order): draw the jitter
 * tau_k = jitter_s * N(0,1) and the gain offset r_k = drift_random * N(0,1);
 * the trace is delayed by tau_k (a linear phase ramp over a zero-padded FFT)
 * and scaled by 1 + drift_linear * k/(K-1) + r_k. Then, position by position
 * and sample by sample, white Gaussian noise of rms
 * reference_peak * 10^(-snr_db/20) is added, reference_peak measured on the
 * scan before any impairment. Normals come from xoshiro256** seeded by
 * splitmix64(seed), by Box-Muller, two per pair of uniforms; the draws are
 * made whatever the settings, so the same seed gives the same noise with or
 * without jitter or drift. Returns 0, or -1 with err filled. */
int uwb_impair_scan(struct uwb_scan *scan, const struct uwb_impairment *imp,
                    struct uwb_impairment_report *report, char *err, size_t errlen);

#endif
