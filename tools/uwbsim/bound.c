/* Cramer-Rao bound of a vertical shift in white Gaussian noise: the Fisher
 * information is |ds/dd|^2 / sigma^2 summed over every sample of every
 * trace, ds/dd taken by a central difference of two noiseless scans. Static
 * clutter does not depend on the shift and drops out of the derivative. */
#include "bound.h"

#include <math.h>
#include <stdio.h>

#include "simulate.h"

#define HALF_STEP_M 0.0005

/* The scene shifted by shift_m, without jitter, drift or quantisation; with
 * or without its noise; with everything or the winding's echo alone. */
static int scene_variant(const struct sim_scene *scene, double shift_m, int winding_only, int noise,
                         struct uwb_scan *scan, char *err, size_t errlen)
{
    struct sim_scene s = *scene;
    s.noise = noise;
    s.jitter_s = 0.0;
    s.drift_db = 0.0;
    s.adc_bits = 0;
    s.displacement_m += shift_m;
    if (winding_only) {
        s.clutter = 0;
        s.coupling_gain = 0.0;
        s.window_echo = 0;
    }
    return sim_make_scan(&s, 1, scan, err, errlen);
}

int sim_displacement_bound(const struct sim_scene *scene, struct sim_bound *b, char *err, size_t errlen)
{
    if (scene->noise_bandwidth_hz > 0.0) {
        snprintf(err, errlen, "precision bound: only for white noise (noise_bandwidth_hz 0)");
        return -1;
    }
    struct uwb_scan up = {0}, down = {0};
    if (scene_variant(scene, HALF_STEP_M, 1, 0, &up, err, errlen) != 0)
        return -1;
    if (scene_variant(scene, -HALF_STEP_M, 1, 0, &down, err, errlen) != 0) {
        uwb_scan_free(&up);
        return -1;
    }
    /* The noise is what the simulator adds, stacking included: the same
     * scene with and without it. */
    struct uwb_scan noisy = {0}, quiet = {0};
    if (scene_variant(scene, 0.0, 0, 1, &noisy, err, errlen) != 0 ||
        scene_variant(scene, 0.0, 0, 0, &quiet, err, errlen) != 0) {
        uwb_scan_free(&up);
        uwb_scan_free(&down);
        uwb_scan_free(&noisy);
        return -1;
    }
    size_t n = (size_t)up.positions * up.samples;
    double noise_energy = 0.0, information = 0.0;
    for (size_t i = 0; i < n; i++) {
        double e = noisy.data[i] - quiet.data[i];
        noise_energy += e * e;
        double d = (up.data[i] - down.data[i]) / (2.0 * HALF_STEP_M);
        information += d * d;
    }
    uwb_scan_free(&up);
    uwb_scan_free(&down);
    uwb_scan_free(&noisy);
    uwb_scan_free(&quiet);
    b->noise_rms = sqrt(noise_energy / (double)n);
    if (!(information > 0.0)) {
        snprintf(err, errlen, "precision bound: the scan does not change when the winding moves");
        return -1;
    }
    b->single_scan_m = b->noise_rms / sqrt(information);
    b->displacement_m = sqrt(2.0) * b->single_scan_m;
    return 0;
}
