/* The imaging core on the simulator's scans: the 2-D mode finds the same
 * edges as on the full-wave FDTD scans, per-trace trigger jitter and gain
 * drift are undone, and displacement in 3-D with tank clutter and noise is
 * within 0.5 mm across -40...+40 mm. Under qemu-user (UWB_EXEC_PREFIX set)
 * the 3-D sweep runs a subset: FFTW is two orders of magnitude slower there. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "scene_support.h"
#include "unity.h"
#include "uwb/evaluate.h"
#include "uwbsim/uwbsim.h"

#define FDTD_SCENE "tools/uwbsim/scenes/fdtd2d-paper.json"

void setUp(void)
{
}
void tearDown(void)
{
}

static int emulated(void)
{
    const char *p = getenv("UWB_EXEC_PREFIX");
    return p && *p;
}

static void simulate(const struct sim_scene *sc, double displacement_m, uint64_t seed, struct uwb_scan *scan)
{
    char err[256];
    struct sim_scene s = *sc;
    s.displacement_m = displacement_m;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&s, seed, scan, err, sizeof err), err);
}

static void analyse(const struct uwb_scan *scan, const struct uwb_analysis_options *opt,
                    struct uwb_edges *edges)
{
    char err[256];
    struct uwb_analysis a;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_analyse_scan(scan, opt, &a, err, sizeof err), err);
    *edges = a.edges;
    uwb_analysis_free(&a);
    TEST_ASSERT_TRUE_MESSAGE(edges->found, edges->reason);
}

static void verdict(const struct uwb_scan *cur, const struct uwb_scan *base,
                    const struct uwb_evaluate_options *opt, struct uwb_verdict *v)
{
    char err[256];
    struct uwb_analysis ca, ba;
    struct uwb_baseline_record rec = {.scan = base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(cur, base ? &rec : NULL, opt, v, &ca, &ba, err, sizeof err),
                                  err);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
}

/* Same scene, two solvers: the edges the core finds must agree. */
static void sim_edges_match_fdtd(const char *fixture)
{
    char err[256];
    struct uwb_scan fdtd, sim;
    fixture_load_scan(fixture, &fdtd);
    struct fixture_truth truth;
    fixture_load_truth(fixture, &truth);
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_load_json(FDTD_SCENE, &sc, err, sizeof err), err);
    simulate(&sc, truth.displacement_mm / 1000.0, 1, &sim);

    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_edges ef, es;
    analyse(&fdtd, &opt, &ef);
    analyse(&sim, &opt, &es);
    printf("%s: FDTD edges %.2f / %.2f mm, simulator %.2f / %.2f mm\n", fixture, ef.lower_m * 1e3,
           ef.upper_m * 1e3, es.lower_m * 1e3, es.upper_m * 1e3);
    TEST_ASSERT_DOUBLE_WITHIN(0.002, ef.lower_m, es.lower_m);
    TEST_ASSERT_DOUBLE_WITHIN(0.002, ef.upper_m, es.upper_m);
    uwb_scan_free(&fdtd);
    uwb_scan_free(&sim);
}

static void test_sim_2d_edges_match_fdtd_intact(void)
{
    sim_edges_match_fdtd(FIXTURE_INTACT);
}

static void test_sim_2d_edges_match_fdtd_up20(void)
{
    sim_edges_match_fdtd(FIXTURE_UP20);
}

/* 8 ps of trigger jitter per trace moves the centre by about a millimetre
 * unless it is measured on the direct coupling and undone. */
static void test_jitter_and_drift_are_undone(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    scene_set_or_fail(&sc, "noise", "false");
    scene_set_or_fail(&sc, "clutter", "false");
    scene_set_or_fail(&sc, "jitter_s", "8e-12");
    scene_set_or_fail(&sc, "drift_db", "0.1");
    struct uwb_scan base, cur;
    simulate(&sc, 0.0, 11, &base);
    simulate(&sc, 0.013, 12, &cur);

    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_verdict aligned, raw;
    verdict(&cur, &base, &opt, &aligned);
    opt.analysis.condition.align_coupling = 0;
    verdict(&cur, &base, &opt, &raw);
    printf("13 mm shift with 8 ps jitter: %.3f mm aligned, %.3f mm without alignment\n",
           aligned.axial_displacement_m * 1e3, raw.axial_displacement_m * 1e3);
    TEST_ASSERT_DOUBLE_WITHIN(0.0001, 0.013, aligned.axial_displacement_m);
    TEST_ASSERT_TRUE(fabs(raw.axial_displacement_m - 0.013) > 0.0003);
    uwb_scan_free(&base);
    uwb_scan_free(&cur);
}

/* Both scans of a pair are processed at one frequency, the baseline's: a
 * scan's own dominant frequency is the highest bin of its spectrum, and
 * where two bins nearly tie, a bulge or the noise can tip it to the other
 * one; compared at two frequencies, the faces' ranges differ by more than
 * the change. The demo's radial step (tank-3d.json, 64 pulses, disks 2..4
 * bulged 6 mm toward the antennas) tipped it from 1.90 to 1.71 GHz and
 * read -6.9 mm at 360 mm, a dent at the wrong disks. */
static void test_a_pair_is_processed_at_the_baselines_frequency(void)
{
    struct sim_scene sc;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, sim_scene_load_json("tools/uwbsim/scenes/tank-3d.json", &sc, err, sizeof err), err);
    scene_set_or_fail(&sc, "stack", "64");
    struct uwb_scan base, cur;
    simulate(&sc, 0.0, 1, &base);
    scene_set_or_fail(&sc, "radial_m", "2-4:0.006");
    simulate(&sc, 0.0, 11, &cur);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_verdict v;
    struct uwb_analysis ca, ba;
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, sizeof err), err);
    printf("disks 2..4 bulged 6 mm: processed at %.3f / %.3f GHz, radial %+.2f mm at %.0f mm\n",
           ca.dominant_hz / 1e9, ba.dominant_hz / 1e9, v.radial.max_change_m * 1e3, v.radial.at_m * 1e3);
    TEST_ASSERT_EQUAL_DOUBLE(ba.dominant_hz, ca.dominant_hz);
    TEST_ASSERT_TRUE_MESSAGE(v.radial.measured, v.radial.withheld);
    TEST_ASSERT_TRUE_MESSAGE(v.radial.max_change_m > 0.003,
                             "a bulge toward the antennas read as none or a dent");
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&base);
    uwb_scan_free(&cur);
}

/* The scene: 3-D, eps_r 2.2, core leg, barrier, far wall, 20 dB
 * per pulse and the appliance's 64 pulses per position. A single pulse at
 * 20 dB cannot give 0.5 mm: the Cramer-Rao bound of the displacement is
 * 0.7-0.9 mm there (README, Accuracy). The clamping plate has its own test
 * below: flush with the face it costs up to half a millimetre. */
static void tank_scene(struct sim_scene *sc)
{
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(sc));
    scene_set_or_fail(sc, "snr_db", "20");
    scene_set_or_fail(sc, "stack", "64");
    scene_set_or_fail(sc, "clamp", "false");
}

static void check_shifts(const struct sim_scene *sc, const double *shifts_mm, int n, double tol_m,
                         int expect_side_reflector)
{
    struct uwb_scan base;
    simulate(sc, 0.0, 100, &base);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        struct uwb_scan cur;
        simulate(sc, shifts_mm[i] / 1000.0, 200 + (uint64_t)i, &cur);
        struct uwb_verdict v;
        verdict(&cur, &base, &opt, &v);
        double e = v.axial_displacement_m - shifts_mm[i] / 1000.0;
        printf("  shift %+6.1f mm: measured %+7.2f mm, error %+5.2f mm, sigma %.2f mm, %s\n", shifts_mm[i],
               v.axial_displacement_m * 1e3, e * 1e3, v.uncertainty_m * 1e3, uwb_status_name(v.status));
        TEST_ASSERT_NOT_EQUAL(UWB_STATUS_INCONCLUSIVE, v.status);
        TEST_ASSERT_EQUAL_INT(expect_side_reflector, v.current.side_reflector);
        TEST_ASSERT_EQUAL_INT(expect_side_reflector, v.baseline.side_reflector);
        /* honest uncertainty: the error lies inside 2 sigma */
        TEST_ASSERT_TRUE(fabs(e) <= 2.0 * v.uncertainty_m);
        worst = fmax(worst, fabs(e));
        if (fabs(shifts_mm[i]) < 1e-9) {
            TEST_ASSERT_EQUAL(UWB_STATUS_OK, v.status);
        }
        uwb_scan_free(&cur);
    }
    printf("  worst error %.2f mm\n", worst * 1e3);
    TEST_ASSERT_TRUE(worst <= tol_m);
    uwb_scan_free(&base);
}

static void test_3d_tank_displacement_within_half_mm(void)
{
    struct sim_scene sc;
    tank_scene(&sc);
    static const double all[] = {-40, -27, -13, -5, 0, 0, 0, 5, 13, 20, 33, 40};
    static const double few[] = {-27, 0, 13};
    if (emulated())
        check_shifts(&sc, few, 3, 0.0005, 0);
    else
        check_shifts(&sc, all, (int)(sizeof all / sizeof all[0]), 0.0005, 0);
}

/* The default clamping plate: steel, 88 mm above the winding, its front edge
 * level with the face. It images into the face's range cell as a blob half
 * as bright as the face; left in, it reads +40 mm as +44.6. Taken out as a
 * side reflector, the error stays within 1 mm (noiseless: 0.5 at most, at
 * +33 and +40, where the plate is 50 mm from the top) and inside the stated
 * uncertainty. The 0.5 mm is not met with this plate (README). */
static void test_3d_tank_with_flush_clamp_plate(void)
{
    struct sim_scene sc;
    tank_scene(&sc);
    scene_set_or_fail(&sc, "clamp", "true");
    static const double all[] = {-40, -20, 0, 13, 27, 33, 40};
    check_shifts(&sc, all, (int)(sizeof all / sizeof all[0]), 0.001, 1);
}

/* The default scene (flush plate included) without noise. */
static void noiseless_plate_scan(double shift_m, struct uwb_scan *scan)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    scene_set_or_fail(&sc, "noise", "false");
    simulate(&sc, shift_m, 1, scan);
}

/* The removal is what makes the difference, and it finds the plate's edge
 * (0.47..0.49 m) to within the model's few millimetres. */
static void test_clamp_plate_removal_is_what_corrects_it(void)
{
    struct uwb_scan base, cur;
    noiseless_plate_scan(0.0, &base);
    noiseless_plate_scan(0.04, &cur);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_verdict on, off;
    verdict(&cur, &base, &opt, &on);
    opt.analysis.remove_side_reflector = 0;
    verdict(&cur, &base, &opt, &off);
    uwb_scan_free(&base);
    uwb_scan_free(&cur);
    printf("+40 mm under a flush plate: %.2f mm with the plate taken out (at %.1f mm), %.2f mm left in\n",
           on.axial_displacement_m * 1e3, on.current.side_reflector_y_m * 1e3,
           off.axial_displacement_m * 1e3);
    TEST_ASSERT_DOUBLE_WITHIN(0.0006, 0.04, on.axial_displacement_m);
    TEST_ASSERT_TRUE(fabs(off.axial_displacement_m - 0.04) > 0.003);
    TEST_ASSERT_EQUAL_INT(1, on.current.side_reflector);
    TEST_ASSERT_DOUBLE_WITHIN(0.01, 0.48, on.current.side_reflector_y_m);
    TEST_ASSERT_EQUAL_INT(0, off.current.side_reflector);
}

/* The row's antisymmetric part reads the same for a plate above and for its
 * mirror image below with the sign flipped; the plate is looked for on the
 * side where the row beyond the winding is stronger. Without that, -40 mm
 * put it 48 mm up and +20 mm below the winding, at 166 mm. Where the plate
 * is found is a property of one scan: no baseline needed. */
static void test_clamp_plate_is_found_on_its_own_side(void)
{
    static const double shifts_m[] = {-0.04, 0.0, 0.02};
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    for (size_t i = 0; i < sizeof shifts_m / sizeof shifts_m[0]; i++) {
        struct uwb_scan scan;
        noiseless_plate_scan(shifts_m[i], &scan);
        struct uwb_edges edges;
        analyse(&scan, &opt, &edges);
        uwb_scan_free(&scan);
        printf("  shift %+5.1f mm: plate found at %.1f mm\n", shifts_m[i] * 1e3,
               edges.side_reflector_y_m * 1e3);
        TEST_ASSERT_EQUAL_INT(1, edges.side_reflector);
        TEST_ASSERT_DOUBLE_WITHIN(0.01, 0.48, edges.side_reflector_y_m);
    }
}

/* The family's shortest winding, 5 disks of 14 mm (86 mm), at 1.8 GHz:
 * at half its peak it stands 1.8 (3-D) to 1.9 (2-D) times as tall as the
 * imaging draws a point there. The face search passes points over (a
 * plate's edge); this winding is no point, and is found where it is. */
static void test_short_winding_at_a_low_frequency_is_found(void)
{
    static const char *const modes[] = {"2d", "3d"};
    for (int m = 0; m < 2; m++) {
        struct sim_scene sc;
        TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
        scene_set_or_fail(&sc, "mode", modes[m]);
        scene_set_or_fail(&sc, "disks", "5");
        scene_set_or_fail(&sc, "disk_height_m", "0.014");
        scene_set_or_fail(&sc, "gap_m", "0.004");
        scene_set_or_fail(&sc, "centre_frequency_hz", "1.8e9");
        scene_set_or_fail(&sc, "noise", "false");
        struct uwb_scan scan;
        simulate(&sc, 0.0, 1, &scan);
        struct uwb_analysis_options opt;
        uwb_analysis_defaults(&opt);
        struct uwb_edges e;
        analyse(&scan, &opt, &e);
        double centre = sim_scene_nominal_center_y_m(&sc), height = sim_scene_stack_height_m(&sc);
        printf("%s: face at %.3f m, edges %.1f..%.1f mm; true face %.3f m, %.1f..%.1f mm\n", modes[m],
               e.face_z_m, e.lower_m * 1e3, e.upper_m * 1e3, sc.face_z_m, (centre - 0.5 * height) * 1e3,
               (centre + 0.5 * height) * 1e3);
        TEST_ASSERT_DOUBLE_WITHIN(0.01, sc.face_z_m, e.face_z_m);
        TEST_ASSERT_DOUBLE_WITHIN(0.015, centre, e.center_m);
        uwb_scan_free(&scan);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_sim_2d_edges_match_fdtd_intact);
    RUN_TEST(test_sim_2d_edges_match_fdtd_up20);
    RUN_TEST(test_jitter_and_drift_are_undone);
    RUN_TEST(test_a_pair_is_processed_at_the_baselines_frequency);
    RUN_TEST(test_3d_tank_displacement_within_half_mm);
    if (!emulated()) /* test_clamp_plate_removal... covers the plate under qemu-user */
        RUN_TEST(test_3d_tank_with_flush_clamp_plate);
    RUN_TEST(test_clamp_plate_removal_is_what_corrects_it);
    RUN_TEST(test_short_winding_at_a_low_frequency_is_found);
    if (!emulated())
        RUN_TEST(test_clamp_plate_is_found_on_its_own_side);
    return UNITY_END();
}
