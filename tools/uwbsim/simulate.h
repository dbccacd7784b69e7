/* Whole scans and their truth: what the CLI, the tests and the emulated
 * board's set-up call. */
#ifndef UWBSIM_SIMULATE_H
#define UWBSIM_SIMULATE_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"
#include "uwb/scan.h"

#define SIM_VERSION "1.0"

/* Simulate every position of the scene with noise driven by `seed` into a
 * freshly allocated scan (free with uwb_scan_free). The header holds what
 * the appliance would know (geometry of the antennas, eps_r, optional
 * target_z_m, created/scan_id/comment if set) and `source`; never the truth. */
int sim_make_scan(const struct sim_scene *scene, uint64_t seed, struct uwb_scan *out, char *err,
                  size_t errlen);

/* The scene's true edges as a JSON object text (malloc'd, caller frees):
 * y1_m, y2_m (front corners of the stack), center_m, height_m, z_face_m,
 * displacement_mm, height_change_mm, tilt_deg, scene (description). */
int sim_truth_json(const struct sim_scene *scene, char **json);

struct sim_truth {
    double y1_m, y2_m, center_m, height_m, z_face_m;
};
void sim_truth(const struct sim_scene *scene, struct sim_truth *truth);

#endif
