/* The best any estimator could do: the Cramer-Rao bound on the winding's
 * displacement for a scene's noise, from the simulator's own derivative. */
#ifndef UWBSIM_BOUND_H
#define UWBSIM_BOUND_H

#include <stddef.h>

#include "scene.h"

struct sim_bound {
    double noise_rms;      /* per sample, after stacking */
    double single_scan_m;  /* 1-sigma bound on one scan's winding height */
    double displacement_m; /* ...on the difference of two scans */
};

/* White receiver noise only (noise_bandwidth_hz 0); the static clutter,
 * jitter and drift are taken as known, so the bound is optimistic.
 * Returns 0, or -1 with err filled. */
int sim_displacement_bound(const struct sim_scene *scene, struct sim_bound *b, char *err, size_t errlen);

#endif
