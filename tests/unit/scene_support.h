/* Helpers shared by the tests that build simulator scenes. */
#ifndef UWB_SCENE_SUPPORT_H
#define UWB_SCENE_SUPPORT_H

#include "uwb/scan.h"
#include "uwbsim/scene.h"

/* Set one scene parameter by name (as uwbsim --name value), or fail the
 * current test with the simulator's message. */
void scene_set_or_fail(struct sim_scene *scene, const char *key, const char *value);

/* The shared full-wave tank's winding in the simulator (its scene with a
 * direct coupling, for the time zero: tools/accuracy/radial-limits.sh),
 * intact into *base, and with one parameter set (key = value) into *cur;
 * fails the current test when the simulator refuses. */
void scene_tank_winding_pair(const char *key, const char *value, struct uwb_scan *base, struct uwb_scan *cur);

/* The same with `common` (key, value, ... NULL) set in both scans first,
 * and `changed` (key, value, ... NULL) in the current one only. */
void scene_tank_winding_pair_with(const char *const *common, const char *const *changed,
                                  struct uwb_scan *base, struct uwb_scan *cur);

#endif
