/* Fuzzing the daemon's side of the emulated-GPIO protocol
 * (src/gpio/gpio_emulated.c, board/emulated-gpio.md): the input is what
 * the board says, from the answer to `hello` to the answers to `get`.
 * The backend's line reader and reply checks are static, so they are
 * driven through the public GPIO API over a scripted link
 * (scripted_link.c): open (hello), then the gets a home search and a
 * scan make, with sets between them, until the first error.
 *
 * Contract: open and get return documented codes and fill err when they
 * fail; a value read is 0 or 1. */
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/gpio.h"

#define GETS 24

static int known_error(int rc)
{
    return rc == UWB_GPIO_ERR_CHIP || rc == UWB_GPIO_ERR_LINE || rc == UWB_GPIO_ERR_BUSY ||
           rc == UWB_GPIO_ERR_IO || rc == UWB_GPIO_ERR_CONFIG;
}

static int run_session(char *why, size_t whylen)
{
    struct uwb_gpio_config cfg;
    uwb_gpio_config_defaults(&cfg);
    snprintf(cfg.backend, sizeof cfg.backend, "emulated");
    snprintf(cfg.endpoint, sizeof cfg.endpoint, "unix:fuzz-gpio.sock");
    struct uwb_gpio *gpio = NULL;
    int rc = uwb_gpio_open(&cfg, &gpio, why, whylen);
    if (rc != UWB_GPIO_OK) {
        if (gpio)
            return fuzz_broken(why, whylen, "open failed (%d) but returned a handle", rc);
        if (!known_error(rc))
            return fuzz_broken(why, whylen, "open returned %d", rc);
        if (!why[0])
            return fuzz_broken(why, whylen, "open failed (%d) without a message", rc);
        return FUZZ_REJECTED;
    }
    int outcome = FUZZ_ACCEPTED, reads = 0;
    for (int i = 0; i < GETS; i++) {
        /* Mostly the home switch, as a home search polls it. */
        enum uwb_gpio_line line = i % 3 ? UWB_LINE_HOME : (enum uwb_gpio_line)(i / 3 % UWB_LINE_RIG);
        char err[512] = "";
        if (line != UWB_LINE_HOME && (rc = uwb_gpio_set(gpio, line, i & 1, err, sizeof err)) != UWB_GPIO_OK) {
            outcome =
                err[0] ? FUZZ_ACCEPTED : fuzz_broken(why, whylen, "set failed (%d) without a message", rc);
            break;
        }
        int value = -1;
        rc = uwb_gpio_get(gpio, line, &value, err, sizeof err);
        if (rc == UWB_GPIO_OK) {
            if (value != 0 && value != 1) {
                outcome = fuzz_broken(why, whylen, "get %s read %d", uwb_gpio_line_name(line), value);
                break;
            }
            reads++;
            continue;
        }
        if (!known_error(rc))
            outcome = fuzz_broken(why, whylen, "get returned %d", rc);
        else if (!err[0])
            outcome = fuzz_broken(why, whylen, "get failed (%d) without a message", rc);
        else
            snprintf(why, whylen, "after %d reads: %s", reads, err);
        break;
    }
    uwb_gpio_close(gpio);
    return outcome;
}

int fuzz_gpio_reply_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    fuzz_link_script(data, size);
    int rc = run_session(why, whylen);
    fuzz_link_script(NULL, 0);
    return rc;
}

UWB_FUZZ_TARGET(fuzz_gpio_reply_input)
