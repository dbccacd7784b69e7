/* Endpoint strings: what is accepted, and how the rest is refused. */
#include <string.h>

#include "unity.h"
#include "uwb/link.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static struct uwb_endpoint ep;
static char err[512];

static void parse_ok(const char *text)
{
    int rc = uwb_endpoint_parse(text, &ep, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, rc, err);
}

/* Refused, and the message quotes the endpoint and mentions `problem`. */
static void parse_bad(const char *text, const char *problem)
{
    err[0] = '\0';
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_ERR_ENDPOINT, uwb_endpoint_parse(text, &ep, err, sizeof err),
                                  text);
    char quoted[300];
    snprintf(quoted, sizeof quoted, "'%s'", text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, quoted), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, problem), err);
}

static void test_serial_with_and_without_baud(void)
{
    parse_ok("serial:/dev/ttyUSB0?baud=921600");
    TEST_ASSERT_EQUAL_INT(UWB_ENDPOINT_SERIAL, ep.kind);
    TEST_ASSERT_EQUAL_STRING("/dev/ttyUSB0", ep.path);
    TEST_ASSERT_EQUAL_INT(921600, ep.baud);
    parse_ok("serial:/dev/ttyAMA1");
    TEST_ASSERT_EQUAL_STRING("/dev/ttyAMA1", ep.path);
    TEST_ASSERT_EQUAL_INT(UWB_SERIAL_DEFAULT_BAUD, ep.baud);
}

static void test_tcp_names_addresses_and_ipv6(void)
{
    parse_ok("tcp:digitiser.local:2001");
    TEST_ASSERT_EQUAL_INT(UWB_ENDPOINT_TCP, ep.kind);
    TEST_ASSERT_EQUAL_STRING("digitiser.local", ep.host);
    TEST_ASSERT_EQUAL_STRING("2001", ep.port);
    parse_ok("tcp:127.0.0.1:65535");
    TEST_ASSERT_EQUAL_STRING("127.0.0.1", ep.host);
    parse_ok("tcp:[::1]:7000");
    TEST_ASSERT_EQUAL_STRING("::1", ep.host);
    TEST_ASSERT_EQUAL_STRING("7000", ep.port);
}

static void test_unix_path(void)
{
    parse_ok("unix:/run/uwbemu/gpio.sock");
    TEST_ASSERT_EQUAL_INT(UWB_ENDPOINT_UNIX, ep.kind);
    TEST_ASSERT_EQUAL_STRING("/run/uwbemu/gpio.sock", ep.path);
    parse_ok("unix:relative.sock");
    TEST_ASSERT_EQUAL_STRING("relative.sock", ep.path);
}

static void test_bad_strings_are_named_and_explained(void)
{
    parse_bad("", "empty");
    parse_bad("/dev/ttyUSB0", "no scheme");
    parse_bad("http://x:80", "unknown scheme 'http'");
    parse_bad("serial:", "needs a device path");
    parse_bad("serial:?baud=9600", "needs a device path");
    parse_bad("serial:/dev/ttyS0?baud=", "baud must be");
    parse_bad("serial:/dev/ttyS0?baud=fast", "baud must be");
    parse_bad("serial:/dev/ttyS0?baud=-9600", "baud must be");
    parse_bad("serial:/dev/ttyS0?parity=even", "unknown serial option 'parity=even'");
    parse_bad("tcp:host", "HOST:PORT");
    parse_bad("tcp::2000", "host is empty");
    parse_bad("tcp:host:", "port is empty");
    parse_bad("tcp:host:0", "1 to 65535");
    parse_bad("tcp:host:65536", "1 to 65535");
    parse_bad("tcp:host:20x", "1 to 65535");
    parse_bad("tcp:::1:7000", "[brackets]");
    parse_bad("tcp:[::1:7000", "closing ']'");
    parse_bad("unix:", "needs a socket path");
    char longpath[200] = "unix:/";
    memset(longpath + 6, 'a', 150);
    longpath[156] = '\0';
    parse_bad(longpath, "longer than");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_serial_with_and_without_baud);
    RUN_TEST(test_tcp_names_addresses_and_ipv6);
    RUN_TEST(test_unix_path);
    RUN_TEST(test_bad_strings_are_named_and_explained);
    return UNITY_END();
}
