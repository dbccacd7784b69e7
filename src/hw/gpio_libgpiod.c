/* The "libgpiod" GPIO backend (libgpiod 1.6 API, Debian 12): the lines a
 * handle opens (the rig's five, or the site's) on one /dev/gpiochip*, by offset or by line name. Active-low
 * wiring (home switch to ground, the driver's EN pin) is handed to the
 * kernel with the request flags, so the rest of the code sees logical
 * values only. */
#include <errno.h>
#include <glob.h>
#include <gpiod.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpio/gpio_backend.h"

#define CONSUMER "uwbd"

struct chip_lines {
    struct gpiod_chip *chip;
    struct gpiod_line *line[UWB_LINE_COUNT];
    int requested[UWB_LINE_COUNT];
};

/* "gpiochip0, gpiochip1" or "none", for the missing-chip message. */
static void list_chips(char *buf, size_t buflen)
{
    glob_t g;
    buf[0] = '\0';
    if (glob("/dev/gpiochip*", 0, NULL, &g) != 0) {
        snprintf(buf, buflen, "none");
        return;
    }
    size_t used = 0;
    for (size_t i = 0; i < g.gl_pathc && used < buflen; i++) {
        const char *name = strrchr(g.gl_pathv[i], '/') + 1;
        used += (size_t)snprintf(buf + used, buflen - used, "%s%s", i ? ", " : "", name);
    }
    globfree(&g);
}

static void release_all(struct chip_lines *cl)
{
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        if (cl->requested[i])
            gpiod_line_release(cl->line[i]);
    if (cl->chip)
        gpiod_chip_close(cl->chip);
    free(cl);
}

/* Finds line `which` on the chip; UWB_GPIO_ERR_LINE with the line named. */
static int find_line(struct chip_lines *cl, const struct uwb_gpio_config *cfg, int which, char *err,
                     size_t errlen)
{
    const char *role = uwb_gpio_line_name(which);
    const char *chip = gpiod_chip_name(cl->chip);
    if (cfg->offset[which] >= 0) {
        cl->line[which] = gpiod_chip_get_line(cl->chip, (unsigned)cfg->offset[which]);
        if (!cl->line[which]) {
            snprintf(err, errlen, "gpio %s line: offset %d is not on %s (it has %u lines, 0..%u)", role,
                     cfg->offset[which], chip, gpiod_chip_num_lines(cl->chip),
                     gpiod_chip_num_lines(cl->chip) - 1);
            return UWB_GPIO_ERR_LINE;
        }
        return UWB_GPIO_OK;
    }
    if (!cfg->name[which][0]) {
        snprintf(err, errlen, "gpio %s line: neither an offset nor a line name configured", role);
        return UWB_GPIO_ERR_CONFIG;
    }
    cl->line[which] = gpiod_chip_find_line(cl->chip, cfg->name[which]);
    if (!cl->line[which]) {
        snprintf(err, errlen, "gpio %s line: no line named '%s' on %s", role, cfg->name[which], chip);
        return UWB_GPIO_ERR_LINE;
    }
    return UWB_GPIO_OK;
}

static int request_line(struct chip_lines *cl, const struct uwb_gpio_config *cfg, int which, char *err,
                        size_t errlen)
{
    struct gpiod_line *line = cl->line[which];
    const char *role = uwb_gpio_line_name(which);
    int rc;
    if (which == UWB_LINE_HOME) {
        int flags = (cfg->home_active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0) |
                    (cfg->home_pull_up ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP : 0);
        rc = gpiod_line_request_input_flags(line, CONSUMER, flags);
    } else if (uwb_gpio_line_is_input(which)) {
        rc = gpiod_line_request_input_flags(line, CONSUMER,
                                            cfg->active_low[which] ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0);
    } else {
        int active_low = which == UWB_LINE_ENABLE ? cfg->enable_active_low
                         : which >= UWB_LINE_RIG  ? cfg->active_low[which]
                                                  : 0;
        int flags = active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
        /* Logical 0 from the first instant: pulser idle, motor off. */
        rc = gpiod_line_request_output_flags(line, CONSUMER, flags, 0);
    }
    if (rc == 0) {
        cl->requested[which] = 1;
        return UWB_GPIO_OK;
    }
    int error = errno;
    const char *chip = gpiod_chip_name(cl->chip);
    unsigned offset = gpiod_line_offset(line);
    if (error == EBUSY) {
        const char *owner = gpiod_line_consumer(line);
        snprintf(err, errlen, "gpio %s line: %s offset %u is already in use by '%s'", role, chip, offset,
                 owner ? owner : "another program");
        return UWB_GPIO_ERR_BUSY;
    }
    snprintf(err, errlen, "gpio %s line: cannot request %s offset %u as %s: %s%s", role, chip, offset,
             uwb_gpio_line_is_input(which) ? "input" : "output", strerror(error),
             which == UWB_LINE_HOME && cfg->home_pull_up
                 ? " (a kernel without bias support rejects the pull-up: fit an external one and set "
                   "home_pull_up false)"
                 : "");
    return UWB_GPIO_ERR_LINE;
}

static int libgpiod_open(struct uwb_gpio *gpio, const struct uwb_gpio_config *cfg, char *err, size_t errlen)
{
    if (!cfg->chip[0]) {
        snprintf(err, errlen, "gpio: no chip configured (a name such as gpiochip0, a label or a /dev path)");
        return UWB_GPIO_ERR_CONFIG;
    }
    struct chip_lines *cl = calloc(1, sizeof *cl);
    if (!cl) {
        snprintf(err, errlen, "gpio: out of memory");
        return UWB_GPIO_ERR_CONFIG;
    }
    /* Name, /dev path, label or number, as gpiodetect shows them. */
    cl->chip = gpiod_chip_open_lookup(cfg->chip);
    if (!cl->chip) {
        int error = errno;
        char chips[256];
        list_chips(chips, sizeof chips);
        snprintf(err, errlen, "gpio chip '%s': cannot open: %s (GPIO chips on this machine: %s)", cfg->chip,
                 error ? strerror(error) : "no such chip", chips);
        free(cl);
        return UWB_GPIO_ERR_CHIP;
    }
    int rc = UWB_GPIO_OK;
    for (int i = 0; rc == UWB_GPIO_OK && i < UWB_LINE_COUNT; i++)
        if (cfg->lines & UWB_GPIO_LINE_BIT(i))
            rc = find_line(cl, cfg, i, err, errlen);
    for (int i = 0; rc == UWB_GPIO_OK && i < UWB_LINE_COUNT; i++)
        if (cfg->lines & UWB_GPIO_LINE_BIT(i))
            rc = request_line(cl, cfg, i, err, errlen);
    if (rc != UWB_GPIO_OK) {
        release_all(cl);
        return rc;
    }
    gpio->state = cl;
    return UWB_GPIO_OK;
}

static int libgpiod_set(struct uwb_gpio *gpio, enum uwb_gpio_line line, int value, char *err, size_t errlen)
{
    struct chip_lines *cl = gpio->state;
    if (gpiod_line_set_value(cl->line[line], value) != 0) {
        snprintf(err, errlen, "gpio %s line: set %d: %s", uwb_gpio_line_name(line), value, strerror(errno));
        return UWB_GPIO_ERR_IO;
    }
    return UWB_GPIO_OK;
}

static int libgpiod_get(struct uwb_gpio *gpio, enum uwb_gpio_line line, int *value, char *err, size_t errlen)
{
    struct chip_lines *cl = gpio->state;
    int v = gpiod_line_get_value(cl->line[line]);
    if (v < 0) {
        snprintf(err, errlen, "gpio %s line: read: %s", uwb_gpio_line_name(line), strerror(errno));
        return UWB_GPIO_ERR_IO;
    }
    *value = v;
    return UWB_GPIO_OK;
}

static void libgpiod_close(struct uwb_gpio *gpio)
{
    struct chip_lines *cl = gpio->state;
    if (!cl)
        return;
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        if (cl->requested[i] && !uwb_gpio_line_is_input(i))
            gpiod_line_set_value(cl->line[i], 0);
    release_all(cl);
    gpio->state = NULL;
}

const struct uwb_gpio_ops uwb_gpio_libgpiod_ops = {
    .name = "libgpiod",
    .open = libgpiod_open,
    .set = libgpiod_set,
    .get = libgpiod_get,
    .close = libgpiod_close,
};
