/* The carriage's motion maths (step timing of the ramp, the backlash
 * approach) and the rig config checks, without any hardware. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "unity.h"
#include "rig/carriage.h"
#include "uwb/rig.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static void check_profile(long steps, double max_hz, double accel)
{
    struct uwb_ramp r;
    uwb_ramp_init(&r, steps, max_hz, accel);
    double prev = 0, min_interval = 1e9;
    for (long k = 1; k <= steps; k++) {
        double t = uwb_ramp_step_time_s(&r, k);
        double dt = t - prev;
        TEST_ASSERT_TRUE_MESSAGE(dt > 0, "step times must increase");
        /* never faster than the top rate (a hair of rounding allowed) */
        TEST_ASSERT_TRUE_MESSAGE(dt >= 1.0 / max_hz * (1 - 1e-9), "a step came faster than max_rate_hz");
        if (dt < min_interval)
            min_interval = dt;
        /* symmetric: the interval before step k equals the one before step n+1-k */
        double mirror = uwb_ramp_step_time_s(&r, steps + 1 - k) - uwb_ramp_step_time_s(&r, steps - k);
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, dt, mirror);
        prev = t;
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, r.total_s, uwb_ramp_step_time_s(&r, steps));
}

static void test_long_move_accelerates_cruises_and_decelerates(void)
{
    const long steps = 20000;
    const double vmax = 4000, a = 8000;
    check_profile(steps, vmax, a);
    struct uwb_ramp r;
    uwb_ramp_init(&r, steps, vmax, a);
    /* trapezoid: T = n / vmax + vmax / a */
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, steps / vmax + vmax / a, r.total_s);
    /* from rest: the first step after sqrt(2/a) */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, sqrt(2.0 / a), uwb_ramp_step_time_s(&r, 1));
    /* in the middle it cruises at exactly max rate */
    double dt = uwb_ramp_step_time_s(&r, steps / 2 + 1) - uwb_ramp_step_time_s(&r, steps / 2);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 1.0 / vmax, dt);
    /* the rate rises during acceleration: intervals shrink */
    double d1 = uwb_ramp_step_time_s(&r, 2) - uwb_ramp_step_time_s(&r, 1);
    double d2 = uwb_ramp_step_time_s(&r, 100) - uwb_ramp_step_time_s(&r, 99);
    TEST_ASSERT_TRUE(d2 < d1);
    /* the accelerating phase covers vmax^2 / 2a steps */
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, vmax * vmax / (2 * a), r.accel_steps);
}

static void test_short_move_is_a_triangle_below_max_rate(void)
{
    const long steps = 200;
    const double vmax = 4000, a = 8000; /* needs 1000 steps to reach vmax */
    check_profile(steps, vmax, a);
    struct uwb_ramp r;
    uwb_ramp_init(&r, steps, vmax, a);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 2 * sqrt(steps / a), r.total_s);
    /* the fastest interval is at the peak rate sqrt(a n) < vmax */
    double peak = sqrt(a * steps);
    TEST_ASSERT_TRUE(peak < vmax);
    double dt = uwb_ramp_step_time_s(&r, steps / 2 + 1) - uwb_ramp_step_time_s(&r, steps / 2);
    TEST_ASSERT_TRUE(dt > 1.0 / vmax);
    TEST_ASSERT_DOUBLE_WITHIN(0.02 / peak, 1.0 / peak, dt);
}

static void test_single_step_move(void)
{
    check_profile(1, 4000, 8000);
    check_profile(2, 4000, 8000);
}

/* Every position is reached by a final upward segment of at least the
 * backlash, whatever the starting point. */
static void test_every_target_is_approached_from_below(void)
{
    const long backlashes[] = {0, 1, 50, 300};
    for (size_t b = 0; b < sizeof backlashes / sizeof backlashes[0]; b++) {
        long backlash = backlashes[b];
        long overshoot = backlash > 1 ? backlash : 1;
        for (long from = 0; from <= 2000; from += 37) {
            for (long to = 400; to <= 1600; to += 53) {
                long w[2];
                int n = uwb_carriage_plan(from, to, backlash, w);
                TEST_ASSERT_TRUE(n == 1 || n == 2);
                TEST_ASSERT_EQUAL_INT32(to, w[n - 1]);
                long last_start = n == 2 ? w[0] : from;
                TEST_ASSERT_TRUE_MESSAGE(to - last_start >= overshoot,
                                         "final segment not upward by the backlash");
                if (n == 2) /* the overshoot goes no further than needed */
                    TEST_ASSERT_EQUAL_INT32(to - overshoot, w[0]);
                else /* no detour when the plain move already comes from below */
                    TEST_ASSERT_TRUE(to - from >= overshoot);
            }
        }
    }
}

static void test_mm_to_steps_rounds_to_the_nearest_microstep(void)
{
    struct uwb_carriage_config c = {.steps_per_mm = 100};
    TEST_ASSERT_EQUAL_INT32(3000, uwb_carriage_mm_to_steps(&c, 30.0));
    TEST_ASSERT_EQUAL_INT32(2, uwb_carriage_mm_to_steps(&c, 0.016));
    TEST_ASSERT_EQUAL_INT32(-50, uwb_carriage_mm_to_steps(&c, -0.5));
    c.steps_per_mm = 80;
    TEST_ASSERT_EQUAL_INT32(2400, uwb_carriage_mm_to_steps(&c, 30.0));
}

static void emulated_config(struct uwb_rig_config *cfg)
{
    uwb_rig_config_defaults(cfg);
    snprintf(cfg->gpio.backend, sizeof cfg->gpio.backend, "emulated");
    snprintf(cfg->gpio.endpoint, sizeof cfg->gpio.endpoint, "unix:/run/uwbemu/gpio.sock");
    snprintf(cfg->digitiser.endpoint, sizeof cfg->digitiser.endpoint, "unix:/run/uwbemu/digitiser.sock");
}

static void assert_config_error(const struct uwb_rig_config *cfg, const char *field)
{
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_ERR_CONFIG, uwb_rig_config_check(cfg, err, sizeof err), field);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, field), err);
}

static void test_defaults_pass_and_bad_fields_are_named(void)
{
    struct uwb_rig_config cfg;
    char err[512];
    emulated_config(&cfg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg, err, sizeof err), err);

    emulated_config(&cfg);
    cfg.carriage.steps_per_mm = 0;
    assert_config_error(&cfg, "carriage.steps_per_mm");
    emulated_config(&cfg);
    cfg.carriage.home_rate_hz = cfg.carriage.max_rate_hz * 2;
    assert_config_error(&cfg, "carriage.home_rate_hz");
    emulated_config(&cfg);
    cfg.carriage.park_mm = cfg.carriage.travel_mm + 1;
    assert_config_error(&cfg, "carriage.park_mm");
    emulated_config(&cfg);
    cfg.digitiser.stack = 0;
    assert_config_error(&cfg, "digitiser.stack");
    emulated_config(&cfg);
    snprintf(cfg.digitiser.endpoint, sizeof cfg.digitiser.endpoint, "usb:0");
    assert_config_error(&cfg, "digitiser.endpoint");
    emulated_config(&cfg);
    cfg.time_scale = -1;
    assert_config_error(&cfg, "time_scale");
}

/* Positions must fit between the backlash overshoot above home and the
 * end of the travel. */
static void test_positions_outside_the_travel_are_refused(void)
{
    struct uwb_rig_config cfg;
    emulated_config(&cfg);
    cfg.positions = 30; /* 0 .. 870 mm, past the 650 mm travel */
    assert_config_error(&cfg, "travel_mm");
    emulated_config(&cfg);
    cfg.first_position_mm = cfg.carriage.home_offset_mm + cfg.carriage.backlash_mm / 2;
    assert_config_error(&cfg, "backlash");
    emulated_config(&cfg);
    cfg.first_position_mm = cfg.carriage.home_offset_mm + cfg.carriage.backlash_mm;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg, err, sizeof err), err);
}

/* The rules between fields are checked in one place, the rig, for the
 * loader and for a program driving the rig alike: a scan no reader takes
 * (over the 64 MiB of samples a scan file may hold) is refused here too. */
static void test_the_rig_refuses_a_scan_no_reader_takes(void)
{
    struct uwb_rig_config cfg;
    emulated_config(&cfg);
    cfg.step_mm = 1;
    cfg.positions = 300;
    cfg.digitiser.samples = 65536;
    assert_config_error(&cfg,
                        "key `digitiser.samples`: 65536 samples x 300 positions = 19660800 samples per scan");
    cfg.positions = 256; /* the limit itself */
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg, err, sizeof err), err);
}

static void test_libgpiod_lines_need_distinct_offsets(void)
{
    struct uwb_rig_config cfg;
    emulated_config(&cfg);
    snprintf(cfg.gpio.backend, sizeof cfg.gpio.backend, "libgpiod");
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg, err, sizeof err), err);
    cfg.gpio.offset[UWB_LINE_DIR] = cfg.gpio.offset[UWB_LINE_STEP];
    assert_config_error(&cfg, "offset");
    cfg.gpio.offset[UWB_LINE_DIR] = -1;
    assert_config_error(&cfg, "dir line");
    snprintf(cfg.gpio.name[UWB_LINE_DIR], sizeof cfg.gpio.name[0], "GPIO22");
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg, err, sizeof err), err);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_long_move_accelerates_cruises_and_decelerates);
    RUN_TEST(test_short_move_is_a_triangle_below_max_rate);
    RUN_TEST(test_single_step_move);
    RUN_TEST(test_every_target_is_approached_from_below);
    RUN_TEST(test_mm_to_steps_rounds_to_the_nearest_microstep);
    RUN_TEST(test_defaults_pass_and_bad_fields_are_named);
    RUN_TEST(test_positions_outside_the_travel_are_refused);
    RUN_TEST(test_the_rig_refuses_a_scan_no_reader_takes);
    RUN_TEST(test_libgpiod_lines_need_distinct_offsets);
    return UNITY_END();
}
