/* The "emulated" GPIO backend: the handle's lines as text lines over a
 * uwb_link to the emulated board (unix:, tcp: or serial:), protocol in
 * board/emulated-gpio.md. Values are logical (ENABLE 1 = energised, HOME 1 =
 * at home): active-low wiring is a property of real pins only.
 *
 * `set` is not answered, so a step costs one write, not a round trip; a
 * `get` is answered after everything sent before it, which keeps the two
 * ends in step. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpio/gpio_backend.h"
#include "uwb/link.h"

#define PROTOCOL "uwb-gpio/1"
/* Long enough for a board that is busy computing a trace under emulation. */
#define REPLY_TIMEOUT_MS 10000
#define WRITE_TIMEOUT_MS 5000

struct emulated {
    struct uwb_link *link;
    char buf[1024]; /* received bytes not yet consumed: one line of up to 1023 bytes and its '\n' */
    size_t len;
};

/* Reads one reply line (without its '\n', nor a '\r' before it: the
 * protocol allows either ending, board/emulated-gpio.md) into line. */
static int read_line(struct uwb_gpio *gpio, char *line, size_t linelen, char *err, size_t errlen)
{
    struct emulated *em = gpio->state;
    for (;;) {
        char *nl = memchr(em->buf, '\n', em->len);
        if (nl) {
            size_t n = (size_t)(nl - em->buf);
            size_t text = n > 0 && em->buf[n - 1] == '\r' ? n - 1 : n;
            snprintf(line, linelen, "%.*s", (int)text, em->buf);
            memmove(em->buf, nl + 1, em->len - n - 1);
            em->len -= n + 1;
            return UWB_GPIO_OK;
        }
        if (em->len == sizeof em->buf) {
            snprintf(err, errlen, "emulated GPIO at %s: reply line longer than %zu bytes", gpio->cfg.endpoint,
                     sizeof em->buf);
            return UWB_GPIO_ERR_IO;
        }
        char why[256];
        ssize_t got = uwb_link_read(em->link, em->buf + em->len, sizeof em->buf - em->len, REPLY_TIMEOUT_MS,
                                    why, sizeof why);
        if (got < 0) {
            snprintf(err, errlen, "emulated GPIO: %s", why);
            return UWB_GPIO_ERR_IO;
        }
        em->len += (size_t)got;
    }
}

static int send_text(struct uwb_gpio *gpio, const char *text, char *err, size_t errlen)
{
    struct emulated *em = gpio->state;
    char why[256];
    if (uwb_link_write_all(em->link, text, strlen(text), WRITE_TIMEOUT_MS, why, sizeof why) != UWB_LINK_OK) {
        snprintf(err, errlen, "emulated GPIO: %s", why);
        return UWB_GPIO_ERR_IO;
    }
    return UWB_GPIO_OK;
}

/* Drives the handle's outputs low (pulser idle, motor off, contacts
 * de-energised); stops at the first failure, as a link that failed once
 * would only time out again. */
static int drive_outputs_low(struct uwb_gpio *gpio, char *err, size_t errlen)
{
    char text[64];
    int rc = UWB_GPIO_OK;
    for (int line = 0; rc == UWB_GPIO_OK && line < UWB_LINE_COUNT; line++) {
        if (!(gpio->cfg.lines & UWB_GPIO_LINE_BIT(line)) || uwb_gpio_line_is_input(line))
            continue;
        snprintf(text, sizeof text, "set %s 0\n", uwb_gpio_line_name(line));
        rc = send_text(gpio, text, err, errlen);
    }
    return rc;
}

static void emulated_close(struct uwb_gpio *gpio)
{
    struct emulated *em = gpio->state;
    if (!em)
        return;
    if (em->link) {
        /* Leave the board's outputs low, as a released real line would. */
        char ignored[512];
        drive_outputs_low(gpio, ignored, sizeof ignored);
        uwb_link_close(em->link);
    }
    free(em);
    gpio->state = NULL;
}

/* The protocol greeting: tells a wrong endpoint (another service, another
 * protocol version) from the emulated board's GPIO. */
static int say_hello(struct uwb_gpio *gpio, const char *endpoint, char *err, size_t errlen)
{
    char line[256];
    int rc = send_text(gpio, "hello " PROTOCOL "\n", err, errlen);
    if (rc == UWB_GPIO_OK)
        rc = read_line(gpio, line, sizeof line, err, errlen);
    if (rc != UWB_GPIO_OK) {
        char inner[512];
        snprintf(inner, sizeof inner, "%s", err);
        snprintf(err, errlen, "%s (no hello from %s: is this the emulated board's GPIO endpoint?)", inner,
                 endpoint);
        return UWB_GPIO_ERR_CHIP;
    }
    if (strncmp(line, "ok " PROTOCOL, strlen("ok " PROTOCOL)) != 0) {
        snprintf(err, errlen,
                 "emulated GPIO at %s: answered '%.80s' to hello, not 'ok " PROTOCOL "' "
                 "(is this the emulated board's GPIO endpoint?)",
                 endpoint, line);
        return UWB_GPIO_ERR_CHIP;
    }
    return UWB_GPIO_OK;
}

static int emulated_open(struct uwb_gpio *gpio, const struct uwb_gpio_config *cfg, char *err, size_t errlen)
{
    if (!cfg->endpoint[0]) {
        snprintf(err, errlen,
                 "emulated GPIO: no endpoint configured (unix:PATH, tcp:HOST:PORT or serial:DEV)");
        return UWB_GPIO_ERR_CONFIG;
    }
    struct emulated *em = calloc(1, sizeof *em);
    if (!em) {
        snprintf(err, errlen, "emulated GPIO: out of memory");
        return UWB_GPIO_ERR_CONFIG;
    }
    gpio->state = em;
    char why[512];
    int rc = uwb_link_open(cfg->endpoint, &em->link, why, sizeof why);
    if (rc != UWB_LINK_OK) {
        snprintf(err, errlen, "emulated GPIO: %s", why);
        rc = rc == UWB_LINK_ERR_ENDPOINT ? UWB_GPIO_ERR_CONFIG : UWB_GPIO_ERR_CHIP;
    } else {
        rc = say_hello(gpio, cfg->endpoint, err, errlen);
        if (rc == UWB_GPIO_OK)
            rc = drive_outputs_low(gpio, err, errlen);
    }
    if (rc != UWB_GPIO_OK) {
        uwb_link_close(em->link); /* NULL when the link did not open */
        free(em);
        gpio->state = NULL;
    }
    return rc;
}

static int emulated_set(struct uwb_gpio *gpio, enum uwb_gpio_line line, int value, char *err, size_t errlen)
{
    char text[64];
    snprintf(text, sizeof text, "set %s %d\n", uwb_gpio_line_name(line), value);
    return send_text(gpio, text, err, errlen);
}

static int emulated_get(struct uwb_gpio *gpio, enum uwb_gpio_line line, int *value, char *err, size_t errlen)
{
    char text[64], reply[256], want[64];
    snprintf(text, sizeof text, "get %s\n", uwb_gpio_line_name(line));
    int rc = send_text(gpio, text, err, errlen);
    if (rc == UWB_GPIO_OK)
        rc = read_line(gpio, reply, sizeof reply, err, errlen);
    if (rc != UWB_GPIO_OK)
        return rc;
    snprintf(want, sizeof want, "val %s ", uwb_gpio_line_name(line));
    size_t n = strlen(want);
    if (strncmp(reply, want, n) != 0 || (reply[n] != '0' && reply[n] != '1') || reply[n + 1]) {
        snprintf(err, errlen, "emulated GPIO at %s: answered '%.80s' to 'get %s'", gpio->cfg.endpoint, reply,
                 uwb_gpio_line_name(line));
        return UWB_GPIO_ERR_IO;
    }
    *value = reply[n] - '0';
    return UWB_GPIO_OK;
}

const struct uwb_gpio_ops uwb_gpio_emulated_ops = {
    .name = "emulated",
    .open = emulated_open,
    .set = emulated_set,
    .get = emulated_get,
    .close = emulated_close,
};
