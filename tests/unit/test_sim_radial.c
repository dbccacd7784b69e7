/* Radial changes in the simulator (issue 30): disks' fronts moved toward
 * the antennas (+, a bulge) or away (-, a dent), and a lean of the face. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"
#include "uwbsim/uwbsim.h"

#define C0 299792458.0

void setUp(void)
{
}
void tearDown(void)
{
}

/* Winding only, nothing random: the paper's six disks. */
static void bare_scene(struct sim_scene *sc, int mode2d)
{
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(sc));
    sc->mode = mode2d ? SIM_MODE_2D : SIM_MODE_3D;
    sc->clutter = 0;
    sc->window_thickness_m = 0;
    sc->window_gap_m = 0;
    sc->window_echo = 0;
    sc->coupling_gain = 0;
    sc->noise = 0;
    sc->jitter_s = 0;
    sc->drift_db = 0;
    sc->adc_bits = 0;
}

static void set(struct sim_scene *sc, const char *key, const char *value)
{
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(sc, key, value, err, sizeof err), err);
}

static float *winding_trace(const struct sim_scene *sc, double y)
{
    struct sim_engine *e;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(sc, &e, err, sizeof err), err);
    double *tr = malloc((size_t)sc->samples * sizeof *tr);
    float *f = malloc((size_t)sc->samples * sizeof *f);
    TEST_ASSERT_NOT_NULL(tr);
    TEST_ASSERT_NOT_NULL(f);
    sim_engine_clean_trace(e, y, SIM_PART_WINDING, 0.0, tr);
    for (int i = 0; i < sc->samples; i++)
        f[i] = (float)tr[i];
    free(tr);
    sim_engine_free(e);
    return f;
}

/* Samples by which the echo of `moved` is later than that of `ref` at
 * antenna height y, over a window around the face echo. */
static double echo_lag(const struct sim_scene *ref, const struct sim_scene *moved, double y, double *corr)
{
    float *a = winding_trace(ref, y), *b = winding_trace(moved, y);
    double path = 2 * ref->face_z_m * sqrt(ref->eps_r) / C0;
    int i0 = (int)((path - ref->t0_s) / ref->sample_interval_s) - 150, i1 = i0 + 400;
    if (i0 < 0)
        i0 = 0;
    if (i1 > ref->samples)
        i1 = ref->samples;
    double lag = sim_xcorr_lag(a, b, ref->samples, i0, i1, 40);
    if (corr)
        *corr = sim_correlation(a, b, i0, i1);
    free(a);
    free(b);
    return lag;
}

/* Two-way delay of a front moved by d, in samples. */
static double two_way_samples(const struct sim_scene *sc, double d)
{
    return 2 * d * sqrt(sc->eps_r) / C0 / sc->sample_interval_s;
}

/* Height of the centre of disk k (1-based) before any displacement. */
static double disk_centre_y(const struct sim_scene *sc, int k)
{
    return sc->bottom_y_m + (k - 1) * (sc->disk_height_m + sc->gap_m) + 0.5 * sc->disk_height_m;
}

static void check_whole_face(int mode2d)
{
    struct sim_scene intact, bulged, nearer;
    bare_scene(&intact, mode2d);
    bulged = intact;
    set(&bulged, "radial_m", "1-6:0.006");
    /* the same solid: the face 6 mm nearer, the back face where it was */
    nearer = intact;
    nearer.face_z_m -= 0.006;
    nearer.outer_radius_m += 0.006;
    nearer.radial_build_m += 0.006;
    double y = sim_scene_nominal_center_y_m(&intact), corr;
    double same = echo_lag(&nearer, &bulged, y, &corr);
    double lag = echo_lag(&intact, &bulged, y, NULL), expect = -two_way_samples(&intact, 0.006);
    printf("%s: every disk bulged 6 mm: echo %.2f samples later (two-way delay %.2f); against a face 6 mm "
           "nearer: lag %.3f, correlation %.6f\n",
           mode2d ? "2-D" : "3-D", lag, expect, same, corr);
    TEST_ASSERT_DOUBLE_WITHIN(0.05, 0.0, same);
    TEST_ASSERT_TRUE(corr > 0.999);
    TEST_ASSERT_DOUBLE_WITHIN(0.3, expect, lag);
}

static void test_every_disk_bulged_is_the_face_nearer_2d(void)
{
    check_whole_face(1);
}

static void test_every_disk_bulged_is_the_face_nearer_3d(void)
{
    check_whole_face(0);
}

/* The antennas see the whole face at once: a bulge of three disks moves the
 * echo facing it by part of its two-way delay, and the echo facing the
 * intact disks far less. */
static void check_partial(int mode2d, double metres)
{
    struct sim_scene intact, moved;
    bare_scene(&intact, mode2d);
    intact.disks = 9;
    moved = intact;
    char text[64];
    snprintf(text, sizeof text, "2-4:%g", metres);
    set(&moved, "radial_m", text);
    double full = -two_way_samples(&intact, metres);
    double facing = echo_lag(&intact, &moved, disk_centre_y(&intact, 3), NULL);
    double away = echo_lag(&intact, &moved, disk_centre_y(&intact, 9), NULL);
    printf(
        "%s: disks 2-4 of 9 moved %+g mm: facing echo %+.2f samples, facing disk 9 %+.2f (two-way %+.2f)\n",
        mode2d ? "2-D" : "3-D", metres * 1e3, facing, away, full);
    TEST_ASSERT_TRUE_MESSAGE(facing / full > 0.3 && facing / full < 1.1,
                             "the facing echo did not move enough");
    TEST_ASSERT_TRUE_MESSAGE(fabs(away) < 0.5 * fabs(facing), "the echo facing intact disks moved as much");
}

static void test_partial_bulge_moves_the_echo_facing_it(void)
{
    check_partial(1, 0.006);
    check_partial(0, 0.006);
}

static void test_partial_dent_delays_the_echo_facing_it(void)
{
    check_partial(1, -0.006);
}

/* Every front-facing element of the winding sits where its disk's (or its
 * gap's mouth's) front is; nothing else moved. */
static void check_front_elements(const struct sim_scene *sc, const double *expect_front, int gaps_at_mouth)
{
    struct sim_geometry g;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_geometry_build(sc, &g, err, sizeof err), err);
    double h = 0.5 * sim_scene_stack_height_m(sc), pitch = sim_scene_pitch_m(sc);
    int seen[SIM_DISKS_MAX] = {0};
    for (size_t i = 0; i < g.count; i++) {
        const struct sim_element *e = &g.el[i];
        if (e->part != SIM_PART_WINDING || fabs(e->nrm[1]) > 1e-9)
            continue; /* end faces */
        double y = e->lpos[1] + h;
        int k = (int)floor(y / pitch);
        if (k >= sc->disks)
            k = sc->disks - 1;
        double in_disk = y - k * pitch, want;
        if (in_disk <= sc->disk_height_m + 1e-12) {
            want = expect_front[k];
            seen[k]++;
        } else {
            want = gaps_at_mouth ? fmin(expect_front[k], expect_front[k + 1]) : NAN;
        }
        double got = sc->mode == SIM_MODE_2D ? -e->lpos[2] - sc->outer_radius_m
                                             : hypot(e->lpos[0], e->lpos[2]) - sc->outer_radius_m;
        if (!isnan(want))
            TEST_ASSERT_DOUBLE_WITHIN(1e-12, want, got);
    }
    for (int k = 0; k < sc->disks; k++)
        TEST_ASSERT_TRUE(seen[k] > 0);
    sim_geometry_free(&g);
}

static void test_front_elements_sit_at_each_disks_front(void)
{
    for (int mode2d = 0; mode2d < 2; mode2d++)
        for (int pol = 0; pol < 2; pol++) {
            struct sim_scene sc;
            bare_scene(&sc, mode2d);
            sc.polarisation = pol;
            set(&sc, "radial_m", "2-4:0.006,5:-0.003");
            double expect[6] = {0, 0.006, 0.006, 0.006, -0.003, 0};
            check_front_elements(&sc, expect, pol == SIM_POL_PARALLEL);
        }
}

static void test_face_tilt_is_linear_from_bottom_to_top(void)
{
    struct sim_scene sc;
    bare_scene(&sc, 1);
    set(&sc, "face_tilt_m", "0.006");
    double front[SIM_DISKS_MAX];
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_disk_fronts(&sc, front, err, sizeof err));
    for (int i = 0; i < 6; i++)
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.006 * i / 5, front[i]);
    double expect[6];
    memcpy(expect, front, sizeof expect);
    check_front_elements(&sc, expect, 1);
    set(&sc, "radial_m", "1:0.002"); /* added to the tilt */
    TEST_ASSERT_EQUAL_INT(0, sim_scene_disk_fronts(&sc, front, err, sizeof err));
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.002, front[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.006, front[5]);
}

/* A lean of the face: the top disk's echo comes earlier, the bottom's not. */
static void test_face_tilt_moves_the_top_echo_not_the_bottom(void)
{
    struct sim_scene intact, tilted;
    bare_scene(&intact, 1);
    intact.disks = 9;
    tilted = intact;
    set(&tilted, "face_tilt_m", "0.008");
    double full = -two_way_samples(&intact, 0.008);
    double top = echo_lag(&intact, &tilted, disk_centre_y(&intact, 9), NULL);
    double bottom = echo_lag(&intact, &tilted, disk_centre_y(&intact, 1), NULL);
    printf("face tilt 8 mm (9 disks): echo facing the top %+.2f samples, facing the bottom %+.2f (two-way "
           "%+.2f)\n",
           top, bottom, full);
    TEST_ASSERT_TRUE(top / full > 0.4);
    TEST_ASSERT_TRUE(fabs(bottom) < 0.5 * fabs(top));
}

static void load_scan(const char *path, struct uwb_scan *scan)
{
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(path, scan, err, sizeof err), err);
}

/* Against the full-wave solver (gprMax 2-D, tests/fixtures): the shared
 * tank's winding with disks 2-4 bulged 4 mm. Where the antennas face the
 * winding, the face echo moves by the same part of the bulge's two-way
 * delay as in the full-wave scans, position by position (the FDTD's barrier,
 * core, clamp and end rings, left out here, are the same in both of its
 * scans). */
static void test_a_bulge_moves_the_echo_as_the_full_wave_solver_does(void)
{
    struct uwb_scan fd_base, fd_bulge, base, bulge;
    load_scan("tests/fixtures/fdtd2d-tank-d+00.0.uwbscan", &fd_base);
    load_scan("tests/fixtures/fdtd2d-tank-radial-r2-4+4-d+00.0.uwbscan", &fd_bulge);
    struct sim_scene sc;
    char err[512];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, sim_scene_load_json("tools/uwbsim/scenes/fdtd2d-tank-winding.json", &sc, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 1, &base, err, sizeof err), err);
    set(&sc, "radial_m", "2-4:0.004");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 1, &bulge, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(fd_base.positions, base.positions);
    TEST_ASSERT_EQUAL_INT(fd_base.samples, base.samples);
    TEST_ASSERT_EQUAL_DOUBLE(fd_base.sample_interval_s, base.sample_interval_s);
    TEST_ASSERT_EQUAL_DOUBLE(fd_base.t0_s, base.t0_s);

    int S = base.samples;
    double full = -two_way_samples(&sc, 0.004);
    int face = (int)((2 * sc.face_z_m * sqrt(sc.eps_r) / C0 - sc.t0_s) / sc.sample_interval_s);
    double worst = 0;
    int k_fd = 0, k_sim = 0;
    double most_fd = 0, most_sim = 0;
    printf("disks 2-4 bulged 4 mm (two-way %.2f samples): y, echo moved / two-way delay: FDTD, sim\n", full);
    for (int k = 0; k < base.positions; k++) {
        double y = base.antenna_y_m[k];
        if (y < 0.18 - 1e-9 || y > 0.39 + 1e-9)
            continue; /* facing the winding (0.23 to 0.392 m) */
        double lf = sim_xcorr_lag(fd_base.data + (size_t)k * S, fd_bulge.data + (size_t)k * S, S, face - 60,
                                  face + 140, 40) /
                    full;
        double ls = sim_xcorr_lag(base.data + (size_t)k * S, bulge.data + (size_t)k * S, S, face - 60,
                                  face + 140, 40) /
                    full;
        printf("  %.2f  %.2f  %.2f\n", y, lf, ls);
        worst = fmax(worst, fabs(lf - ls));
        if (lf > most_fd) {
            most_fd = lf;
            k_fd = k;
        }
        if (ls > most_sim) {
            most_sim = ls;
            k_sim = k;
        }
    }
    printf("worst difference %.2f of the two-way delay; largest move at y = %.2f m (FDTD), %.2f m (sim)\n",
           worst, base.antenna_y_m[k_fd], base.antenna_y_m[k_sim]);
    TEST_ASSERT_TRUE(worst < 0.2);
    TEST_ASSERT_TRUE(abs(k_fd - k_sim) <= 1);
    TEST_ASSERT_TRUE(most_sim > 0.6 && most_sim < 1.0);
    uwb_scan_free(&fd_base);
    uwb_scan_free(&fd_bulge);
    uwb_scan_free(&base);
    uwb_scan_free(&bulge);
}

/* No change written out is no change: bit for bit the same scan. */
static void test_zero_changes_give_the_same_scan(void)
{
    struct sim_scene plain, zeros;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&plain));
    plain.positions = 4;
    zeros = plain;
    set(&zeros, "radial_m", "2-4:0,6:0");
    set(&zeros, "face_tilt_m", "0");
    struct uwb_scan a, b;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&plain, 7, &a, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&zeros, 7, &b, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(a.positions, b.positions);
    TEST_ASSERT_EQUAL_INT(a.samples, b.samples);
    TEST_ASSERT_EQUAL_MEMORY(a.data, b.data, (size_t)a.positions * a.samples * sizeof *a.data);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
    char *ta, *tb;
    TEST_ASSERT_EQUAL_INT(0, sim_truth_json(&plain, &ta));
    TEST_ASSERT_EQUAL_INT(0, sim_truth_json(&zeros, &tb));
    TEST_ASSERT_EQUAL_STRING(ta, tb);
    TEST_ASSERT_NULL(strstr(ta, "radial"));
    free(ta);
    free(tb);
}

static void expect_refused(struct sim_scene *sc, const char *key, const char *value, const char *words)
{
    char err[512] = "";
    struct sim_scene before = *sc;
    int rc = sim_scene_set(sc, key, value, err, sizeof err);
    if (rc == 0)
        rc = sim_scene_validate(sc, err, sizeof err);
    printf("%s = \"%s\": %s\n", key, value, err);
    TEST_ASSERT_NOT_EQUAL_MESSAGE(0, rc, value);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, key), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, words), err);
    *sc = before;
}

static void test_bad_radial_changes_are_refused_naming_the_problem(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    expect_refused(&sc, "radial_m", "2-4", "not FROM-TO:METRES");
    expect_refused(&sc, "radial_m", "0-2:0.001", "not FROM-TO:METRES");
    expect_refused(&sc, "radial_m", "4-2:0.001", "FROM <= TO");
    expect_refused(&sc, "radial_m", "2-4:abc", "\"2-4:abc\"");
    expect_refused(&sc, "radial_m", "2-4:0.001;", "not FROM-TO:METRES");
    expect_refused(&sc, "radial_m", "2:0.001,,3:0.001", "an empty entry");
    expect_refused(&sc, "radial_m", "2-4:5", "|METRES| <= 1");
    expect_refused(&sc, "radial_m", "5-7:0.002", "fewer disks");
    expect_refused(&sc, "radial_m", "3:-0.06", "through its back face");
    expect_refused(&sc, "radial_m", "3:0.02", "reaches the barrier");
    expect_refused(&sc, "face_tilt_m", "-0.07", "disk 6's front");
    set(&sc, "radial_m", " 2-4:0.001 ");
    char err[256];
    expect_refused(&sc, "radial_m", "2 - 4", "not FROM-TO");
    set(&sc, "radial_m", "1:0.001, 2-3:-0.002");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_validate(&sc, err, sizeof err), err);
}

static void test_set_radial_keeps_the_other_disks(void)
{
    struct sim_scene sc;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set_radial(&sc, 2, 4, 0.006, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("2-4:0.006", sc.radial_m);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set_radial(&sc, 3, 3, 0, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("2:0.006,4:0.006", sc.radial_m);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set_radial(&sc, 5, 6, -0.0025, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("2:0.006,4:0.006,5-6:-0.0025", sc.radial_m);
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set_radial(&sc, 5, 7, 0.001, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "1..6"), err);
    TEST_ASSERT_EQUAL_INT(-1, sim_scene_set_radial(&sc, 3, 2, 0.001, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("2:0.006,4:0.006,5-6:-0.0025", sc.radial_m);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set_radial(&sc, 1, 6, 0, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("", sc.radial_m);
}

/* The truth names the change as the shared full-wave truth files do. */
static void test_truth_gives_the_changed_disks_and_heights(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    sc.displacement_m = 0.010;
    set(&sc, "radial_m", "4-5:0.006");
    char *json;
    TEST_ASSERT_EQUAL_INT(0, sim_truth_json(&sc, &json));
    cJSON *o = cJSON_Parse(json);
    free(json);
    TEST_ASSERT_NOT_NULL(o);
    cJSON *runs = cJSON_GetObjectItem(o, "radial");
    TEST_ASSERT_EQUAL_INT(1, cJSON_GetArraySize(runs));
    cJSON *run = cJSON_GetArrayItem(runs, 0);
    cJSON *disks = cJSON_GetObjectItem(run, "disks");
    TEST_ASSERT_EQUAL_INT(4, cJSON_GetArrayItem(disks, 0)->valueint);
    TEST_ASSERT_EQUAL_INT(5, cJSON_GetArrayItem(disks, 1)->valueint);
    /* disk 4's lower edge: 230 + 3 x 26 + 10 mm; disk 5's upper edge: 230 + 4 x 26 + 22 + 10 */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.318, cJSON_GetObjectItem(run, "y_from_m")->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.366, cJSON_GetObjectItem(run, "y_to_m")->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 6.0, cJSON_GetObjectItem(run, "change_mm")->valuedouble);
    cJSON *fronts = cJSON_GetObjectItem(o, "disk_front_mm");
    TEST_ASSERT_EQUAL_INT(6, cJSON_GetArraySize(fronts));
    double expect[6] = {0, 0, 0, 6, 6, 0};
    for (int i = 0; i < 6; i++)
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, expect[i], cJSON_GetArrayItem(fronts, i)->valuedouble);
    TEST_ASSERT_NULL(cJSON_GetObjectItem(o, "face_tilt_mm"));
    cJSON_Delete(o);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_disk_bulged_is_the_face_nearer_2d);
    RUN_TEST(test_every_disk_bulged_is_the_face_nearer_3d);
    RUN_TEST(test_partial_bulge_moves_the_echo_facing_it);
    RUN_TEST(test_partial_dent_delays_the_echo_facing_it);
    RUN_TEST(test_front_elements_sit_at_each_disks_front);
    RUN_TEST(test_face_tilt_is_linear_from_bottom_to_top);
    RUN_TEST(test_face_tilt_moves_the_top_echo_not_the_bottom);
    RUN_TEST(test_a_bulge_moves_the_echo_as_the_full_wave_solver_does);
    RUN_TEST(test_zero_changes_give_the_same_scan);
    RUN_TEST(test_bad_radial_changes_are_refused_naming_the_problem);
    RUN_TEST(test_set_radial_keeps_the_other_disks);
    RUN_TEST(test_truth_gives_the_changed_disks_and_heights);
    return UNITY_END();
}
