/* The truth file: where the stack's front corners really are. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"
#include "uwbsim/uwbsim.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static void test_default_truth(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    struct sim_truth t;
    sim_truth(&sc, &t);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.230, t.y1_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.382, t.y2_m); /* 6 x 22 mm + 5 x 4 mm */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.306, t.center_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.152, t.height_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.450, t.z_face_m);
}

static void test_displacement_and_height_change(void)
{
    struct sim_scene sc;
    struct sim_truth t;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.displacement_m = 0.020;
    sim_truth(&sc, &t);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.250, t.y1_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.402, t.y2_m);
    sc.displacement_m = 0;
    sc.height_change_m = 0.010; /* elongation about a fixed centre */
    sim_truth(&sc, &t);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.162, t.height_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.306, t.center_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.225, t.y1_m);
}

static void test_tilt_moves_the_front_corners(void)
{
    struct sim_scene sc;
    struct sim_truth t;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.tilt_deg = 2.0; /* top toward the antennas */
    sim_truth(&sc, &t);
    double th = 2.0 * M_PI / 180, h = 0.076, R = 0.15, yc = 0.306;
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, yc - h * cos(th) - R * sin(th), t.y1_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, yc + h * cos(th) - R * sin(th), t.y2_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.45 + R - R * cos(th), t.z_face_m);
    sc.tilt_azimuth_deg = 90; /* sideways: the front corners barely move */
    sim_truth(&sc, &t);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, yc - h * cos(th), t.y1_m);
}

static void test_truth_json(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.displacement_m = -0.0125;
    strcpy(sc.description, "unit test scene");
    char *json;
    TEST_ASSERT_EQUAL_INT(0, sim_truth_json(&sc, &json));
    cJSON *o = cJSON_Parse(json);
    TEST_ASSERT_NOT_NULL(o);
    struct sim_truth t;
    sim_truth(&sc, &t);
    const char *keys[] = {"y1_m", "y2_m", "center_m", "height_m", "z_face_m", "displacement_mm"};
    const double want[] = {t.y1_m, t.y2_m, t.center_m, t.height_m, t.z_face_m, -12.5};
    for (int i = 0; i < 6; i++) {
        cJSON *v = cJSON_GetObjectItemCaseSensitive(o, keys[i]);
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(v), keys[i]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, want[i], v->valuedouble);
    }
    cJSON *d = cJSON_GetObjectItemCaseSensitive(o, "scene");
    TEST_ASSERT_TRUE(cJSON_IsString(d));
    TEST_ASSERT_EQUAL_STRING("unit test scene", d->valuestring);
    cJSON_Delete(o);
    free(json);
}

/* The truth never leaks into what processing reads: the header holds no
 * winding geometry, whatever the displacement. */
static void test_header_carries_no_truth(void)
{
    struct sim_scene a, b;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&a));
    b = a;
    b.displacement_m = 0.037;
    b.height_change_m = -0.004;
    struct uwb_scan sa, sb;
    char err[512];
    unsigned char *ba, *bb;
    size_t la, lb;
    TEST_ASSERT_EQUAL_INT(0, sim_make_scan(&a, 1, &sa, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, sim_make_scan(&b, 1, &sb, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbscan_serialise(&sa, &ba, &la, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbscan_serialise(&sb, &bb, &lb, err, sizeof err));
    size_t ha = (size_t)((unsigned char *)memchr(ba, '\n', la) - ba);
    size_t hb = (size_t)((unsigned char *)memchr(bb, '\n', lb) - bb);
    TEST_ASSERT_EQUAL_UINT64(ha, hb);
    TEST_ASSERT_EQUAL_INT(0, memcmp(ba, bb, ha));
    TEST_ASSERT_FALSE(sa.has_target_z);
    free(ba);
    free(bb);
    uwb_scan_free(&sa);
    uwb_scan_free(&sb);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_default_truth);
    RUN_TEST(test_displacement_and_height_change);
    RUN_TEST(test_tilt_moves_the_front_corners);
    RUN_TEST(test_truth_json);
    RUN_TEST(test_header_carries_no_truth);
    return UNITY_END();
}
