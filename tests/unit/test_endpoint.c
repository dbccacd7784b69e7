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

/* Issue 43, break 5: the Modbus serial line's framing (its standard's
 * default is 8E1) in the endpoint; without it, 8N1 as before. */
static void test_serial_parity_and_stop_bits(void)
{
    parse_ok("serial:/dev/ttyUSB0?baud=19200");
    TEST_ASSERT_EQUAL_INT('N', ep.parity);
    TEST_ASSERT_EQUAL_INT(1, ep.stop_bits);
    const struct {
        const char *text;
        char parity;
        int stop_bits;
    } cases[] = {
        {"serial:/dev/ttyUSB0?baud=19200&parity=even", 'E', 1},
        {"serial:/dev/ttyUSB0?baud=19200&parity=odd", 'O', 1},
        {"serial:/dev/ttyUSB0?baud=19200&parity=none", 'N', 1},
        {"serial:/dev/ttyUSB0?baud=19200&parity=none&stopbits=2", 'N', 2},
        {"serial:/dev/ttyUSB0?parity=even&stopbits=2&baud=19200", 'E', 2},
        {"serial:/dev/ttyUSB0?stopbits=1&parity=odd&baud=19200", 'O', 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        parse_ok(cases[i].text);
        TEST_ASSERT_EQUAL_STRING_MESSAGE("/dev/ttyUSB0", ep.path, cases[i].text);
        TEST_ASSERT_EQUAL_INT_MESSAGE(19200, ep.baud, cases[i].text);
        TEST_ASSERT_EQUAL_INT_MESSAGE(cases[i].parity, ep.parity, cases[i].text);
        TEST_ASSERT_EQUAL_INT_MESSAGE(cases[i].stop_bits, ep.stop_bits, cases[i].text);
    }
    parse_ok("serial:/dev/ttyS1?parity=even");
    TEST_ASSERT_EQUAL_INT(UWB_SERIAL_DEFAULT_BAUD, ep.baud);
    TEST_ASSERT_EQUAL_INT('E', ep.parity);
    parse_bad("serial:/dev/ttyS0?parity=mark", "parity must be none, even or odd");
    parse_bad("serial:/dev/ttyS0?parity=", "parity must be none, even or odd");
    parse_bad("serial:/dev/ttyS0?stopbits=3", "stopbits must be 1 or 2");
    parse_bad("serial:/dev/ttyS0?stopbits=1.5", "stopbits must be 1 or 2");
    parse_bad("serial:/dev/ttyS0?baud=9600&baud=19200", "baud given twice");
    parse_bad("serial:/dev/ttyS0?parity=even&parity=odd", "parity given twice");
    parse_bad("serial:/dev/ttyS0?baud=9600&", "empty serial option");
    parse_bad("serial:/dev/ttyS0?baud=9600&&parity=even", "empty serial option");
    parse_bad("serial:/dev/ttyS0?baud=9600&flow=rtscts", "unknown serial option 'flow=rtscts'");
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
    parse_bad("serial:/dev/ttyS0?speed=9600", "unknown serial option 'speed=9600'");
    parse_bad("serial:/dev/ttyS0?baud=9600x", "baud must be");
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
    RUN_TEST(test_serial_parity_and_stop_bits);
    RUN_TEST(test_tcp_names_addresses_and_ipv6);
    RUN_TEST(test_unix_path);
    RUN_TEST(test_bad_strings_are_named_and_explained);
    return UNITY_END();
}
