/* The site's keys (site.asset_id, contacts.*, event.*): off by default,
 * and an integration that is on without what it needs is refused with
 * the key named, as `uwbd --check-config` shows it. */
#include "unity.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scratch_support.h"
#include "config/config_load.h"

#define SAMPLE_EMULATED "board/emulated/uwbd.json"

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

static int parse_with(const struct uwbd_override *o, size_t n)
{
    err[0] = '\0';
    return uwbd_config_parse(sample_text, strlen(sample_text), "f", o, n, &cfg, err, sizeof err);
}

static void expect_refused(const struct uwbd_override *o, size_t n, const char *key_and_problem)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, parse_with(o, n), key_and_problem);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, key_and_problem), err);
}

static void test_every_integration_is_off_by_default(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(NULL, 0), err);
    TEST_ASSERT_EQUAL_STRING("", cfg.site.asset_id);
    TEST_ASSERT_FALSE(cfg.site.contacts_enabled);
    TEST_ASSERT_FALSE(cfg.site.event_enabled);
    TEST_ASSERT_FALSE(cfg.site.prometheus_enabled);
    TEST_ASSERT_EQUAL_UINT(0, cfg.site.io.lines); /* the site opens no line */
    TEST_ASSERT_TRUE(cfg.site.watch_latch);
    TEST_ASSERT_TRUE(cfg.site.alarm_latch);
}

static void test_asset_id_is_checked_and_kept(void)
{
    struct uwbd_override ok[] = {{"site.asset_id", "\"T3-Northfield_2\""}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(ok, 1), err);
    TEST_ASSERT_EQUAL_STRING("T3-Northfield_2", cfg.site.asset_id);

    struct uwbd_override slash[] = {{"site.asset_id", "\"T3/north\""}};
    expect_refused(slash, 1, "key `site.asset_id`: \"T3/north\": only letters, digits");
    struct uwbd_override wildcard[] = {{"site.asset_id", "\"T3+\""}};
    expect_refused(wildcard, 1, "key `site.asset_id`");
    struct uwbd_override dash[] = {{"site.asset_id", "\"-T3\""}};
    expect_refused(dash, 1, "key `site.asset_id`");
    struct uwbd_override too_long[] = {
        {"site.asset_id", "\"0123456789012345678901234567890123456789012345678901234567890123\""}};
    expect_refused(too_long, 1, "key `site.asset_id`");
}

static void test_an_integration_needs_the_asset_id(void)
{
    struct uwbd_override contacts[] = {{"contacts.enabled", "true"},
                                       {"gpio.site_endpoint", "\"unix:run/site.sock\""}};
    expect_refused(contacts, 2,
                   "key `site.asset_id`: missing: required once an integration is on (contacts.enabled)");
    struct uwbd_override event[] = {{"event.enabled", "true"},
                                    {"gpio.site_endpoint", "\"unix:run/site.sock\""}};
    expect_refused(event, 2,
                   "key `site.asset_id`: missing: required once an integration is on (event.enabled)");
}

static void test_emulated_contacts_need_the_site_endpoint(void)
{
    struct uwbd_override none[] = {{"site.asset_id", "T1"}, {"contacts.enabled", "true"}};
    expect_refused(none, 2, "key `gpio.site_endpoint`: missing");
    struct uwbd_override same[] = {{"site.asset_id", "T1"},
                                   {"contacts.enabled", "true"},
                                   {"gpio.site_endpoint", "\"unix:run/gpio.sock\""}};
    expect_refused(same, 3, "key `gpio.site_endpoint`: \"unix:run/gpio.sock\" is gpio.endpoint too");
    struct uwbd_override bad[] = {
        {"site.asset_id", "T1"}, {"contacts.enabled", "true"}, {"gpio.site_endpoint", "\"ftp:x\""}};
    expect_refused(bad, 3, "key `gpio.site_endpoint`");

    struct uwbd_override ok[] = {{"site.asset_id", "T1"},
                                 {"contacts.enabled", "true"},
                                 {"gpio.site_endpoint", "\"unix:run/site.sock\""},
                                 {"contacts.alarm.latch", "false"}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(ok, 4), err);
    TEST_ASSERT_EQUAL_STRING("emulated", cfg.site.io.backend);
    TEST_ASSERT_EQUAL_STRING("unix:run/site.sock", cfg.site.io.endpoint);
    TEST_ASSERT_FALSE(cfg.site.alarm_latch);
    /* The contacts' three outputs, not the event input, not the rig's lines. */
    TEST_ASSERT_EQUAL_HEX(UWB_GPIO_LINE_BIT(UWB_LINE_WATCH) | UWB_GPIO_LINE_BIT(UWB_LINE_ALARM) |
                              UWB_GPIO_LINE_BIT(UWB_LINE_FAULT),
                          cfg.site.io.lines);
    TEST_ASSERT_EQUAL_HEX(UWB_GPIO_RIG_LINES, cfg.rig.gpio.lines);
}

/* With libgpiod every enabled line must be named; the rig's are required as before. */
static const struct uwbd_override libgpiod_rig[] = {
    {"gpio.backend", "libgpiod"}, {"gpio.chip", "gpiochip0"}, {"gpio.endpoint", "\"\""},
    {"gpio.lines.trigger", "17"}, {"gpio.lines.step", "27"},  {"gpio.lines.dir", "22"},
    {"gpio.lines.enable", "23"},  {"gpio.lines.home", "24"},  {"site.asset_id", "T1"},
};
#define RIG_N (sizeof libgpiod_rig / sizeof libgpiod_rig[0])

static void test_libgpiod_contacts_and_event_need_their_lines(void)
{
    struct uwbd_override o[RIG_N + 6];
    memcpy(o, libgpiod_rig, sizeof libgpiod_rig);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(o, RIG_N), err); /* nothing on: no site line needed */

    o[RIG_N] = (struct uwbd_override){"contacts.enabled", "true"};
    expect_refused(o, RIG_N + 1, "key `contacts.watch.line`: missing: required with the libgpiod backend");
    o[RIG_N + 1] = (struct uwbd_override){"contacts.watch.line", "5"};
    o[RIG_N + 2] = (struct uwbd_override){"contacts.alarm.line", "\"ALARM_RELAY\""};
    expect_refused(o, RIG_N + 3, "key `contacts.fault.line`: missing");
    o[RIG_N + 3] = (struct uwbd_override){"contacts.fault.line", "6"};
    o[RIG_N + 4] = (struct uwbd_override){"contacts.fault.active_low", "true"};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(o, RIG_N + 5), err);
    TEST_ASSERT_EQUAL_INT(5, cfg.site.io.offset[UWB_LINE_WATCH]);
    TEST_ASSERT_EQUAL_INT(-1, cfg.site.io.offset[UWB_LINE_ALARM]);
    TEST_ASSERT_EQUAL_STRING("ALARM_RELAY", cfg.site.io.name[UWB_LINE_ALARM]);
    TEST_ASSERT_TRUE(cfg.site.io.active_low[UWB_LINE_FAULT]);
    TEST_ASSERT_FALSE(cfg.site.io.active_low[UWB_LINE_WATCH]);
    TEST_ASSERT_EQUAL_STRING("gpiochip0", cfg.site.io.chip);
    TEST_ASSERT_EQUAL_INT(17, cfg.rig.gpio.offset[UWB_LINE_TRIGGER]); /* the rig's lines stay the rig's */

    o[RIG_N + 5] = (struct uwbd_override){"event.enabled", "true"};
    expect_refused(o, RIG_N + 6,
                   "key `event.line`: missing: required with the libgpiod backend when event.enabled");

    struct uwbd_override endpoint[RIG_N + 1];
    memcpy(endpoint, libgpiod_rig, sizeof libgpiod_rig);
    endpoint[RIG_N] = (struct uwbd_override){"gpio.site_endpoint", "\"unix:x\""};
    expect_refused(endpoint, RIG_N + 1,
                   "key `gpio.site_endpoint`: only the emulated backend uses an endpoint");
}

static void test_event_keys(void)
{
    struct uwbd_override ok[] = {{"site.asset_id", "T1"},
                                 {"event.enabled", "true"},
                                 {"gpio.site_endpoint", "\"unix:run/site.sock\""},
                                 {"event.debounce_ms", "20"},
                                 {"event.min_interval_s", "30"}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(ok, 5), err);
    TEST_ASSERT_EQUAL_DOUBLE(0.020, cfg.site.event_debounce_s);
    TEST_ASSERT_EQUAL_DOUBLE(30.0, cfg.site.event_min_interval_s);
    TEST_ASSERT_EQUAL_HEX(UWB_GPIO_LINE_BIT(UWB_LINE_EVENT), cfg.site.io.lines);

    struct uwbd_override slow_poll[] = {{"site.asset_id", "T1"},
                                        {"event.enabled", "true"},
                                        {"gpio.site_endpoint", "\"unix:run/site.sock\""},
                                        {"event.debounce_ms", "5"},
                                        {"event.poll_ms", "20"}};
    expect_refused(slow_poll, 5, "key `event.poll_ms`: 20 ms is above event.debounce_ms (5 ms)");
    struct uwbd_override negative[] = {{"event.debounce_ms", "-1"}};
    expect_refused(negative, 1, "key `event.debounce_ms`");
}

static void test_prometheus_needs_a_prom_file(void)
{
    struct uwbd_override no_id[] = {{"prometheus.enabled", "true"},
                                    {"prometheus.textfile", "\"/tmp/uwbd.prom\""}};
    expect_refused(no_id, 2,
                   "key `site.asset_id`: missing: required once an integration is on (prometheus.enabled)");
    struct uwbd_override none[] = {{"site.asset_id", "T1"}, {"prometheus.enabled", "true"}};
    expect_refused(none, 2, "key `prometheus.textfile`: missing: required when prometheus.enabled is true");
    struct uwbd_override txt[] = {{"site.asset_id", "T1"},
                                  {"prometheus.enabled", "true"},
                                  {"prometheus.textfile", "\"/var/lib/prometheus/node-exporter/uwbd.txt\""}};
    expect_refused(txt, 3,
                   "key `prometheus.textfile`: \"/var/lib/prometheus/node-exporter/uwbd.txt\": the name must "
                   "end in .prom");
    struct uwbd_override bare[] = {
        {"site.asset_id", "T1"}, {"prometheus.enabled", "true"}, {"prometheus.textfile", "\"/x/.prom\""}};
    expect_refused(bare, 3, "key `prometheus.textfile`");
    struct uwbd_override ok[] = {{"site.asset_id", "T1"},
                                 {"prometheus.enabled", "true"},
                                 {"prometheus.textfile", "\"run/uwbd.prom\""}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(ok, 3), err);
    TEST_ASSERT_EQUAL_STRING("run/uwbd.prom", cfg.site.prometheus_textfile);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0, cfg.site.io.lines, "the textfile opens no line");
}

static void test_mqtt_needs_endpoint_and_a_private_password(void)
{
    struct uwbd_override none[] = {{"site.asset_id", "T1"}, {"mqtt.enabled", "true"}};
    expect_refused(none, 2, "key `mqtt.endpoint`: missing: required when mqtt.enabled is true");
    struct uwbd_override unix_ep[] = {
        {"site.asset_id", "T1"}, {"mqtt.enabled", "true"}, {"mqtt.endpoint", "\"unix:/run/broker.sock\""}};
    expect_refused(unix_ep, 3, "key `mqtt.endpoint`: \"unix:/run/broker.sock\": the broker is tcp:HOST:PORT");
    struct uwbd_override no_id[] = {{"mqtt.enabled", "true"}, {"mqtt.endpoint", "\"tcp:127.0.0.1:1883\""}};
    expect_refused(no_id, 2,
                   "key `site.asset_id`: missing: required once an integration is on (mqtt.enabled)");
    struct uwbd_override user[] = {{"site.asset_id", "T1"},
                                   {"mqtt.enabled", "true"},
                                   {"mqtt.endpoint", "\"tcp:127.0.0.1:1883\""},
                                   {"mqtt.username", "uwbd"}};
    expect_refused(user, 4, "key `mqtt.password_file`: missing: required with mqtt.username");

    char dir[256], secret[300], open_file[300];
    scratch_scratch_dir(dir, sizeof dir, "mqtt-pw");
    snprintf(secret, sizeof secret, "\"%s/secret\"", dir);
    snprintf(open_file, sizeof open_file, "\"%s/open\"", dir);
    char path[300];
    snprintf(path, sizeof path, "%s/secret", dir);
    scratch_spit(path, "pw\n");
    chmod(path, 0600);
    snprintf(path, sizeof path, "%s/open", dir);
    scratch_spit(path, "pw\n");
    chmod(path, 0644);
    struct uwbd_override open_pw[] = {{"site.asset_id", "T1"},
                                      {"mqtt.enabled", "true"},
                                      {"mqtt.endpoint", "\"tcp:127.0.0.1:1883\""},
                                      {"mqtt.username", "uwbd"},
                                      {"mqtt.password_file", open_file}};
    expect_refused(open_pw, 5, "is readable by others (mode 0644)");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `mqtt.password_file`"), err);
    struct uwbd_override ok[] = {{"site.asset_id", "T1"},
                                 {"mqtt.enabled", "true"},
                                 {"mqtt.endpoint", "\"tcp:127.0.0.1:1883\""},
                                 {"mqtt.username", "uwbd"},
                                 {"mqtt.password_file", secret}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(ok, 5), err);
    TEST_ASSERT_EQUAL_STRING("uwbd", cfg.site.mqtt_topic_prefix);
    TEST_ASSERT_EQUAL_INT(1000, cfg.site.mqtt_queue_max);
    struct uwbd_override cert[] = {{"site.asset_id", "T1"},
                                   {"mqtt.enabled", "true"},
                                   {"mqtt.endpoint", "\"tcp:127.0.0.1:8883\""},
                                   {"mqtt.cert_file", "\"/x.pem\""}};
    expect_refused(cert, 4, "key `mqtt.key_file`: missing: a client certificate needs both");
    struct uwbd_override wild[] = {{"site.asset_id", "T1"},
                                   {"mqtt.enabled", "true"},
                                   {"mqtt.endpoint", "\"tcp:127.0.0.1:1883\""},
                                   {"mqtt.topic_prefix", "\"plant/#\""}};
    expect_refused(wild, 4, "key `mqtt.topic_prefix`");
    scratch_remove_tree(dir);
}

/* issue 27, break 8: a TLS file that is missing, not a file or not
 * readable passed --check-config; the start then failed in libmosquitto
 * with "Invalid function arguments provided." and no file named. */
static void test_mqtt_tls_files_must_be_readable_files(void)
{
    char dir[256], missing[320], dir_value[320], ca[300], ca_value[320], key[300], key_value[320];
    scratch_scratch_dir(dir, sizeof dir, "mqtt-tls");
    snprintf(missing, sizeof missing, "\"%s/no-such-ca.crt\"", dir);
    snprintf(dir_value, sizeof dir_value, "\"%s\"", dir);
    snprintf(ca, sizeof ca, "%s/ca.crt", dir);
    scratch_spit(ca, "-----BEGIN CERTIFICATE-----\n");
    snprintf(ca_value, sizeof ca_value, "\"%s\"", ca);
    snprintf(key, sizeof key, "%s/client.key", dir);
    scratch_spit(key, "key\n");
    chmod(key, 0600);
    snprintf(key_value, sizeof key_value, "\"%s\"", key);

    struct uwbd_override no_ca[] = {{"site.asset_id", "T1"},
                                    {"mqtt.enabled", "true"},
                                    {"mqtt.endpoint", "\"tcp:127.0.0.1:8883\""},
                                    {"mqtt.ca_file", missing}};
    expect_refused(no_ca, 4, "key `mqtt.ca_file`");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no-such-ca.crt\": No such file or directory"), err);
    struct uwbd_override ca_dir[] = {{"site.asset_id", "T1"},
                                     {"mqtt.enabled", "true"},
                                     {"mqtt.endpoint", "\"tcp:127.0.0.1:8883\""},
                                     {"mqtt.ca_file", dir_value}};
    expect_refused(ca_dir, 4, "key `mqtt.ca_file`");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is not a regular file"), err);
    struct uwbd_override no_cert[] = {
        {"site.asset_id", "T1"},    {"mqtt.enabled", "true"},    {"mqtt.endpoint", "\"tcp:127.0.0.1:8883\""},
        {"mqtt.ca_file", ca_value}, {"mqtt.cert_file", missing}, {"mqtt.key_file", key_value}};
    expect_refused(no_cert, 6, "key `mqtt.cert_file`");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "No such file or directory"), err);
    struct uwbd_override ok[] = {
        {"site.asset_id", "T1"},    {"mqtt.enabled", "true"},     {"mqtt.endpoint", "\"tcp:127.0.0.1:8883\""},
        {"mqtt.ca_file", ca_value}, {"mqtt.cert_file", ca_value}, {"mqtt.key_file", key_value}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, parse_with(ok, 6), err);
    if (geteuid() != 0) { /* root reads a mode-000 file */
        chmod(ca, 0);
        expect_refused(ok, 6, "key `mqtt.ca_file`");
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "Permission denied"), err);
    }
    scratch_remove_tree(dir);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_integration_is_off_by_default);
    RUN_TEST(test_asset_id_is_checked_and_kept);
    RUN_TEST(test_an_integration_needs_the_asset_id);
    RUN_TEST(test_emulated_contacts_need_the_site_endpoint);
    RUN_TEST(test_libgpiod_contacts_and_event_need_their_lines);
    RUN_TEST(test_event_keys);
    RUN_TEST(test_prometheus_needs_a_prom_file);
    RUN_TEST(test_mqtt_needs_endpoint_and_a_private_password);
    RUN_TEST(test_mqtt_tls_files_must_be_readable_files);
    return UNITY_END();
}
