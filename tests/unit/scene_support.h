/* Helpers shared by the tests that build simulator scenes. */
#ifndef UWB_SCENE_SUPPORT_H
#define UWB_SCENE_SUPPORT_H

#include "uwbsim/scene.h"

/* Set one scene parameter by name (as uwbsim --name value), or fail the
 * current test with the simulator's message. */
void scene_set_or_fail(struct sim_scene *scene, const char *key, const char *value);

#endif
