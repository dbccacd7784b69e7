#include "scene_support.h"

#include "unity.h"
#include "uwbsim/simulate.h"

void scene_set_or_fail(struct sim_scene *scene, const char *key, const char *value)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(scene, key, value, err, sizeof err), err);
}

void scene_tank_winding_pair_with(const char *const *common, const char *const *changed,
                                  struct uwb_scan *base, struct uwb_scan *cur)
{
    struct sim_scene scene;
    char err[512];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&scene));
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, sim_scene_load_json("tools/uwbsim/scenes/fdtd2d-tank-winding.json", &scene, err, sizeof err), err);
    scene_set_or_fail(&scene, "coupling_gain", "0.05");
    scene_set_or_fail(&scene, "t0_s", "-1e-9");
    for (int i = 0; common && common[i]; i += 2)
        scene_set_or_fail(&scene, common[i], common[i + 1]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&scene, 1, base, err, sizeof err), err);
    for (int i = 0; changed && changed[i]; i += 2)
        scene_set_or_fail(&scene, changed[i], changed[i + 1]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&scene, 1, cur, err, sizeof err), err);
}

void scene_tank_winding_pair(const char *key, const char *value, struct uwb_scan *base, struct uwb_scan *cur)
{
    struct sim_scene scene;
    char err[512];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&scene));
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, sim_scene_load_json("tools/uwbsim/scenes/fdtd2d-tank-winding.json", &scene, err, sizeof err), err);
    scene_set_or_fail(&scene, "coupling_gain", "0.05");
    scene_set_or_fail(&scene, "t0_s", "-1e-9");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&scene, 1, base, err, sizeof err), err);
    scene_set_or_fail(&scene, key, value);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&scene, 1, cur, err, sizeof err), err);
}
