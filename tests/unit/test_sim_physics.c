/* The simulator's physics against geometry and closed-form results. */
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

/* Winding only, nothing random, no window: geometry in its plainest form. */
static void bare_scene(struct sim_scene *sc)
{
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(sc));
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

static struct sim_engine *engine_for(const struct sim_scene *sc)
{
    struct sim_engine *e;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(sc, &e, err, sizeof err), err);
    return e;
}

static void to_float(const double *d, float *f, int n)
{
    for (int i = 0; i < n; i++)
        f[i] = (float)d[i];
}

/* The noise-free trace of some parts of the scene at antenna height y, in
 * float for the measuring helpers. Caller frees. */
static float *clean_float_trace(struct sim_engine *e, double y, unsigned parts, int n)
{
    double *tr = malloc((size_t)n * sizeof *tr);
    float *f = malloc((size_t)n * sizeof *f);
    TEST_ASSERT_NOT_NULL(tr);
    TEST_ASSERT_NOT_NULL(f);
    sim_engine_clean_trace(e, y, parts, 0.0, tr);
    to_float(tr, f, n);
    free(tr);
    return f;
}

/* A 2 m x 2 m metal plate at z = 0.5 m (the "core" of a scene whose
 * winding is moved far above the record), seen by isotropic antennas. */
static void plate_scene(struct sim_scene *sc, int mode2d)
{
    bare_scene(sc);
    sc->mode = mode2d ? SIM_MODE_2D : SIM_MODE_3D;
    sc->beamwidth_deg = 0;
    sc->edge_diffraction = 0;
    sc->bottom_y_m = 10;
    sc->face_z_m = 0.5;
    sc->clutter = 1;
    sc->barrier = sc->clamp = sc->far_wall = 0;
    sc->core_front_m = sc->outer_radius_m;
    sc->core_width_m = 2.0;
    sc->core_y_min_m = -1.0;
    sc->core_y_max_m = 1.0;
    sc->positions = 1;
}

/* A large flat metal plate must return exactly its image source:
 * -f(t - L/v)/L in 3-D, -f(t - L/v)/sqrt(L) in 2-D, L the Tx-image-Rx path.
 * This pins the PO constants, the obliquity and the propagation operator
 * (and, in 3-D, the Kirchhoff kernel's near-field 1/R term). */
static void check_plate(int mode2d, double tolerance)
{
    struct sim_scene sc;
    plate_scene(&sc, mode2d);
    struct sim_engine *e = engine_for(&sc);
    int S = sc.samples;
    double *tr = malloc((size_t)S * sizeof *tr);
    sim_engine_clean_trace(e, 0.0, SIM_PART_CLUTTER, 0.0, tr);

    double v = C0 / sqrt(sc.eps_r), dy = sc.rx_dy_m - sc.tx_dy_m;
    double L = sqrt(4 * 0.5 * 0.5 + dy * dy);
    double spread = mode2d ? sqrt(L) : L;
    double max_err = 0, peak = 0;
    for (int i = 0; i < S; i++) {
        double t = sc.t0_s + i * sc.sample_interval_s;
        double x = M_PI * sc.centre_frequency_hz * (t - L / v);
        if (fabs(t - L / v) > 1e-9)
            continue; /* the plate's own edges come much later */
        double expect = -sc.pulse_amplitude * (1 - 2 * x * x) * exp(-x * x) / spread;
        max_err = fmax(max_err, fabs(tr[i] - expect));
        peak = fmax(peak, fabs(expect));
    }
    printf("%s plate: image peak %.4f V, worst deviation %.3f %% of it\n", mode2d ? "2-D" : "3-D", peak,
           100 * max_err / peak);
    TEST_ASSERT_TRUE_MESSAGE(max_err < tolerance * peak, "a flat plate does not return its image");
    free(tr);
    sim_engine_free(e);
}

static void test_flat_plate_returns_its_image_3d(void)
{
    check_plate(0, 0.002); /* exact up to discretisation */
}

static void test_flat_plate_returns_its_image_2d(void)
{
    check_plate(1, 0.015); /* far-field Hankel forms: O(1/(8 k R)) */
}

/* A tall stack seen square-on: the face echo's envelope peaks at the
 * bistatic delay (|P-Tx| + |P-Rx|)/v of the face point P level with the pair. */
static void test_boresight_face_delay(void)
{
    struct sim_scene sc;
    bare_scene(&sc);
    sc.disks = 20;
    sc.bottom_y_m = 0.0;
    sc.positions = 1;
    struct sim_engine *e = engine_for(&sc);
    int S = sc.samples;
    float *f = clean_float_trace(e, sim_scene_nominal_center_y_m(&sc), SIM_PART_WINDING, S);
    double v = C0 / sqrt(sc.eps_r);
    double expect = (hypot(sc.face_z_m, sc.tx_dy_m) + hypot(sc.face_z_m, sc.rx_dy_m)) / v;
    int ie = (int)((expect - sc.t0_s) / sc.sample_interval_s);
    double got = sc.t0_s + sim_envelope_peak(f, S, ie - 60, ie + 60) * sc.sample_interval_s;
    printf("boresight: expected %.2f ps, envelope peak %.2f ps (sample %.0f ps)\n", expect * 1e12, got * 1e12,
           sc.sample_interval_s * 1e12);
    TEST_ASSERT_DOUBLE_WITHIN(sc.sample_interval_s, expect, got);
    free(f);
    sim_engine_free(e);
}

/* Seen from below (y = 0), the first echo is the bottom corner's
 * diffraction; lifting the winding by d must delay it by exactly what the
 * path to the moved corner says. */
static void test_displacement_moves_corner_diffraction(void)
{
    double d = 0.010;
    struct sim_scene a, b;
    bare_scene(&a);
    a.positions = 1;
    b = a;
    b.displacement_m = d;
    struct sim_engine *ea = engine_for(&a), *eb = engine_for(&b);
    int S = a.samples;
    float *fa = clean_float_trace(ea, 0.0, SIM_PART_WINDING, S);
    float *fb = clean_float_trace(eb, 0.0, SIM_PART_WINDING, S);
    double v = C0 / sqrt(a.eps_r);
    double y1 = a.bottom_y_m, z = a.face_z_m;
    double path0 = hypot(y1 - a.tx_dy_m, z) + hypot(y1 - a.rx_dy_m, z);
    double path1 = hypot(y1 + d - a.tx_dy_m, z) + hypot(y1 + d - a.rx_dy_m, z);
    double predicted = (path1 - path0) / v;
    int ic = (int)((path0 / v - a.t0_s) / a.sample_interval_s);
    int half = (int)(0.35e-9 / a.sample_interval_s); /* the top corner arrives 0.8 ns later */
    double lag = sim_xcorr_lag(fa, fb, S, ic - half, ic + half, 20) * a.sample_interval_s;
    printf("corner: predicted delay %.2f ps, measured %.2f ps\n", predicted * 1e12, lag * 1e12);
    TEST_ASSERT_TRUE(predicted > 30e-12); /* a real, measurable shift */
    TEST_ASSERT_DOUBLE_WITHIN(0.05 * predicted, predicted, lag);
    free(fa);
    free(fb);
    sim_engine_free(ea);
    sim_engine_free(eb);
}

/* The tank window delays each leg by t (n_w - n_oil)/c at normal incidence,
 * costs 1 - r^2 in amplitude over the round trip, and makes the source look
 * nearer by t (1 - n_oil/n_w) per leg (the plate's image grows accordingly). */
static void test_window_delay_and_transmission(void)
{
    struct sim_scene a, b;
    plate_scene(&a, 0);
    b = a;
    double t = 0.03, nw = 2.0, no = sqrt(a.eps_r);
    b.window_thickness_m = t;
    b.window_eps_r = nw * nw;
    struct sim_engine *ea = engine_for(&a), *eb = engine_for(&b);
    int S = a.samples;
    float *fa = clean_float_trace(ea, 0.0, SIM_PART_CLUTTER, S);
    float *fb = clean_float_trace(eb, 0.0, SIM_PART_CLUTTER, S);
    double predicted = 2 * t * (nw - no) / C0;
    double v = C0 / no, L = 2 * 0.5;
    int ie = (int)((L / v - a.t0_s) / a.sample_interval_s);
    double lag = sim_xcorr_lag(fa, fb, S, ie - 80, ie + 80, 30) * a.sample_interval_s;
    float pa = 0, pb = 0;
    for (int i = ie - 80; i < ie + 120; i++) {
        pa = fmaxf(pa, fabsf(fa[i]));
        pb = fmaxf(pb, fabsf(fb[i]));
    }
    double r = (nw - no) / (nw + no);
    double expect = (1 - r * r) * L / (L - 2 * t * (1 - no / nw));
    printf("window: predicted delay %.2f ps, measured %.2f ps; amplitude ratio %.4f, predicted %.4f\n",
           predicted * 1e12, lag * 1e12, pb / pa, expect);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, predicted, lag);
    TEST_ASSERT_DOUBLE_WITHIN(0.003, expect, pb / pa);
    free(fa);
    free(fb);
    sim_engine_free(ea);
    sim_engine_free(eb);
}

/* Discretisation: halving the surface elements must not change the scan. */
static void test_element_size_converged(void)
{
    struct sim_scene a, b;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&a));
    a.noise = 0;
    a.jitter_s = 0;
    a.drift_db = 0;
    a.adc_bits = 0;
    a.coupling_gain = 0;
    a.window_echo = 0;
    b = a;
    b.element_size_m = sim_geometry_element_size(&a) / 2;
    struct sim_engine *ea = engine_for(&a), *eb = engine_for(&b);
    TEST_ASSERT_TRUE(sim_engine_element_count(eb) > 3 * sim_engine_element_count(ea));
    int S = a.samples;
    double *ta = malloc((size_t)S * sizeof *ta), *tb = malloc((size_t)S * sizeof *tb);
    double worst = 0;
    for (int k = 0; k < a.positions; k++) {
        double y = sim_scene_antenna_y_m(&a, k), num = 0, den = 0;
        sim_engine_clean_trace(ea, y, SIM_PART_ALL, 0.0, ta);
        sim_engine_clean_trace(eb, y, SIM_PART_ALL, 0.0, tb);
        for (int i = 0; i < S; i++) {
            num += (ta[i] - tb[i]) * (ta[i] - tb[i]);
            den += tb[i] * tb[i];
        }
        worst = fmax(worst, sqrt(num / den));
    }
    printf("convergence: %zu vs %zu elements, worst rms difference %.3f %%\n", sim_engine_element_count(ea),
           sim_engine_element_count(eb), 100 * worst);
    TEST_ASSERT_TRUE_MESSAGE(worst < 0.01, "scan changes by over 1 % when the elements are halved");
    free(ta);
    free(tb);
    sim_engine_free(ea);
    sim_engine_free(eb);
}

static double peak_between(const double *tr, const struct sim_scene *sc, double t0, double t1)
{
    double p = 0;
    for (int i = 0; i < sc->samples; i++) {
        double t = sc->t0_s + i * sc->sample_interval_s;
        if (t >= t0 && t <= t1)
            p = fmax(p, fabs(tr[i]));
    }
    return p;
}

/* The core leg runs behind the winding: level with the winding the winding
 * hides it; above and below it returns more than the winding itself. */
static void test_winding_hides_the_core(void)
{
    struct sim_scene sc;
    bare_scene(&sc);
    sc.clutter = 1;
    sc.barrier = sc.clamp = sc.far_wall = 0;
    struct sim_engine *e = engine_for(&sc);
    int S = sc.samples;
    double *tr = malloc((size_t)S * sizeof *tr);
    double v = C0 / sqrt(sc.eps_r);
    double zc = sc.face_z_m + sc.outer_radius_m - sc.core_front_m;
    double tc = 2 * zc / v;
    sim_engine_clean_trace(e, 0.0, SIM_PART_CLUTTER, 0.0, tr);
    double below = peak_between(tr, &sc, tc - 0.3e-9, tc + 0.5e-9);
    sim_engine_clean_trace(e, sim_scene_nominal_center_y_m(&sc), SIM_PART_CLUTTER, 0.0, tr);
    double level = peak_between(tr, &sc, tc - 0.3e-9, tc + 0.5e-9);
    double winding = sim_engine_peak_echo(e);
    printf("core: %.4f V below the winding, %.4f V level with it; winding peak %.4f V\n", below, level,
           winding);
    TEST_ASSERT_TRUE_MESSAGE(level < 0.5 * below, "the winding does not hide the core behind it");
    TEST_ASSERT_TRUE_MESSAGE(below > winding, "the core leg should out-shine the winding");
    free(tr);
    sim_engine_free(e);
}

/* E across the gaps (perpendicular) leaves them open: the face loses the gaps'
 * share of its area and the stack's echo changes; E along them closes them. */
static void test_polarisation_opens_the_gaps(void)
{
    struct sim_scene a, b;
    bare_scene(&a);
    a.disks = 20;
    a.bottom_y_m = 0.0;
    a.positions = 1;
    b = a;
    b.polarisation = SIM_POL_PERPENDICULAR;
    struct sim_engine *ea = engine_for(&a), *eb = engine_for(&b);
    int S = a.samples;
    double *ta = malloc((size_t)S * sizeof *ta), *tb = malloc((size_t)S * sizeof *tb);
    double y = sim_scene_nominal_center_y_m(&a);
    sim_engine_clean_trace(ea, y, SIM_PART_WINDING, 0.0, ta);
    sim_engine_clean_trace(eb, y, SIM_PART_WINDING, 0.0, tb);
    double v = C0 / sqrt(a.eps_r), t = 2 * a.face_z_m / v;
    double pa = peak_between(ta, &a, t - 0.5e-9, t + 0.5e-9),
           pb = peak_between(tb, &a, t - 0.5e-9, t + 0.5e-9);
    double fill = a.disk_height_m / (a.disk_height_m + a.gap_m);
    printf("polarisation: open/closed face echo %.3f (metal fill factor %.3f)\n", pb / pa, fill);
    TEST_ASSERT_TRUE(pb / pa < 0.97);
    TEST_ASSERT_TRUE(pb / pa > fill - 0.1);
    free(ta);
    free(tb);
    sim_engine_free(ea);
    sim_engine_free(eb);
}

/* The fringe term stays finite where physical optics and the exact wedge
 * solution both blow up (reflection boundaries): stepping the antennas 5 mm
 * at a time past the corners, the winding's echo changes smoothly in both
 * polarisations, and turning the antennas never makes the stack brighter. */
static void test_edges_smooth_across_reflection_boundaries(void)
{
    double peak_of[2] = {0, 0};
    for (int pol = 0; pol < 2; pol++) {
        struct sim_scene sc;
        bare_scene(&sc);
        sc.polarisation = pol;
        sc.positions = 121;
        sc.position_step_m = 0.005;
        struct sim_engine *e = engine_for(&sc);
        double *tr = malloc((size_t)sc.samples * sizeof *tr), prev = 0, lo = 1e9, hi = 0;
        for (int k = 0; k < sc.positions; k++) {
            sim_engine_clean_trace(e, sim_scene_antenna_y_m(&sc, k), SIM_PART_WINDING, 0.0, tr);
            double p = 0;
            for (int i = 0; i < sc.samples; i++)
                p = fmax(p, fabs(tr[i]));
            if (k > 0) {
                lo = fmin(lo, p / prev);
                hi = fmax(hi, p / prev);
            }
            prev = p;
            peak_of[pol] = fmax(peak_of[pol], p);
        }
        printf("%s: peak %.4f V, neighbour ratio %.3f..%.3f\n", pol ? "perpendicular" : "parallel",
               peak_of[pol], lo, hi);
        TEST_ASSERT_TRUE(lo > 0.85 && hi < 1.18);
        free(tr);
        sim_engine_free(e);
    }
    TEST_ASSERT_TRUE(peak_of[1] < 1.2 * peak_of[0]);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_flat_plate_returns_its_image_3d);
    RUN_TEST(test_flat_plate_returns_its_image_2d);
    RUN_TEST(test_boresight_face_delay);
    RUN_TEST(test_displacement_moves_corner_diffraction);
    RUN_TEST(test_window_delay_and_transmission);
    RUN_TEST(test_element_size_converged);
    RUN_TEST(test_winding_hides_the_core);
    RUN_TEST(test_polarisation_opens_the_gaps);
    RUN_TEST(test_edges_smooth_across_reflection_boundaries);
    return UNITY_END();
}
