/* The rig against the emulated board, as separate processes: uwbemu is
 * started from the build directory (through $UWB_EXEC_PREFIX under
 * qemu-user) and every test drives full scan cycles over its sockets. The
 * board's control log says, for every trigger, where the carriage really
 * was; the traces themselves are checked against the simulator. */
#include <cjson/cJSON.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "scratch_support.h"
#include "unity.h"
#include "uwb/gpio.h"
#include "uwb/link.h"
#include "uwb/rig.h"
#include "uwbsim/uwbsim.h"

extern char **environ;

#define BOARD_STEPS_PER_MM 10.0
#define START_TIMEOUT_S 120

static char dir[64], gpio_ep[128], dig_ep[128], ctl_ep[128];
static pid_t emu_pid = -1;
static int under_emulation; /* $UWB_EXEC_PREFIX set: everything is ~100x slower */
static char err[1024];

/* ---- the uwbemu process --------------------------------------------------- */

static char *ctl_raw(const char *command)
{
    struct uwb_link *link;
    if (uwb_link_open(ctl_ep, &link, err, sizeof err) != UWB_LINK_OK)
        return NULL;
    char *reply = NULL;
    size_t cap = 1 << 16, len = 0;
    if (uwb_link_write_all(link, command, strlen(command), 5000, err, sizeof err) == UWB_LINK_OK &&
        uwb_link_write_all(link, "\n", 1, 5000, err, sizeof err) == UWB_LINK_OK && (reply = malloc(cap))) {
        for (;;) {
            if (len + 1 >= cap) {
                char *bigger = realloc(reply, cap *= 2);
                TEST_ASSERT_NOT_NULL(bigger);
                reply = bigger;
            }
            ssize_t n = uwb_link_read(link, reply + len, cap - len - 1, 60000, err, sizeof err);
            if (n < 0) {
                free(reply);
                reply = NULL;
                break;
            }
            len += (size_t)n;
            reply[len] = '\0';
            char *nl = strchr(reply, '\n');
            if (nl) {
                *nl = '\0';
                break;
            }
        }
    }
    uwb_link_close(link);
    return reply;
}

/* A control command whose reply must not be an ERROR. */
static cJSON *ctl(const char *command)
{
    char *text = ctl_raw(command);
    TEST_ASSERT_NOT_NULL_MESSAGE(text, err);
    cJSON *o = cJSON_Parse(text);
    TEST_ASSERT_NOT_NULL_MESSAGE(o, text);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsString(cls) && strcmp(cls->valuestring, "ERROR") != 0, text);
    free(text);
    return o;
}

static void ctl_ok(const char *command)
{
    cJSON_Delete(ctl(command));
}

static double status_number(const cJSON *status, const char *key)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(status, key);
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(item), key);
    return item->valuedouble;
}

static int status_line(const cJSON *status, const char *line)
{
    const cJSON *lines = cJSON_GetObjectItemCaseSensitive(status, "lines");
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(lines, line);
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(item), line);
    return item->valueint;
}

/* Outside any test, so no assertions: a problem is kept and every test
 * reports it. */
static const char *board_problem;

static void start_board(void)
{
    strcpy(dir, "/tmp/uwb-rig-XXXXXX");
    if (!mkdtemp(dir)) {
        board_problem = "cannot make a temporary directory";
        return;
    }
    snprintf(gpio_ep, sizeof gpio_ep, "unix:%s/gpio", dir);
    snprintf(dig_ep, sizeof dig_ep, "unix:%s/digitiser", dir);
    snprintf(ctl_ep, sizeof ctl_ep, "unix:%s/control", dir);
    const char *build = getenv("UWB_BUILD_DIR");
    const char *prefix = getenv("UWB_EXEC_PREFIX");
    under_emulation = prefix && *prefix;
    static char program[512], prefix_copy[256], steps[32];
    snprintf(program, sizeof program, "%s/uwbemu", build && *build ? build : UWB_BUILD_DIR);
    snprintf(prefix_copy, sizeof prefix_copy, "%s", prefix ? prefix : "");
    snprintf(steps, sizeof steps, "%g", BOARD_STEPS_PER_MM);
    char *argv[32];
    int argc = 0;
    for (char *w = strtok(prefix_copy, " "); w && argc < 8; w = strtok(NULL, " "))
        argv[argc++] = w;
    char *args[] = {program, "--gpio",         gpio_ep, "--digitiser", dig_ep, "--control",
                    ctl_ep,  "--steps-per-mm", steps,   "--seed",      "7"};
    for (size_t i = 0; i < sizeof args / sizeof args[0]; i++)
        argv[argc++] = args[i];
    argv[argc] = NULL;
    if (posix_spawnp(&emu_pid, argv[0], NULL, NULL, argv, environ) != 0) {
        emu_pid = -1;
        board_problem = "cannot start uwbemu (is it built?)";
        return;
    }
    /* Ready when the control endpoint answers. */
    for (int i = 0; i < START_TIMEOUT_S * 20; i++) {
        char *reply = ctl_raw("status");
        if (reply) {
            free(reply);
            return;
        }
        int status;
        if (waitpid(emu_pid, &status, WNOHANG) != 0) {
            emu_pid = -1;
            board_problem = "uwbemu exited at start";
            return;
        }
        struct timespec ts = {0, 50000000};
        nanosleep(&ts, NULL);
    }
    board_problem = "uwbemu did not answer on its control endpoint";
}

static void stop_board(void)
{
    if (emu_pid <= 0)
        return;
    int status = 0;
    char *reply = ctl_raw("quit");
    free(reply);
    for (int i = 0; i < 200 && waitpid(emu_pid, &status, WNOHANG) == 0; i++) {
        struct timespec ts = {0, 50000000};
        nanosleep(&ts, NULL);
        if (i == 100)
            kill(emu_pid, SIGTERM);
    }
    if (scratch_remove_tree(dir) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
}

/* Scene parameters a test changed on the board: put back to uwbsim's
 * defaults (the board's scene) before the next test, even after a failure. */
static const char *const scene_keys_changed[] = {"noise", "jitter_s", "drift_db", "clutter"};
static int scene_changed;

static void restore_scene(void)
{
    char cmd[128];
    scene_changed = 0;
    for (size_t i = 0; i < sizeof scene_keys_changed / sizeof scene_keys_changed[0]; i++) {
        snprintf(cmd, sizeof cmd, "set %s %s", scene_keys_changed[i],
                 sim_param_find(scene_keys_changed[i])->def);
        ctl_ok(cmd);
    }
    ctl_ok("set radial 1 6 0");
}

void setUp(void)
{
    static const char *const faults[] = {"crc",        "truncate",   "drop",      "silent",
                                         "disconnect", "home-never", "home-stuck"};
    char cmd[64];
    if (board_problem)
        TEST_FAIL_MESSAGE(board_problem);
    for (size_t i = 0; i < sizeof faults / sizeof faults[0]; i++) {
        snprintf(cmd, sizeof cmd, "fault %s off", faults[i]);
        ctl_ok(cmd);
    }
    ctl_ok("board invert_dir 0");
    ctl_ok("board steps_per_mm 10");
    ctl_ok("board position_mm 50");
    ctl_ok("log clear");
    if (scene_changed)
        restore_scene();
}

void tearDown(void)
{
}

/* ---- the rig under test --------------------------------------------------- */

static void rig_config(struct uwb_rig_config *cfg, int positions)
{
    uwb_rig_config_defaults(cfg);
    snprintf(cfg->gpio.backend, sizeof cfg->gpio.backend, "emulated");
    snprintf(cfg->gpio.endpoint, sizeof cfg->gpio.endpoint, "%s", gpio_ep);
    snprintf(cfg->digitiser.endpoint, sizeof cfg->digitiser.endpoint, "%s", dig_ep);
    snprintf(cfg->source, sizeof cfg->source, "test_rig_emulated");
    cfg->carriage.steps_per_mm = BOARD_STEPS_PER_MM;
    cfg->carriage.travel_mm = 640;
    cfg->positions = positions;
    /* the same aperture (0..600 mm) with fewer positions */
    cfg->step_mm = positions > 1 ? 600.0 / (positions - 1) : 30;
    cfg->digitiser.stack = under_emulation ? 1 : 2;
    cfg->digitiser.frame_timeout_ms = under_emulation ? 2000 : 400;
    cfg->digitiser.frame_retries = 4;
    /* no waiting: the step timing has its own tests (test_carriage_motion) */
    cfg->time_scale = 0;
}

static int full_positions(void)
{
    return under_emulation ? 7 : 21;
}

static struct uwb_rig *open_rig(const struct uwb_rig_config *cfg)
{
    struct uwb_rig *rig;
    int detail;
    int rc = uwb_rig_open(cfg, &rig, &detail, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, rc, err);
    return rig;
}

/* After any scan, successful or not: pulser idle, motor off, no step lost
 * to a disabled motor. */
static void assert_board_safe(void)
{
    cJSON *status = ctl("status");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, status_line(status, "enable"), "motor left enabled");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, status_line(status, "trigger"), "trigger left high");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, status_line(status, "step"), "step left high");
    TEST_ASSERT_EQUAL_DOUBLE(0, status_number(status, "steps_while_disabled"));
    cJSON_Delete(status);
}

/* The log's answered triggers, in order: y (m) of each. Returns the count. */
static int sent_ys(double *ys, int max)
{
    cJSON *log = ctl("log");
    const cJSON *entries = cJSON_GetObjectItemCaseSensitive(log, "entries");
    int n = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, entries)
    {
        const cJSON *result = cJSON_GetObjectItemCaseSensitive(e, "result");
        if (strcmp(result->valuestring, "sent") == 0 && n < max)
            ys[n++] = cJSON_GetObjectItemCaseSensitive(e, "y_m")->valuedouble;
    }
    cJSON_Delete(log);
    return n;
}

/* How many log entries have this result. */
static int count_results(const char *result)
{
    cJSON *log = ctl("log");
    const cJSON *e;
    int n = 0;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(log, "entries")) n +=
        strcmp(cJSON_GetObjectItemCaseSensitive(e, "result")->valuestring, result) == 0;
    cJSON_Delete(log);
    return n;
}

/* Every position's `stack` answered triggers were computed at its y. */
static void assert_traces_at_requested_positions(const struct uwb_rig_config *cfg)
{
    double ys[4096];
    int n = sent_ys(ys, 4096);
    TEST_ASSERT_EQUAL_INT(cfg->positions * cfg->digitiser.stack, n);
    for (int k = 0; k < cfg->positions; k++)
        for (int p = 0; p < cfg->digitiser.stack; p++) {
            double want_mm = cfg->first_position_mm + k * cfg->step_mm;
            char msg[96];
            snprintf(msg, sizeof msg, "position %d pulse %d", k, p);
            TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.5 / cfg->carriage.steps_per_mm + 1e-9, want_mm,
                                              ys[k * cfg->digitiser.stack + p] * 1000, msg);
        }
}

/* The data itself: each trace a is nearer the simulator's noiseless trace
 * at its own y than at a y half a position step away (b). Noise adds the
 * same to both distances on average, so ||t-b||^2 - ||t-a||^2 is close to
 * ||a-b||^2; a trace from the wrong height makes it negative. */
static void assert_traces_match_the_simulator(const struct uwb_scan *scan, int check_every)
{
    struct sim_scene scene;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&scene));
    struct sim_engine *engine;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&scene, &engine, err, sizeof err), err);
    double *a = malloc((size_t)scan->samples * sizeof *a), *b = malloc((size_t)scan->samples * sizeof *b);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    double step = scan->positions > 1 ? scan->antenna_y_m[1] - scan->antenna_y_m[0] : 0.03;
    for (int k = 0; k < scan->positions; k += check_every) {
        const float *t = scan->data + (size_t)k * scan->samples;
        double y = scan->antenna_y_m[k];
        sim_engine_clean_trace(engine, y, SIM_PART_ALL, 0, a);
        sim_engine_clean_trace(engine, y + 0.5 * step, SIM_PART_ALL, 0, b);
        double to_a = 0, to_b = 0, ab = 0;
        for (int i = 0; i < scan->samples; i++) {
            to_a += (t[i] - a[i]) * (t[i] - a[i]);
            to_b += (t[i] - b[i]) * (t[i] - b[i]);
            ab += (a[i] - b[i]) * (a[i] - b[i]);
        }
        char msg[160];
        snprintf(msg, sizeof msg,
                 "position %d: squared distance %.4g at its y, %.4g half a step above (apart %.4g)", k, to_a,
                 to_b, ab);
        TEST_ASSERT_TRUE_MESSAGE(to_b - to_a > 0.5 * ab, msg);
    }
    free(a);
    free(b);
    sim_engine_free(engine);
}

/* ---- tests ---------------------------------------------------------------- */

static void test_full_scan_traces_are_computed_where_the_carriage_is(void)
{
    struct uwb_rig_config cfg;
    rig_config(&cfg, full_positions());
    /* real waits, a thousand times shorter: the pacing path as on the board */
    cfg.time_scale = under_emulation ? 0 : 0.001;
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    int rc = uwb_rig_scan(rig, NULL, &scan, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, rc, err);
    TEST_ASSERT_EQUAL_INT(cfg.positions, scan.positions);
    TEST_ASSERT_EQUAL_INT(cfg.digitiser.samples, scan.samples);
    for (int k = 0; k < scan.positions; k++)
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, (cfg.first_position_mm + k * cfg.step_mm) / 1000,
                                  scan.antenna_y_m[k]);
    /* header */
    TEST_ASSERT_EQUAL_INT(cfg.digitiser.stack, scan.stack);
    TEST_ASSERT_EQUAL_DOUBLE(cfg.digitiser.sample_interval_s, scan.sample_interval_s);
    TEST_ASSERT_EQUAL_DOUBLE(cfg.digitiser.t0_s, scan.t0_s);
    TEST_ASSERT_EQUAL_DOUBLE(cfg.eps_r, scan.eps_r);
    TEST_ASSERT_EQUAL_DOUBLE(cfg.tx_m[0], scan.tx_m[0]);
    TEST_ASSERT_EQUAL_DOUBLE(cfg.rx_m[0], scan.rx_m[0]);
    TEST_ASSERT_NOT_NULL(scan.created);
    TEST_ASSERT_EQUAL_INT(20, (int)strlen(scan.created)); /* 2024-05-01T12:00:00Z */
    TEST_ASSERT_EQUAL_INT('T', scan.created[10]);
    TEST_ASSERT_EQUAL_INT('Z', scan.created[19]);
    TEST_ASSERT_NOT_NULL(scan.scan_id);
    TEST_ASSERT_EQUAL_INT(0, strncmp(scan.scan_id, "uwb-", 4));
    TEST_ASSERT_NOT_NULL(strstr(scan.source, "test_rig_emulated"));
    TEST_ASSERT_NOT_NULL(strstr(scan.source, "uwbemu"));

    assert_traces_at_requested_positions(&cfg);
    assert_traces_match_the_simulator(&scan, under_emulation ? 3 : 1);
    assert_board_safe();
    /* parked */
    cJSON *status = ctl("status");
    TEST_ASSERT_DOUBLE_WITHIN(0.5 / BOARD_STEPS_PER_MM, cfg.carriage.park_mm,
                              status_number(status, "position_mm"));
    cJSON_Delete(status);
    struct uwb_rig_stats st;
    uwb_rig_get_stats(rig, &st);
    TEST_ASSERT_EQUAL_UINT32(1, st.scans);
    TEST_ASSERT_EQUAL_UINT32(0, st.retries);
    TEST_ASSERT_EQUAL_UINT32((unsigned)(cfg.positions * cfg.digitiser.stack), st.traces);

    /* A second scan on the same rig re-homes and gives the same geometry. */
    struct uwb_scan again;
    ctl_ok("log clear");
    rc = uwb_rig_scan(rig, NULL, &again, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, rc, err);
    assert_traces_at_requested_positions(&cfg);
    TEST_ASSERT_EQUAL_INT(scan.positions, again.positions);
    uwb_scan_free(&again);
    uwb_scan_free(&scan);
    uwb_rig_close(rig);
}

static char scan_log_line[1024];

static void keep_scan_line(void *ctx, int priority, const char *message)
{
    (void)ctx;
    (void)priority;
    if (strncmp(message, "scan ", 5) == 0)
        snprintf(scan_log_line, sizeof scan_log_line, "%s", message);
}

/* Issue 48, finding 4: with an asset the rig's scan id leads with it, so
 * its log line names the scan with its asset as every scan line does
 * ("scan T3-north-uwb-20261207T032316.813Z: 5 positions ..."); it said
 * "scan uwb-...". One form: ASSET-uwb-YYYYMMDDTHHMMSS.mmmZ. */
static void test_the_rigs_scan_id_and_log_line_name_the_asset(void)
{
    struct uwb_rig_config cfg;
    rig_config(&cfg, 5);
    cfg.digitiser.stack = 1;
    snprintf(cfg.asset_id, sizeof cfg.asset_id, "T3-north");
    struct uwb_rig *rig = open_rig(&cfg);
    scan_log_line[0] = '\0';
    uwb_rig_set_log(rig, keep_scan_line, NULL);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_scan(rig, NULL, &scan, err, sizeof err), err);
    const char *id = scan.scan_id;
    TEST_ASSERT_EQUAL_INT_MESSAGE(strlen("T3-north-uwb-20261207T032316.813Z"), strlen(id), id);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(id, "T3-north-uwb-", 13), id);
    for (int i = 13; i < 33; i++) {
        int digit = id[i] >= '0' && id[i] <= '9';
        TEST_ASSERT_TRUE_MESSAGE(digit || i == 21 || i == 28 || i == 32, id);
    }
    TEST_ASSERT_EQUAL_INT('T', id[21]);
    TEST_ASSERT_EQUAL_INT('.', id[28]);
    TEST_ASSERT_EQUAL_INT('Z', id[32]);
    /* The same instant as the header's created, to the second. */
    TEST_ASSERT_EQUAL_MEMORY(scan.created, id + 13, 4);
    char line_start[128];
    snprintf(line_start, sizeof line_start, "scan %s: ", id);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(scan_log_line, line_start, strlen(line_start)), scan_log_line);
    uwb_scan_free(&scan);
    uwb_rig_close(rig);
}

/* The daemon thinks 10 steps/mm, the mechanics do 12: homing works, but the
 * traces come from the wrong heights, and the board's log shows it. */
static void test_wrong_steps_per_mm_gives_traces_from_wrong_heights(void)
{
    ctl_ok("board steps_per_mm 12");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 5);
    cfg.digitiser.stack = 1;
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_scan(rig, NULL, &scan, err, sizeof err), err);
    double ys[64];
    TEST_ASSERT_EQUAL_INT(5, sent_ys(ys, 64));
    double worst = 0;
    for (int k = 0; k < 5; k++)
        worst = fmax(worst, fabs(ys[k] - scan.antenna_y_m[k]));
    /* the last position, 620 mm above home, is really 516.7 mm up: off by 103.3 mm */
    TEST_ASSERT_DOUBLE_WITHIN(0.002, 0.1033, worst);
    uwb_scan_free(&scan);
    uwb_rig_close(rig);
}

/* A scene parameter's value as the board gives it (caller frees). */
static char *scene_value(const char *key)
{
    char cmd[96];
    snprintf(cmd, sizeof cmd, "get %s", key);
    cJSON *o = ctl(cmd);
    char *value = strdup(cJSON_GetObjectItemCaseSensitive(o, "value")->valuestring);
    cJSON_Delete(o);
    TEST_ASSERT_NOT_NULL(value);
    return value;
}

/* A command the board must refuse, its message holding `words`. */
static void ctl_refused(const char *command, const char *words)
{
    char *text = ctl_raw(command);
    TEST_ASSERT_NOT_NULL_MESSAGE(text, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"class\":\"ERROR\""), text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, words), text);
    free(text);
}

/* `set radial` on the board (issue 30): in the scan the rig records next,
 * the face echo facing the bulged disks comes earlier, by part of the
 * bulge's two-way delay (the antennas see the whole face at once, so not
 * all of it); bad input is refused, named, and changes nothing. */
static void test_a_radial_change_set_on_the_board_moves_the_face_echo(void)
{
    scene_changed = 1;
    ctl_ok("set noise false"); /* the echo alone, and from the same winding */
    ctl_ok("set jitter_s 0");
    ctl_ok("set drift_db 0");
    ctl_ok("set clutter false");
    struct uwb_rig_config cfg;
    rig_config(&cfg, full_positions());
    cfg.digitiser.stack = 1;
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan intact, bulged;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_scan(rig, NULL, &intact, err, sizeof err), err);

    ctl_refused("set radial 2 9 6", "disks 2 to 9");
    ctl_refused("set radial 2 4", "set radial FROM TO MM");
    ctl_refused("set radial 2 4 6mm", "'6mm' is not a number of mm");
    ctl_refused("set radial 2 4 -70", "through its back face");
    ctl_refused("set face_tilt x", "'x' is not a number of mm");
    char *unchanged = scene_value("radial_m");
    TEST_ASSERT_EQUAL_STRING("", unchanged);
    free(unchanged);
    cJSON *reply = ctl("set radial 2 4 6");
    TEST_ASSERT_EQUAL_STRING("2-4:0.006", cJSON_GetObjectItemCaseSensitive(reply, "value")->valuestring);
    cJSON_Delete(reply);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_scan(rig, NULL, &bulged, err, sizeof err), err);
    restore_scene();

    /* the position facing disk 3 (the paper's stack: 22 mm disks, 4 mm gaps, from 230 mm) */
    double y3 = 0.230 + 2 * 0.026 + 0.011;
    int k = 0;
    for (int i = 1; i < intact.positions; i++)
        if (fabs(intact.antenna_y_m[i] - y3) < fabs(intact.antenna_y_m[k] - y3))
            k = i;
    double v = 299792458.0 / sqrt(intact.eps_r), dt = intact.sample_interval_s;
    int face = (int)((2 * 0.45 / v - intact.t0_s) / dt);
    const float *a = intact.data + (size_t)k * intact.samples, *b = bulged.data + (size_t)k * bulged.samples;
    double lag = sim_xcorr_lag(a, b, intact.samples, face - 150, face + 250, 40);
    double full = -2 * 0.006 / v / dt;
    printf("board: disks 2-4 bulged 6 mm: face echo at y = %.3f m %+.2f samples (two-way %+.2f)\n",
           intact.antenna_y_m[k], lag, full);
    TEST_ASSERT_TRUE_MESSAGE(lag / full > 0.3 && lag / full < 1.1,
                             "the face echo facing the bulge did not move");
    uwb_scan_free(&intact);
    uwb_scan_free(&bulged);
    uwb_rig_close(rig);
}

/* The daemon thinks 10 steps/mm, the mechanics do 8: the last positions lie
 * past the travel, where the carriage meets its top stop (670 mm above the
 * switch); the stalled steps are lost, and the home check says so. */
static void test_a_scale_past_the_travel_stalls_at_the_top_stop(void)
{
    ctl_ok("board steps_per_mm 8");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 5);
    cfg.digitiser.stack = 1;
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_ERR_HOME, uwb_rig_scan(rig, NULL, &scan, err, sizeof err), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "steps lost"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "top stop"), err);
    double ys[64];
    int n = sent_ys(ys, 64);
    TEST_ASSERT_EQUAL_INT(5, n);
    double highest = 0;
    for (int k = 0; k < n; k++)
        highest = fmax(highest, ys[k]);
    /* y = home_y_mm (-20) + 670 mm: the stop, not 775 mm up */
    TEST_ASSERT_DOUBLE_WITHIN(0.001, 0.650, highest);
    cJSON *status = ctl("status");
    TEST_ASSERT_TRUE(status_number(status, "steps_stalled") > 0);
    cJSON_Delete(status);
    assert_board_safe();
    uwb_rig_close(rig);
}

/* DIR wired backwards: the home search runs up and away, and says so. */
static void test_inverted_dir_is_caught_by_the_home_search(void)
{
    ctl_ok("board invert_dir 1");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 3);
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_HOME, uwb_rig_scan(rig, NULL, &scan, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "never closed"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "DIR"), err);
    TEST_ASSERT_NULL(scan.data);
    double ys[4];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sent_ys(ys, 4), "fired without a home");
    assert_board_safe();
    uwb_rig_close(rig);
}

static void test_bad_and_missing_frames_are_fired_again(void)
{
    ctl_ok("fault crc every 3");
    ctl_ok("fault drop every 7");
    ctl_ok("fault truncate next 1");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 5);
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_scan(rig, NULL, &scan, err, sizeof err), err);
    struct uwb_rig_stats st;
    uwb_rig_get_stats(rig, &st);
    TEST_ASSERT_TRUE(st.bad_frames >= 2); /* crc strikes, the truncated frame overrun */
    TEST_ASSERT_TRUE(st.timeouts >= 2);   /* drop, truncate */
    TEST_ASSERT_EQUAL_UINT32(st.fired - st.traces, st.retries);
    TEST_ASSERT_EQUAL_UINT32((unsigned)(cfg.positions * cfg.digitiser.stack), st.traces);
    assert_traces_at_requested_positions(&cfg);
    assert_traces_match_the_simulator(&scan, under_emulation ? 2 : 1);
    assert_board_safe();
    uwb_scan_free(&scan);
    uwb_rig_close(rig);
}

static void test_a_dropped_digitiser_link_is_reopened(void)
{
    ctl_ok("fault disconnect next 1");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 3);
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_scan(rig, NULL, &scan, err, sizeof err), err);
    struct uwb_rig_stats st;
    uwb_rig_get_stats(rig, &st);
    TEST_ASSERT_EQUAL_UINT32(1, st.reconnects);
    assert_traces_at_requested_positions(&cfg);
    uwb_scan_free(&scan);
    uwb_rig_close(rig);
}

static void test_a_silent_digitiser_fails_the_scan_and_leaves_the_rig_safe(void)
{
    ctl_ok("fault silent on");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 3);
    cfg.digitiser.frame_retries = 2;
    if (!under_emulation)
        cfg.digitiser.frame_timeout_ms = 150;
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_DIGITISER, uwb_rig_scan(rig, NULL, &scan, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no good frame after 3 triggers"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "position 0"), err);
    TEST_ASSERT_EQUAL_INT(3, count_results("silent"));
    assert_board_safe();
    uwb_rig_close(rig);
}

static void test_home_switch_never_closing_is_a_home_error(void)
{
    ctl_ok("fault home-never on");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 3);
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_HOME, uwb_rig_scan(rig, NULL, &scan, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "home switch never closed"), err);
    assert_board_safe();
    uwb_rig_close(rig);
}

static void test_home_switch_stuck_closed_is_a_home_error(void)
{
    ctl_ok("fault home-stuck on");
    struct uwb_rig_config cfg;
    rig_config(&cfg, 3);
    struct uwb_rig *rig = open_rig(&cfg);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_HOME, uwb_rig_scan(rig, NULL, &scan, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "stays closed"), err);
    /* it backed off only the configured distance before giving up */
    cJSON *status = ctl("status");
    TEST_ASSERT_DOUBLE_WITHIN(0.2, 50 + cfg.carriage.home_backoff_mm, status_number(status, "position_mm"));
    cJSON_Delete(status);
    assert_board_safe();
    uwb_rig_close(rig);
}

static volatile sig_atomic_t stop_flag;

static void stop_when_homed(void *ctx, int priority, const char *message)
{
    (void)ctx;
    (void)priority;
    if (strstr(message, "homed"))
        stop_flag = 1;
}

static void test_stop_request_ends_the_scan_safely(void)
{
    struct uwb_rig_config cfg;
    rig_config(&cfg, 5);
    struct uwb_rig *rig = open_rig(&cfg);
    uwb_rig_set_log(rig, stop_when_homed, NULL);
    stop_flag = 0;
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_STOPPED, uwb_rig_scan(rig, &stop_flag, &scan, err, sizeof err));
    TEST_ASSERT_NULL(scan.data);
    double ys[4];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sent_ys(ys, 4), "fired after the stop request");
    assert_board_safe();
    uwb_rig_close(rig);
}

/* n full STEP pulses (high, then low). */
static void pulse_steps(struct uwb_gpio *gpio, int n)
{
    for (int i = 0; i < n; i++) {
        uwb_gpio_set(gpio, UWB_LINE_STEP, 1, err, sizeof err);
        uwb_gpio_set(gpio, UWB_LINE_STEP, 0, err, sizeof err);
    }
}

/* The emulated GPIO backend on its own: steps count only while enabled,
 * DIR gives the direction, HOME reads the switch. */
static void test_emulated_gpio_backend_drives_the_board(void)
{
    struct uwb_gpio_config cfg;
    uwb_gpio_config_defaults(&cfg);
    snprintf(cfg.backend, sizeof cfg.backend, "emulated");
    snprintf(cfg.endpoint, sizeof cfg.endpoint, "%s", gpio_ep);
    struct uwb_gpio *gpio;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_open(&cfg, &gpio, err, sizeof err), err);
    int home = -1;
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_OK, uwb_gpio_get(gpio, UWB_LINE_HOME, &home, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, home);
    /* 3 steps while disabled are lost; 20 down and 5 up while enabled count */
    pulse_steps(gpio, 3);
    uwb_gpio_set(gpio, UWB_LINE_ENABLE, 1, err, sizeof err);
    uwb_gpio_set(gpio, UWB_LINE_DIR, 0, err, sizeof err);
    pulse_steps(gpio, 20);
    uwb_gpio_set(gpio, UWB_LINE_DIR, 1, err, sizeof err);
    pulse_steps(gpio, 5);
    int enable = -1;
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_OK, uwb_gpio_get(gpio, UWB_LINE_ENABLE, &enable, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, enable);
    cJSON *status = ctl("status");
    TEST_ASSERT_EQUAL_DOUBLE(50 * BOARD_STEPS_PER_MM - 15, status_number(status, "steps"));
    TEST_ASSERT_EQUAL_DOUBLE(3, status_number(status, "steps_while_disabled"));
    cJSON_Delete(status);
    /* at the switch, HOME reads closed */
    ctl_ok("board position_mm 0");
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_OK, uwb_gpio_get(gpio, UWB_LINE_HOME, &home, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, home);
    /* HOME is an input */
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_LINE, uwb_gpio_set(gpio, UWB_LINE_HOME, 1, err, sizeof err));
    uwb_gpio_close(gpio);
    /* closing releases the outputs low */
    status = ctl("status");
    TEST_ASSERT_EQUAL_INT(0, status_line(status, "enable"));
    cJSON_Delete(status);
}

/* One line of the board's GPIO protocol; the reply line ("" when none
 * comes within 300 ms: a good `set` is not answered). */
static void gpio_exchange(struct uwb_link *link, const char *line, char *reply, size_t n)
{
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_write_all(link, line, strlen(line), 5000, err, sizeof err));
    size_t len = 0;
    reply[0] = '\0';
    while (len + 1 < n && !strchr(reply, '\n')) {
        ssize_t got =
            uwb_link_read(link, reply + len, n - len - 1, under_emulation ? 3000 : 300, err, sizeof err);
        if (got <= 0)
            break;
        len += (size_t)got;
        reply[len] = '\0';
    }
}

/* The board's `set LINE LEVEL`: a level is exactly 0 or 1 (no sign, no
 * leading zero, nothing after it), anything else is refused and the line
 * keeps its level. */
static void test_emulated_gpio_protocol_takes_levels_0_and_1_only(void)
{
    struct uwb_link *link;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, uwb_link_open(gpio_ep, &link, err, sizeof err), err);
    char reply[256];
    gpio_exchange(link, "hello uwb-gpio/1\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(reply, "ok uwb-gpio/1", 13), reply);
    gpio_exchange(link, "get enable\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_STRING("val enable 0\n", reply);
    static const char *const refused[] = {"set enable 2\n",  "set enable 01\n", "set enable +1\n",
                                          "set enable -1\n", "set enable 1x\n", "set enable x\n",
                                          "set home 1\n",    "set nosuch 1\n"};
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
        gpio_exchange(link, refused[i], reply, sizeof reply);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(reply, "err cannot set", 14), refused[i]);
    }
    gpio_exchange(link, "set enable 1 2\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(reply, "err unknown command", 19), reply);
    gpio_exchange(link, "get enable\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_STRING("val enable 0\n", reply);
    gpio_exchange(link, "set enable 1\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_STRING("", reply);
    gpio_exchange(link, "get enable\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_STRING("val enable 1\n", reply);
    gpio_exchange(link, "set enable 0\n", reply, sizeof reply);
    gpio_exchange(link, "get enable\n", reply, sizeof reply);
    TEST_ASSERT_EQUAL_STRING("val enable 0\n", reply);
    uwb_link_close(link);
}

static void test_rig_open_without_a_digitiser_is_a_link_error(void)
{
    struct uwb_rig_config cfg;
    rig_config(&cfg, 3);
    snprintf(cfg.digitiser.endpoint, sizeof cfg.digitiser.endpoint, "unix:%s/nobody", dir);
    struct uwb_rig *rig;
    int detail = 0;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_LINK, uwb_rig_open(&cfg, &rig, &detail, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_OPEN, detail);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "nobody"), err);
    /* a GPIO endpoint that is not the board's GPIO: the hello is refused */
    rig_config(&cfg, 3);
    snprintf(cfg.gpio.endpoint, sizeof cfg.gpio.endpoint, "%s", ctl_ep);
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_GPIO, uwb_rig_open(&cfg, &rig, &detail, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CHIP, detail);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "hello"), err);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    UNITY_BEGIN();
    start_board();
    RUN_TEST(test_full_scan_traces_are_computed_where_the_carriage_is);
    RUN_TEST(test_wrong_steps_per_mm_gives_traces_from_wrong_heights);
    RUN_TEST(test_the_rigs_scan_id_and_log_line_name_the_asset);
    RUN_TEST(test_a_radial_change_set_on_the_board_moves_the_face_echo);
    RUN_TEST(test_a_scale_past_the_travel_stalls_at_the_top_stop);
    RUN_TEST(test_inverted_dir_is_caught_by_the_home_search);
    RUN_TEST(test_bad_and_missing_frames_are_fired_again);
    RUN_TEST(test_a_dropped_digitiser_link_is_reopened);
    RUN_TEST(test_a_silent_digitiser_fails_the_scan_and_leaves_the_rig_safe);
    RUN_TEST(test_home_switch_never_closing_is_a_home_error);
    RUN_TEST(test_home_switch_stuck_closed_is_a_home_error);
    RUN_TEST(test_stop_request_ends_the_scan_safely);
    RUN_TEST(test_emulated_gpio_backend_drives_the_board);
    RUN_TEST(test_emulated_gpio_protocol_takes_levels_0_and_1_only);
    RUN_TEST(test_rig_open_without_a_digitiser_is_a_link_error);
    stop_board();
    return UNITY_END();
}
