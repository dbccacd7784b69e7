/* The daemon's configuration: the shipped samples load, defaults apply,
 * and every kind of mistake is refused with a message naming the key. */
#include "unity.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scratch_support.h"
#include "config/winding_span.h"
#include "config/config_load.h"

#define SAMPLE_EMULATED "board/emulated/uwbd.json"
#define SAMPLE_RPI4 "board/raspberry-pi-4/uwbd.json"

static struct uwbd_config cfg;
static char err[1024];
static char *sample_text;

void setUp(void)
{
    sample_text = scratch_slurp(SAMPLE_EMULATED, NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(sample_text, SAMPLE_EMULATED);
    err[0] = '\0';
}

void tearDown(void)
{
    free(sample_text);
}

static int parse_text(const char *text)
{
    return uwbd_config_parse(text, strlen(text), "test.json", NULL, 0, &cfg, err, sizeof err);
}

/* A JSON document, printed, through the loader. */
static int parse_document(const cJSON *root)
{
    char *text = cJSON_Print(root);
    TEST_ASSERT_NOT_NULL(text);
    int rc = parse_text(text);
    free(text);
    return rc;
}

/* The emulated sample with one change: `path` set to the JSON `value`, or
 * removed when value is NULL. Returns what the loader says. */
static int parse_changed(const char *path, const char *value)
{
    cJSON *root = cJSON_Parse(sample_text);
    TEST_ASSERT_NOT_NULL(root);
    char buf[128];
    snprintf(buf, sizeof buf, "%s", path);
    cJSON *obj = root;
    char *part = buf, *dot;
    while ((dot = strchr(part, '.')) != NULL) {
        *dot = '\0';
        cJSON *next = cJSON_GetObjectItemCaseSensitive(obj, part);
        if (!next)
            next = cJSON_AddObjectToObject(obj, part);
        obj = next;
        part = dot + 1;
    }
    cJSON_DeleteItemFromObjectCaseSensitive(obj, part);
    if (value) {
        cJSON *v = cJSON_Parse(value);
        TEST_ASSERT_NOT_NULL_MESSAGE(v, value);
        cJSON_AddItemToObject(obj, part, v);
    }
    int rc = parse_document(root);
    cJSON_Delete(root);
    return rc;
}

/* The error names the changed key and says `words`. */
static void assert_refused(const char *path, const char *value, const char *words)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, parse_changed(path, value), path);
    char want[160];
    snprintf(want, sizeof want, "test.json: key `%s`: ", path);
    if (strncmp(err, want, strlen(want)) != 0 || !strstr(err, words)) {
        char msg[1400];
        snprintf(msg, sizeof msg, "want \"%s...%s\", got \"%s\"", want, words, err);
        TEST_FAIL_MESSAGE(msg);
    }
}

static void test_emulated_sample_loads_with_units_converted(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_config_load(SAMPLE_EMULATED, NULL, 0, &cfg, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("emulated", cfg.rig.gpio.backend);
    TEST_ASSERT_EQUAL_STRING("unix:run/digitiser.sock", cfg.rig.digitiser.endpoint);
    TEST_ASSERT_EQUAL_INT(2048, cfg.rig.digitiser.samples);
    TEST_ASSERT_DOUBLE_WITHIN(1e-18, 10e-12, cfg.rig.digitiser.sample_interval_s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, -1e-9, cfg.rig.digitiser.t0_s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, -0.020, cfg.rig.tx_m[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.020, cfg.rig.rx_m[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.005, cfg.evaluate.compare.thresholds.alarm_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-18, 20e-12, cfg.evaluate.direct_coupling.tolerance_s);
    TEST_ASSERT_EQUAL_UINT(0660, cfg.control_mode);
    TEST_ASSERT_EQUAL_INT(UWB_DEFAULT_STACK, cfg.rig.digitiser.stack);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cfg.interval_s);
}

static void test_raspberry_pi_sample_loads(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_config_load(SAMPLE_RPI4, NULL, 0, &cfg, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("libgpiod", cfg.rig.gpio.backend);
    TEST_ASSERT_EQUAL_STRING("/var/lib/uwbd", cfg.state_dir);
    for (int i = 0; i < UWB_LINE_RIG; i++)
        TEST_ASSERT_TRUE(cfg.rig.gpio.offset[i] >= 0 || cfg.rig.gpio.name[i][0]);
    TEST_ASSERT_EQUAL_INT(0, cfg.allow_root);
    TEST_ASSERT_EQUAL_INT(UWB_DEFAULT_STACK, cfg.rig.digitiser.stack);
}

static void test_defaults_fill_what_is_left_out(void)
{
    static const char minimal[] =
        "{\"gpio\":{\"backend\":\"emulated\",\"endpoint\":\"unix:g.sock\"},"
        "\"digitiser\":{\"endpoint\":\"unix:d.sock\",\"samples\":1024,\"sample_interval_ps\":10},"
        "\"carriage\":{\"steps_per_mm\":100,\"travel_mm\":650,\"home_offset_mm\":-20},"
        "\"scan\":{\"positions\":21,\"first_position_mm\":0,\"step_mm\":30},"
        "\"geometry\":{\"tx_mm\":[-20,0],\"rx_mm\":[20,0],\"eps_r\":2.2}}";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_text(minimal), err);
    TEST_ASSERT_EQUAL_STRING("/var/lib/uwbd", cfg.state_dir);
    TEST_ASSERT_EQUAL_STRING(UWBD_DEFAULT_CONTROL_SOCKET, cfg.control_socket);
    TEST_ASSERT_EQUAL_UINT(0660, cfg.control_mode);
    TEST_ASSERT_EQUAL_DOUBLE(86400.0, cfg.interval_s);
    TEST_ASSERT_EQUAL_INT(1000, cfg.retention_max_scans);
    /* One stacking default: the key table, the rig's own defaults and the samples (above). */
    TEST_ASSERT_EQUAL_INT(64, cfg.rig.digitiser.stack);
    struct uwb_rig_config rig_defaults;
    uwb_rig_config_defaults(&rig_defaults);
    TEST_ASSERT_EQUAL_INT(cfg.rig.digitiser.stack, rig_defaults.digitiser.stack);
    TEST_ASSERT_EQUAL_STRING("", cfg.console_endpoint);
    TEST_ASSERT_EQUAL_INT(0, cfg.rig.has_target_z);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.002, cfg.evaluate.compare.thresholds.watch_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-18, 2e-9, cfg.evaluate.direct_coupling.window_end_s);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, cfg.rig.time_scale);
}

static void test_unknown_keys_are_errors(void)
{
    assert_refused("bogus", "1", "unknown key");
    assert_refused("digitiser.sampels", "2048", "unknown key");
    assert_refused("gpio.lines.bogus", "3", "unknown key");
}

/* Issue 31: a near miss names the key meant, as a mistyped option does. */
static void test_unknown_keys_name_the_one_meant(void)
{
    assert_refused("digitiser.sampels", "2048", "unknown key (did you mean `digitiser.samples`?");
    assert_refused("schedule.intervall_s", "60", "did you mean `schedule.interval_s`?");
    TEST_ASSERT_EQUAL_INT(-1, parse_changed("digitizer.samples", "2048"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `digitizer`: unknown key (did you mean `digitiser`?"), err);
    assert_refused("bogus", "1", "unknown key (uwbd --config-keys lists them all)");

    struct uwbd_override typo[] = {{"schedule.intervall_s", "60"}};
    TEST_ASSERT_EQUAL_INT(
        -1, uwbd_config_parse(sample_text, strlen(sample_text), "f", typo, 1, &cfg, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "did you mean `schedule.interval_s`?"), err);
}

static void test_wrong_types_are_errors(void)
{
    assert_refused("digitiser.samples", "\"2048\"", "expected an integer");
    assert_refused("digitiser.samples", "2048.5", "not an integer");
    assert_refused("carriage.steps_per_mm", "true", "expected a number");
    assert_refused("allow_root", "1", "expected true or false");
    assert_refused("state_dir", "7", "expected a string");
    assert_refused("geometry.tx_mm", "[1]", "two numbers");
    assert_refused("gpio", "5", "expected an object");
    assert_refused("gpio.lines.step", "[1]", "offset (integer) or a line name");
}

static void test_out_of_range_and_bad_choices_are_errors(void)
{
    assert_refused("analysis.edge_fraction", "2", "out of range");
    assert_refused("digitiser.sample_interval_ps", "0", "out of range");
    assert_refused("schedule.interval_s", "-5", "out of range");
    assert_refused("gpio.backend", "\"sysfs\"", "not one of libgpiod, emulated");
    assert_refused("analysis.migration", "\"double\"", "neither fixed nor float");
    assert_refused("control.mode", "\"0666\"", "gives others access");
    assert_refused("control.mode", "\"0440\"", "owner");
    assert_refused("control.mode", "\"rw\"", "not an octal mode");
    assert_refused("state_dir", "\"a\\nb\"", "control character");
}

static void test_missing_required_keys_are_errors(void)
{
    assert_refused("digitiser.endpoint", NULL, "missing");
    assert_refused("scan.positions", NULL, "missing");
    assert_refused("geometry.eps_r", NULL, "missing");
    assert_refused("carriage.home_offset_mm", NULL, "missing");
}

static void test_keys_that_depend_on_others(void)
{
    assert_refused("analysis.alarm_mm", "1", "below analysis.watch_mm");
    assert_refused("scan.positions", "40", "beyond the travel");
    assert_refused("scan.first_position_mm", "-25", "below home");
    assert_refused("gpio.endpoint", NULL, "required with the emulated backend");
    assert_refused("digitiser.endpoint", "\"ttyUSB0\"", "ttyUSB0");
    assert_refused("console.endpoint", "\"9600\"", "9600");
    assert_refused("geometry.target_z_mm", "[900, 300]", "below far");
    assert_refused("analysis.winding_span_mm", "[400, 230]", "lower (400 mm) must be below upper (230 mm)");
    assert_refused("carriage.home_rate_hz", "5000", "above carriage.max_rate_hz");
    /* Issue 17, break 5: the rig may not record a scan the reader refuses. */
    assert_refused("scan.step_mm", "0.5", "under the smallest step a scan file may hold (1 mm");
    assert_refused("scan.positions", "4000", "over the largest travel a scan file may hold (5000 mm)");
}

/* Issue 43, break 7: `--winding-span` and analysis.winding_span_mm are
 * judged by one validator: what the key refuses (past +-100,000 mm, or not
 * lower < upper) the validator refuses too, in the same words. */
static void test_the_winding_span_has_one_validator(void)
{
    static const char *const refused[][2] = {
        {"[1e300, 1e301]", "out of range [-100000, 100000] mm"},
        {"[-100001, 0]", "out of range [-100000, 100000] mm"},
        {"[0, 100000.5]", "out of range [-100000, 100000] mm"},
        {"[400, 230]", "lower (400 mm) must be below upper (230 mm)"},
    };
    static const double refused_m[][2] = {{1e297, 1e298}, {-100.001, 0}, {0, 100.0005}, {0.4, 0.23}};
    char problem[200];
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
        assert_refused("analysis.winding_span_mm", refused[i][0], refused[i][1]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, uwbd_winding_span_check(refused_m[i], problem, sizeof problem),
                                      refused[i][0]);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(problem, refused[i][1]), problem);
    }
    static const double limits_m[2] = {-100.0, 100.0};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_winding_span_check(limits_m, problem, sizeof problem), problem);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("analysis.winding_span_mm", "[-100000, 100000]"), err);
}

/* Issue 27, break 11: a rig whose scan is over the 64 MiB of samples a
 * scan file may hold would record what no reader takes back. */
static void test_a_rig_whose_scan_the_reader_refuses_is_refused(void)
{
    struct uwbd_override o[] = {
        {"scan.step_mm", "1"}, {"scan.positions", "300"}, {"digitiser.samples", "65536"}};
    TEST_ASSERT_EQUAL_INT(
        -1, uwbd_config_parse(sample_text, strlen(sample_text), "test.json", o, 3, &cfg, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err,
                                        "key `digitiser.samples`: 65536 samples x 300 positions = 19660800 "
                                        "samples per scan, over the limit of 16777216 (64 MiB of float32)"),
                                 err);
    o[1].value = "256"; /* 256 x 65536 is the limit itself */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_config_parse(sample_text, strlen(sample_text), "test.json", o, 3, &cfg, err, sizeof err),
        err);
}

/* Issue 17, break 1: state_dir "/" passed --check-config, and the start-up
 * cleanup then walked the whole tree. */
static void test_state_dir_must_be_a_directory_of_its_own(void)
{
    assert_refused("state_dir", "\"/\"", "a system directory");
    assert_refused("state_dir", "\"/etc\"", "a system directory");
    assert_refused("state_dir", "\"/var/lib/\"", "is /var/lib");
    assert_refused("state_dir", "\"//usr/./local/bin/..\"", "is /usr/local");
    assert_refused("state_dir", "\"/home/alice/..\"", "is /home");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("state_dir", "\"/var/lib/uwbd\""), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("state_dir", "\"/srv/uwbd\""), err);
}

/* Issue 17, break 9: --check-config passed a control.group that does not
 * exist, and the daemon then stopped with exit 78. */
static void test_check_system_refuses_a_missing_control_group(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("control.group", "\"uwbd-no-such-group-17\""), err);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_config_check_system(&cfg, "test.json", err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(err, "test.json: key `control.group`: no group named \"uwbd-no-such-group-17\""), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("control.group", "\"root\""), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_config_check_system(&cfg, "test.json", err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("control.group", "\"\""), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_config_check_system(&cfg, "test.json", err, sizeof err), err);
}

static void test_libgpiod_needs_chip_and_lines(void)
{
    cJSON *root = cJSON_Parse(sample_text);
    cJSON *gpio = cJSON_GetObjectItemCaseSensitive(root, "gpio");
    cJSON_ReplaceItemInObjectCaseSensitive(gpio, "backend", cJSON_CreateString("libgpiod"));
    cJSON_DeleteItemFromObjectCaseSensitive(gpio, "endpoint");
    TEST_ASSERT_EQUAL_INT(-1, parse_document(root));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `gpio.chip`: missing"), err);
    cJSON_AddStringToObject(gpio, "chip", "gpiochip0");
    TEST_ASSERT_EQUAL_INT(-1, parse_document(root));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `gpio.lines.trigger`: missing"), err);
    cJSON *lines = cJSON_AddObjectToObject(gpio, "lines");
    cJSON_AddNumberToObject(lines, "trigger", 17);
    cJSON_AddStringToObject(lines, "step", "STEP");
    cJSON_AddNumberToObject(lines, "dir", 22);
    cJSON_AddNumberToObject(lines, "enable", 23);
    cJSON_AddNumberToObject(lines, "home", 24);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_document(root), err);
    TEST_ASSERT_EQUAL_INT(17, cfg.rig.gpio.offset[UWB_LINE_TRIGGER]);
    TEST_ASSERT_EQUAL_INT(-1, cfg.rig.gpio.offset[UWB_LINE_STEP]);
    TEST_ASSERT_EQUAL_STRING("STEP", cfg.rig.gpio.name[UWB_LINE_STEP]);
    cJSON_Delete(root);
}

static void test_syntax_errors_name_the_place(void)
{
    TEST_ASSERT_EQUAL_INT(-1, parse_text("{\n  \"state_dir\": \"/x\",\n  oops\n}"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "test.json: line 3 column"), err);
    TEST_ASSERT_EQUAL_INT(-1, parse_text("{} {}"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "text after the end"), err);
    TEST_ASSERT_EQUAL_INT(-1, parse_text("[1,2]"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "one JSON object"), err);
    TEST_ASSERT_EQUAL_INT(-1, parse_text("{\"state_dir\":\"/a\",\"state_dir\":\"/b\"}"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `state_dir`: given twice"), err);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_config_load("/nonexistent/uwbd.json", NULL, 0, &cfg, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "/nonexistent/uwbd.json: cannot open"), err);
}

static void test_overrides_are_checked_like_the_file(void)
{
    struct uwbd_override ok[] = {{"schedule.interval_s", "60"},
                                 {"state_dir", "/srv/uwbd"},
                                 {"console.endpoint", "\"unix:/tmp/c.sock\""}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_config_parse(sample_text, strlen(sample_text), "f", ok, 3, &cfg, err, sizeof err), err);
    TEST_ASSERT_EQUAL_DOUBLE(60.0, cfg.interval_s);
    TEST_ASSERT_EQUAL_STRING("/srv/uwbd", cfg.state_dir); /* a bare word is a string */
    TEST_ASSERT_EQUAL_STRING("unix:/tmp/c.sock", cfg.console_endpoint);

    struct uwbd_override unknown[] = {{"schedule.intervall_s", "60"}};
    TEST_ASSERT_EQUAL_INT(
        -1, uwbd_config_parse(sample_text, strlen(sample_text), "f", unknown, 1, &cfg, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `schedule.intervall_s`: unknown key"), err);

    struct uwbd_override bad[] = {{"digitiser.stack", "lots"}};
    TEST_ASSERT_EQUAL_INT(
        -1, uwbd_config_parse(sample_text, strlen(sample_text), "f", bad, 1, &cfg, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `digitiser.stack`: expected an integer"), err);
}

/* board/config.md documents the keys: every key of the table is in it. */
static void test_config_md_documents_every_key(void)
{
    char *doc = scratch_slurp("board/config.md", NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(doc, "board/config.md");
    for (size_t i = 0; i < uwbd_config_key_count(); i++) {
        char quoted[160];
        snprintf(quoted, sizeof quoted, "`%s`", uwbd_config_key_path(i));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(doc, quoted), quoted);
    }
    /* ...and each row as `uwbd --config-keys` prints it, defaults included. */
    char *table = NULL;
    size_t table_len = 0;
    FILE *out = open_memstream(&table, &table_len);
    TEST_ASSERT_NOT_NULL(out);
    uwbd_config_print_keys_markdown(out);
    fclose(out);
    for (char *row = strtok(table, "\n"); row; row = strtok(NULL, "\n"))
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(doc, row), row);
    free(table);
    free(doc);
}

/* The display image's range: the analysis' default unless the key says otherwise. */
static void test_display_half_range_key_sets_the_analysis_option(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("analysis.display_half_range_mm", NULL), err);
    struct uwb_analysis_options defaults;
    uwb_analysis_defaults(&defaults);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, defaults.display_half_range_m,
                              cfg.evaluate.analysis.display_half_range_m);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_changed("analysis.display_half_range_mm", "100"), err);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.1, cfg.evaluate.analysis.display_half_range_m);
    assert_refused("analysis.display_half_range_mm", "5", "out of range");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_emulated_sample_loads_with_units_converted);
    RUN_TEST(test_raspberry_pi_sample_loads);
    RUN_TEST(test_defaults_fill_what_is_left_out);
    RUN_TEST(test_unknown_keys_are_errors);
    RUN_TEST(test_wrong_types_are_errors);
    RUN_TEST(test_out_of_range_and_bad_choices_are_errors);
    RUN_TEST(test_missing_required_keys_are_errors);
    RUN_TEST(test_keys_that_depend_on_others);
    RUN_TEST(test_the_winding_span_has_one_validator);
    RUN_TEST(test_a_rig_whose_scan_the_reader_refuses_is_refused);
    RUN_TEST(test_state_dir_must_be_a_directory_of_its_own);
    RUN_TEST(test_check_system_refuses_a_missing_control_group);
    RUN_TEST(test_libgpiod_needs_chip_and_lines);
    RUN_TEST(test_syntax_errors_name_the_place);
    RUN_TEST(test_overrides_are_checked_like_the_file);
    RUN_TEST(test_config_md_documents_every_key);
    RUN_TEST(test_unknown_keys_name_the_one_meant);
    RUN_TEST(test_display_half_range_key_sets_the_analysis_option);
    return UNITY_END();
}
