/* Scene parameters: one table, settable by name, loadable from JSON with
 * errors that name the offending key; example scene files stay valid. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
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

static char *scene_json(const struct sim_scene *sc)
{
    char *j;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_to_json(sc, &j));
    return j;
}

static void test_defaults_are_the_papers_scene(void)
{
    struct sim_scene sc;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_validate(&sc, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(SIM_MODE_3D, sc.mode);
    TEST_ASSERT_EQUAL_INT(6, sc.disks);
    TEST_ASSERT_EQUAL_DOUBLE(0.022, sc.disk_height_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.004, sc.gap_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.15, sc.outer_radius_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.45, sc.face_z_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.23, sc.bottom_y_m);
    TEST_ASSERT_EQUAL_DOUBLE(2.2, sc.eps_r);
    TEST_ASSERT_EQUAL_INT(21, sc.positions);
    TEST_ASSERT_EQUAL_DOUBLE(0.03, sc.position_step_m);
    TEST_ASSERT_EQUAL_DOUBLE(-0.02, sc.tx_dy_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.02, sc.rx_dy_m);
    TEST_ASSERT_EQUAL_INT(SIM_PULSE_RICKER, sc.pulse);
    TEST_ASSERT_EQUAL_DOUBLE(2e9, sc.centre_frequency_hz);
    TEST_ASSERT_TRUE(sc.clutter && sc.core && sc.barrier && sc.clamp && sc.far_wall);
    TEST_ASSERT_TRUE(isnan(sc.target_z_near_m));
    TEST_ASSERT_EQUAL_STRING("", sc.created); /* reproducible files by default */
}

/* Every parameter's value survives text -> value -> text. */
static void test_every_parameter_round_trips_as_text(void)
{
    struct sim_scene sc;
    char err[256], a[SIM_TEXT_MAX + 64], b[SIM_TEXT_MAX + 64];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    size_t n;
    const struct sim_param *all = sim_params(&n);
    TEST_ASSERT_TRUE(n > 60);
    for (size_t i = 0; i < n; i++) {
        sim_scene_get(&sc, &all[i], a, sizeof a);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(&sc, all[i].name, a, err, sizeof err), err);
        sim_scene_get(&sc, &all[i], b, sizeof b);
        TEST_ASSERT_EQUAL_STRING_MESSAGE(a, b, all[i].name);
        TEST_ASSERT_TRUE_MESSAGE(strlen(all[i].help) > 10, all[i].name);
        TEST_ASSERT_EQUAL_PTR(&all[i], sim_param_find(all[i].name));
    }
}

static void test_cli_spelling_and_errors(void)
{
    struct sim_scene sc;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_set(&sc, "snr-db", "12.5", err, sizeof err));
    TEST_ASSERT_EQUAL_DOUBLE(12.5, sc.snr_db);
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set(&sc, "snr", "1", err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "snr"));
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set(&sc, "disks", "2.5", err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "disks"));
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set(&sc, "eps_r", "0.5", err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "eps_r"));
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set(&sc, "pulse", "square", err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "ricker"));
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set(&sc, "clutter", "maybe", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set(&sc, "face_z_m", "0.4x", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_set(&sc, "target_z_near_m", "0.4", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_validate(&sc, err, sizeof err)); /* near without far */
    TEST_ASSERT_NOT_NULL(strstr(err, "target_z"));
}

static void expect_json_error(const char *text, const char *needle)
{
    struct sim_scene sc;
    char err[512];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    char *before = scene_json(&sc);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, sim_scene_apply_json_text(text, "scene.json", &sc, err, sizeof err),
                                  text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "scene.json"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, needle), err);
    char *after = scene_json(&sc);
    TEST_ASSERT_EQUAL_STRING_MESSAGE(before, after, "a refused file must leave the scene untouched");
    free(before);
    free(after);
}

static void test_json_loader_rejects_with_the_key_named(void)
{
    expect_json_error("{\"snr_db\": 20, \"snr\": 20}", "\"snr\"");
    expect_json_error("{\"disks\": 6, \"face_z_m\": \"0.45\"}", "face_z_m");
    expect_json_error("{\"disks\": 6.5}", "disks");
    expect_json_error("{\"clutter\": 1}", "clutter");
    expect_json_error("{\"pulse\": 2}", "pulse");
    expect_json_error("{\"pulse\": \"square\"}", "pulse");
    expect_json_error("{\"eps_r\": 0.5}", "eps_r");
    expect_json_error("{\"snr-db\": 20}", "snr-db"); /* JSON uses the underscore names */
    expect_json_error("[1, 2]", "one JSON object");
    expect_json_error("{\"disks\": 6,,}", "not valid JSON");
}

static void test_json_round_trip_and_partial_files(void)
{
    struct sim_scene a, b;
    char err[512];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&a));
    a.mode = SIM_MODE_2D;
    a.displacement_m = -0.013;
    a.tilt_deg = 1.5;
    a.target_z_near_m = 0.40;
    a.target_z_far_m = 0.50;
    strcpy(a.comment, "bench \"quoted\" text");
    char *text = scene_json(&a);
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&b));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_apply_json_text(text, "round", &b, err, sizeof err), err);
    char *again = scene_json(&b);
    TEST_ASSERT_EQUAL_STRING(text, again);
    free(text);
    free(again);
    /* a partial file changes only what it names */
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&b));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_apply_json_text("{\"snr_db\": 12, \"target_z_near_m\": null}", "p", &b,
                                                       err, sizeof err));
    TEST_ASSERT_EQUAL_DOUBLE(12, b.snr_db);
    TEST_ASSERT_EQUAL_INT(6, b.disks);
    TEST_ASSERT_TRUE(isnan(b.target_z_near_m));
    /* a missing file is named */
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_load_json("/nonexistent/scene.json", &b, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "/nonexistent/scene.json"));
}

static void test_validation_names_the_parameters(void)
{
    struct sim_scene sc;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.height_change_m = -0.03; /* five 4 mm gaps cannot lose 30 mm */
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_validate(&sc, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "height_change_m"));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.sample_interval_s = 1e-10; /* too coarse for 2 GHz */
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_validate(&sc, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "sample_interval_s"));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.pulse = SIM_PULSE_FILE;
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_validate(&sc, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "pulse_file"));
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.reference = 1;
    sc.reference_z_m = sc.face_z_m; /* the reference target stands in front of the barrier */
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_validate(&sc, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "reference_z_m"));
    sc.reference_z_m = 0.2;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_validate(&sc, err, sizeof err));
}

/* The example scenes shipped in tools/uwbsim/scenes load, validate and run. */
static void test_example_scenes_run(void)
{
    glob_t g;
    TEST_ASSERT_EQUAL_INT(0, glob("tools/uwbsim/scenes/*.json", 0, NULL, &g));
    TEST_ASSERT_TRUE(g.gl_pathc >= 3);
    for (size_t i = 0; i < g.gl_pathc; i++) {
        struct sim_scene sc;
        struct uwb_scan s;
        char err[512];
        TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_load_json(g.gl_pathv[i], &sc, err, sizeof err), err);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 1, &s, err, sizeof err), err);
        TEST_ASSERT_TRUE_MESSAGE(sc.description[0] != '\0', g.gl_pathv[i]);
        uwb_scan_free(&s);
    }
    globfree(&g);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_defaults_are_the_papers_scene);
    RUN_TEST(test_every_parameter_round_trips_as_text);
    RUN_TEST(test_cli_spelling_and_errors);
    RUN_TEST(test_json_loader_rejects_with_the_key_named);
    RUN_TEST(test_json_round_trip_and_partial_files);
    RUN_TEST(test_validation_names_the_parameters);
    RUN_TEST(test_example_scenes_run);
    return UNITY_END();
}
