/* uwbd_mqtt_open failing half-way (after the eventfd, the mosquitto handle
 * and the queue are held): it names the input at fault and leaves nothing
 * open, so a reload that fails again and again leaks no descriptors (and,
 * under ASan, no memory). No broker is needed: each open fails before its
 * network thread starts. */
#include "scratch_support.h"
#include "unity.h"

#include <dirent.h>
#include <stdio.h>
#include <string.h>

#include "integrations/mqtt_publisher.h"

static char dir[256], err[1024];
static struct uwbd_site_config cfg;

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "mqtt-open");
    memset(&cfg, 0, sizeof cfg);
    snprintf(cfg.asset_id, sizeof cfg.asset_id, "t1");
    cfg.mqtt_enabled = 1;
    snprintf(cfg.mqtt_endpoint, sizeof cfg.mqtt_endpoint, "tcp:127.0.0.1:1");
    snprintf(cfg.mqtt_topic_prefix, sizeof cfg.mqtt_topic_prefix, "uwb");
    cfg.mqtt_queue_max = 10;
    cfg.mqtt_reconnect_max_s = 1;
    cfg.mqtt_commands = 1; /* an eventfd, held before the mosquitto handle */
}

void tearDown(void)
{
    scratch_remove_tree(dir);
}

static int open_fds(void)
{
    DIR *d = opendir("/proc/self/fd");
    TEST_ASSERT_NOT_NULL(d);
    int n = 0;
    while (readdir(d))
        n++;
    closedir(d);
    return n;
}

/* Opens three times, each must fail naming `want`; the first may leave
 * libmosquitto's process-wide state (OpenSSL's random device), the
 * next two nothing at all. */
static void assert_fails_cleanly(const char *want)
{
    struct uwbd_mqtt *m = (struct uwbd_mqtt *)&cfg; /* not NULL: open must clear it */
    TEST_ASSERT_EQUAL_INT(-1, uwbd_mqtt_open(&m, &cfg, dir, err, sizeof err));
    TEST_ASSERT_NULL(m);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, want), err);
    int before = open_fds();
    for (int i = 0; i < 2; i++) {
        TEST_ASSERT_EQUAL_INT(-1, uwbd_mqtt_open(&m, &cfg, dir, err, sizeof err));
        TEST_ASSERT_NULL(m);
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(before, open_fds(), "a failed open left descriptors open");
}

static void test_a_missing_ca_file_is_named(void)
{
    snprintf(cfg.mqtt_ca_file, sizeof cfg.mqtt_ca_file, "%s/gone-ca.pem", dir);
    assert_fails_cleanly("mqtt.ca_file");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, cfg.mqtt_ca_file), err);
}

static void test_a_missing_client_key_is_named(void)
{
    char ca[300], cert[300];
    snprintf(ca, sizeof ca, "%s/ca.pem", dir);
    snprintf(cert, sizeof cert, "%s/client.pem", dir);
    scratch_spit(ca, "not a certificate, but there\n");
    scratch_spit(cert, "not a certificate, but there\n");
    snprintf(cfg.mqtt_ca_file, sizeof cfg.mqtt_ca_file, "%s", ca);
    snprintf(cfg.mqtt_cert_file, sizeof cfg.mqtt_cert_file, "%s", cert);
    snprintf(cfg.mqtt_key_file, sizeof cfg.mqtt_key_file, "%s/gone-key.pem", dir);
    assert_fails_cleanly("mqtt.key_file");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, cfg.mqtt_key_file), err);
}

static void test_a_missing_password_file_is_named(void)
{
    snprintf(cfg.mqtt_username, sizeof cfg.mqtt_username, "uwbd");
    snprintf(cfg.mqtt_password_file, sizeof cfg.mqtt_password_file, "%s/gone-password", dir);
    assert_fails_cleanly(cfg.mqtt_password_file);
}

static void test_a_queue_directory_that_cannot_be_made_is_named(void)
{
    char state[300];
    snprintf(state, sizeof state, "%s/no-such-state-dir", dir);
    struct uwbd_mqtt *m = NULL;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_mqtt_open(&m, &cfg, state, err, sizeof err));
    int before = open_fds();
    TEST_ASSERT_EQUAL_INT(-1, uwbd_mqtt_open(&m, &cfg, state, err, sizeof err));
    TEST_ASSERT_NULL(m);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no-such-state-dir/mqtt-queue"), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(before, open_fds(), "a failed open left descriptors open");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_missing_ca_file_is_named);
    RUN_TEST(test_a_missing_client_key_is_named);
    RUN_TEST(test_a_missing_password_file_is_named);
    RUN_TEST(test_a_queue_directory_that_cannot_be_made_is_named);
    return UNITY_END();
}
