#include "scene_support.h"

#include "unity.h"

void scene_set_or_fail(struct sim_scene *scene, const char *key, const char *value)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(scene, key, value, err, sizeof err), err);
}
