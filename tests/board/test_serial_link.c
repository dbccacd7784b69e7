/* The link layer's serial: endpoint (libserialport, src/hw/) on a real
 * kernel UART driver: the 16550 behind qemu's pci-serial inside the
 * emulated board. The host end of the UART's socket runs
 * `unix_peer invert` (tests/e2e/helpers), which answers every byte with its
 * bitwise inverse, so a reply proves the bytes went out through the UART
 * and came back in, and a wrong tty mode (echo, CR/LF mapping, software
 * flow control eating 0x11/0x13) shows up as a wrong byte.
 * UWB_BOARD_SERIAL names the tty (default /dev/ttyS0). */
#include "unity.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>

#include "uwb/link.h"

#define REPLY_TIMEOUT_MS 10000

static char err[512];
static char endpoint[UWB_ENDPOINT_MAX];
static const char *device;

void setUp(void)
{
    device = getenv("UWB_BOARD_SERIAL");
    if (!device || !*device)
        device = "/dev/ttyS0";
    snprintf(endpoint, sizeof endpoint, "serial:%s?baud=115200", device);
}

void tearDown(void)
{
}

static struct uwb_link *open_port(void)
{
    struct uwb_link *link = NULL;
    err[0] = '\0';
    int rc = uwb_link_open(endpoint, &link, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, rc, err);
    TEST_ASSERT_NOT_NULL(link);
    return link;
}

/* Sends `len` bytes and checks the peer's inverted reply, byte for byte. */
static void round_trip(struct uwb_link *link, const uint8_t *out, size_t len)
{
    uint8_t *back = malloc(len);
    TEST_ASSERT_NOT_NULL(back);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK,
                                  uwb_link_write_all(link, out, len, REPLY_TIMEOUT_MS, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        UWB_LINK_OK, uwb_link_read_exact(link, back, len, REPLY_TIMEOUT_MS, err, sizeof err), err);
    for (size_t i = 0; i < len; i++) {
        if ((uint8_t)(back[i] ^ out[i]) != 0xff) {
            char where[96];
            snprintf(where, sizeof where, "byte %zu: sent 0x%02x, got 0x%02x back (want 0x%02x)", i, out[i],
                     back[i], (uint8_t)~out[i]);
            TEST_FAIL_MESSAGE(where);
        }
    }
    free(back);
}

static void test_every_byte_value_crosses_the_uart_unchanged(void)
{
    struct uwb_link *link = open_port();
    TEST_ASSERT_TRUE(uwb_link_fd(link) >= 0);
    uint8_t all[256];
    for (int i = 0; i < 256; i++)
        all[i] = (uint8_t)i; /* includes NUL, XON/XOFF, CR, LF, ^C, ^D */
    round_trip(link, all, sizeof all);
    uwb_link_close(link);
}

/* Bigger than the 16550's FIFO and the tty buffers, in one write. */
static void test_a_block_larger_than_the_buffers_round_trips(void)
{
    struct uwb_link *link = open_port();
    enum { LEN = 16384 };
    static uint8_t block[LEN];
    uint32_t x = 2463534242u; /* xorshift32: reproducible, not periodic in the block */
    for (size_t i = 0; i < LEN; i++) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        block[i] = (uint8_t)x;
    }
    round_trip(link, block, LEN);
    uwb_link_close(link);
}

/* A reopened port still works: close leaves nothing behind. */
static void test_port_reopens_after_close(void)
{
    for (int i = 0; i < 3; i++) {
        struct uwb_link *link = open_port();
        uint8_t hello[] = {'u', 'w', 'b', (uint8_t)i};
        round_trip(link, hello, sizeof hello);
        uwb_link_close(link);
    }
}

static void test_silent_peer_times_out(void)
{
    struct uwb_link *link = open_port();
    uint8_t byte;
    ssize_t n = uwb_link_read(link, &byte, 1, 300, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_ERR_TIMEOUT, (int)n, err);
    uwb_link_close(link);
}

/* Issue 43, break 5: the framing the endpoint names is the tty's (a Modbus
 * RTU at 19200 8E1, the serial line standard's default, or 8O1, 8N2), and
 * bytes cross the UART with it (the socket behind qemu's UART carries
 * bytes, not frames, so every framing round-trips). */
static void test_the_endpoints_parity_and_stop_bits_are_the_ttys(void)
{
    const struct {
        const char *options;
        int parenb, parodd, cstopb;
    } framings[] = {
        {"baud=19200", 0, 0, 0},
        {"baud=19200&parity=even", 1, 0, 0},
        {"baud=19200&parity=odd", 1, 1, 0},
        {"baud=19200&parity=none&stopbits=2", 0, 0, 1},
        {"baud=19200&parity=even&stopbits=2", 1, 0, 1},
    };
    for (size_t i = 0; i < sizeof framings / sizeof framings[0]; i++) {
        snprintf(endpoint, sizeof endpoint, "serial:%s?%s", device, framings[i].options);
        struct uwb_link *link = open_port();
        struct termios tio;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, tcgetattr(uwb_link_fd(link), &tio), endpoint);
        TEST_ASSERT_EQUAL_INT_MESSAGE(framings[i].parenb, !!(tio.c_cflag & PARENB), endpoint);
        TEST_ASSERT_EQUAL_INT_MESSAGE(framings[i].parodd, !!(tio.c_cflag & PARODD), endpoint);
        TEST_ASSERT_EQUAL_INT_MESSAGE(framings[i].cstopb, !!(tio.c_cflag & CSTOPB), endpoint);
        TEST_ASSERT_EQUAL_INT_MESSAGE(CS8, (int)(tio.c_cflag & CSIZE), endpoint);
        TEST_ASSERT_TRUE_MESSAGE(cfgetospeed(&tio) == B19200, endpoint);
        uint8_t frame[] = {0x07, 0x04, 0x00, 0x00, 0x00, 0x02, 0x71, 0xad}; /* an RTU request */
        round_trip(link, frame, sizeof frame);
        uwb_link_close(link);
    }
}

static void expect_open_error(const char *text, int want, const char *must_mention)
{
    struct uwb_link *link = NULL;
    err[0] = '\0';
    int rc = uwb_link_open(text, &link, err, sizeof err);
    printf("# open error (expected): %s\n", err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, rc, err);
    TEST_ASSERT_NULL(link);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, must_mention), err);
}

static void test_missing_port_is_an_open_error_naming_it(void)
{
    expect_open_error("serial:/dev/ttyUSB7?baud=921600", UWB_LINK_ERR_OPEN, "/dev/ttyUSB7");
}

/* The 8250 driver registers ttyS2 and ttyS3 with no UART behind them. */
static void test_tty_without_a_uart_is_an_open_error(void)
{
    expect_open_error("serial:/dev/ttyS3", UWB_LINK_ERR_OPEN, "/dev/ttyS3");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_byte_value_crosses_the_uart_unchanged);
    RUN_TEST(test_a_block_larger_than_the_buffers_round_trips);
    RUN_TEST(test_port_reopens_after_close);
    RUN_TEST(test_silent_peer_times_out);
    RUN_TEST(test_the_endpoints_parity_and_stop_bits_are_the_ttys);
    RUN_TEST(test_missing_port_is_an_open_error_naming_it);
    RUN_TEST(test_tty_without_a_uart_is_an_open_error);
    return UNITY_END();
}
