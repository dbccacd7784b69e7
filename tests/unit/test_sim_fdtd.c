/* The simulator's 2-D mode against full-wave 2-D FDTD (gprMax) scans of the
 * paper's geometry: a solver that shares nothing with ours. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwbsim/uwbsim.h"

#define SCENE "tools/uwbsim/scenes/fdtd2d-paper.json"

void setUp(void)
{
}
void tearDown(void)
{
}

/* Simulate the fixture's scene (its displacement from its truth file) and
 * compare position by position. */
static void compare_with_fixture(const char *stem)
{
    char path[256], err[512];
    snprintf(path, sizeof path, "tests/fixtures/%s.uwbscan", stem);
    struct uwb_scan fd, sim;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(path, &fd, err, sizeof err), err);

    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_load_json(SCENE, &sc, err, sizeof err), err);
    struct fixture_truth truth;
    fixture_load_truth(path, &truth);
    sc.displacement_m = truth.displacement_mm / 1000.0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 1, &sim, err, sizeof err), err);

    /* the scene file reproduces the fixture's acquisition exactly */
    TEST_ASSERT_EQUAL_INT(fd.positions, sim.positions);
    TEST_ASSERT_EQUAL_INT(fd.samples, sim.samples);
    TEST_ASSERT_EQUAL_DOUBLE(fd.sample_interval_s, sim.sample_interval_s);
    TEST_ASSERT_EQUAL_DOUBLE(fd.t0_s, sim.t0_s);
    for (int k = 0; k < fd.positions; k++)
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, fd.antenna_y_m[k], sim.antenna_y_m[k]);

    int S = fd.samples;
    double dt = fd.sample_interval_s;
    double period = 1.0 / sc.centre_frequency_hz;
    /* the face and corner echoes arrive near 2 * 0.45 m / c = 3.0 ns: look
     * from 2.5 ns (after the direct coupling) to 4.6 ns */
    int i0 = (int)((2.5e-9 - fd.t0_s) / dt), i1 = (int)((4.6e-9 - fd.t0_s) / dt);
    printf("%s: position, y, arrival FDTD (ns), sim - FDTD (ps), shape correlation, amplitude ratio\n", stem);
    double worst = 0;
    for (int k = 0; k < fd.positions; k++) {
        const float *a = fd.data + (size_t)k * S, *b = sim.data + (size_t)k * S;
        double ta = sim_envelope_peak(a, S, i0, i1), tb = sim_envelope_peak(b, S, i0, i1);
        TEST_ASSERT_TRUE(ta > 0 && tb > 0);
        double diff = (tb - ta) * dt;
        double corr = sim_correlation(a, b, i0, i1);
        double pa = 0, pb = 0;
        for (int i = i0; i < i1; i++) {
            pa = fmax(pa, fabs(a[i]));
            pb = fmax(pb, fabs(b[i]));
        }
        printf("  %2d %.2f %.4f %+6.1f %.4f %.3f\n", k, fd.antenna_y_m[k], fd.t0_s * 1e9 + ta * dt * 1e9,
               diff * 1e12, corr, pb / pa);
        worst = fmax(worst, fabs(diff));
        /* Done-when: every position within a tenth of the pulse's period */
        TEST_ASSERT_TRUE_MESSAGE(fabs(diff) < period / 10,
                                 "face echo arrival differs from FDTD by more than T/10");
        /* and the waveform itself, edges and all, looks like the full-wave one */
        TEST_ASSERT_TRUE_MESSAGE(corr > 0.98, "echo waveform differs from FDTD");
        TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.10, 1.0, pb / pa,
                                          "echo amplitude differs from FDTD by over 10 %");
    }
    printf("  worst |arrival difference| %.1f ps (limit %.0f ps)\n", worst * 1e12, period / 10 * 1e12);

    /* the direct coupling (exact 2-D near field) matches too: same peak within 1 % */
    int idirect = (int)((1.0e-9 - fd.t0_s) / dt);
    double da = 0, db = 0;
    for (int i = 0; i < idirect; i++) {
        da = fmax(da, fabs(fd.data[i]));
        db = fmax(db, fabs(sim.data[i]));
    }
    TEST_ASSERT_DOUBLE_WITHIN(0.01, 1.0, db / da);
    uwb_scan_free(&fd);
    uwb_scan_free(&sim);
}

static void test_intact_winding_matches_fdtd(void)
{
    compare_with_fixture("fdtd2d-paper-intact");
}

static void test_displaced_winding_matches_fdtd(void)
{
    compare_with_fixture("fdtd2d-paper-up20mm");
}

/* Without the fringe term, plain physical optics under-states the corner
 * diffraction the FDTD shows: the test above would catch a model that lost it. */
static void test_physical_optics_alone_is_weaker_at_the_corners(void)
{
    char err[512];
    struct uwb_scan fd, sim;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbscan_read_file("tests/fixtures/fdtd2d-paper-intact.uwbscan", &fd, err, sizeof err), err);
    struct sim_scene sc;
    sim_scene_default(&sc);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_load_json(SCENE, &sc, err, sizeof err), err);
    sc.edge_diffraction = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 1, &sim, err, sizeof err), err);
    int S = fd.samples;
    int i0 = (int)((2.5e-9 - fd.t0_s) / fd.sample_interval_s),
        i1 = (int)((4.6e-9 - fd.t0_s) / fd.sample_interval_s);
    double pa = 0, pb = 0; /* position 0 (y = 0) sees only the corners */
    for (int i = i0; i < i1; i++) {
        pa = fmax(pa, fabs(fd.data[i]));
        pb = fmax(pb, fabs(sim.data[i]));
    }
    TEST_ASSERT_TRUE_MESSAGE(pb / pa < 0.8, "physical optics alone should under-state corner diffraction");
    (void)S;
    uwb_scan_free(&fd);
    uwb_scan_free(&sim);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_intact_winding_matches_fdtd);
    RUN_TEST(test_displaced_winding_matches_fdtd);
    RUN_TEST(test_physical_optics_alone_is_weaker_at_the_corners);
    return UNITY_END();
}
