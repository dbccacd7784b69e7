/* A broker port nobody listens on: the link reports "Connection refused"
 * within about a second, with TLS (mqtt.ca_file) as without. Issue 43,
 * break 3: with TLS, libmosquitto's handshake took the refusal for "try
 * again" and the link said nothing for 10 s, then "no connection within
 * 10 s". The port is bound here and never listened on, so nobody else can
 * take it while the test runs (loopback only). */
#include "scratch_support.h"
#include "unity.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "integrations/mqtt_publisher.h"

/* A self-signed CA (EC P-256, valid to 2126): libmosquitto loads it before
 * it connects; no broker ever presents a certificate here. */
static const char TEST_CA_PEM[] = "-----BEGIN CERTIFICATE-----\n"
                                  "MIIBjzCCATWgAwIBAgIUAybXlFqGXykEnSo0AKqjR4P/oSMwCgYIKoZIzj0EAwIw\n"
                                  "HDEaMBgGA1UEAwwRdXdiZCB1bml0IHRlc3QgQ0EwIBcNMjYxMjA3MDUyMTM5WhgP\n"
                                  "MjEyNjExMTMwNTIxMzlaMBwxGjAYBgNVBAMMEXV3YmQgdW5pdCB0ZXN0IENBMFkw\n"
                                  "EwYHKoZIzj0CAQYIKoZIzj0DAQcDQgAETVzbiz/k0e4JEy/Fl1TO3048xDQ/n+1O\n"
                                  "W+TmJ5sGrPEwLuP15EX0PqWFhVnjoADxxeITOVxzhVZrEaCNB/0amqNTMFEwHQYD\n"
                                  "VR0OBBYEFG7mE6lEFvakCCReoI/JaKZ50cCrMB8GA1UdIwQYMBaAFG7mE6lEFvak\n"
                                  "CCReoI/JaKZ50cCrMA8GA1UdEwEB/wQFMAMBAf8wCgYIKoZIzj0EAwIDSAAwRQIh\n"
                                  "ALPHwZto+fb26u7ouxHg7cqztsRaSVbWorBxgDmbPUZ1AiBYGHHx7MZ1Dk+pniIE\n"
                                  "gJpT0TtkHDWOI3qG3cVAb7Zqag==\n"
                                  "-----END CERTIFICATE-----\n";

/* "About a second": the plain link reports within one loop (0.1 s). */
#define REPORT_WITHIN_S 2.0

static char dir[256], err[1024];
static struct uwbd_site_config cfg;
static int closed_port_fd = -1;

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "mqtt-refused");
    memset(&cfg, 0, sizeof cfg);
    snprintf(cfg.asset_id, sizeof cfg.asset_id, "t1");
    cfg.mqtt_enabled = 1;
    snprintf(cfg.mqtt_topic_prefix, sizeof cfg.mqtt_topic_prefix, "uwb");
    cfg.mqtt_queue_max = 10;
    cfg.mqtt_reconnect_max_s = 1;
    /* Bound, not listening: a connection to it is refused. */
    closed_port_fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    TEST_ASSERT_TRUE(closed_port_fd >= 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    TEST_ASSERT_EQUAL_INT(0, bind(closed_port_fd, (struct sockaddr *)&a, sizeof a));
    socklen_t len = sizeof a;
    TEST_ASSERT_EQUAL_INT(0, getsockname(closed_port_fd, (struct sockaddr *)&a, &len));
    snprintf(cfg.mqtt_endpoint, sizeof cfg.mqtt_endpoint, "tcp:127.0.0.1:%d", ntohs(a.sin_port));
}

void tearDown(void)
{
    close(closed_port_fd);
    scratch_remove_tree(dir);
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* Opens the publisher and waits (bounded) for its link to fail; the
 * reason into `reason`, the seconds it took returned. */
static double seconds_until_failing(char *reason, size_t n)
{
    struct uwbd_mqtt *m = NULL;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_mqtt_open(&m, &cfg, dir, err, sizeof err), err);
    double start = now_s(), took = -1;
    struct uwbd_mqtt_link link;
    while (now_s() - start < 3 * REPORT_WITHIN_S) {
        uwbd_mqtt_link(m, &link);
        if (strcmp(link.state, "failing") == 0) {
            took = now_s() - start;
            snprintf(reason, n, "%s", link.reason);
            break;
        }
        nanosleep(&(struct timespec){.tv_nsec = 20000000L}, NULL);
    }
    uwbd_mqtt_close(m);
    TEST_ASSERT_TRUE_MESSAGE(took >= 0, "the link did not fail within 6 s");
    return took;
}

static void test_a_refused_plain_connection_is_reported_at_once(void)
{
    char reason[512];
    double took = seconds_until_failing(reason, sizeof reason);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reason, "Connection refused"), reason);
    TEST_ASSERT_TRUE_MESSAGE(took < REPORT_WITHIN_S, reason);
}

static void test_a_refused_tls_connection_is_reported_the_same_at_once(void)
{
    char plain[512], tls[512], ca[300];
    seconds_until_failing(plain, sizeof plain);
    snprintf(ca, sizeof ca, "%s/ca.pem", dir);
    scratch_spit(ca, TEST_CA_PEM);
    snprintf(cfg.mqtt_ca_file, sizeof cfg.mqtt_ca_file, "%s", ca);
    double took = seconds_until_failing(tls, sizeof tls);
    TEST_ASSERT_EQUAL_STRING(plain, tls);
    char message[600];
    snprintf(message, sizeof message, "%.2f s: %s", took, tls);
    TEST_ASSERT_TRUE_MESSAGE(took < REPORT_WITHIN_S, message);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_refused_plain_connection_is_reported_at_once);
    RUN_TEST(test_a_refused_tls_connection_is_reported_the_same_at_once);
    return UNITY_END();
}
