/* The GPIO dispatcher: picks the backend the config names and guards the
 * calls (outputs are only set, inputs only read, and only lines the handle
 * opened). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpio/gpio_backend.h"

static const struct uwb_gpio_ops *const backends[] = {&uwb_gpio_libgpiod_ops, &uwb_gpio_emulated_ops};

static const char *const line_names[UWB_LINE_COUNT] = {"trigger", "step",  "dir",   "enable", "home",
                                                       "watch",   "alarm", "fault", "event"};

/* Raspberry Pi 4 wiring of board/raspberry-pi-4/pinmap.md (BCM numbers on
 * gpiochip0), with the A4988/TMC2209's active-low EN and a home switch to
 * ground on a pulled-up input. */
static const int rpi4_offsets[UWB_LINE_RIG] = {17, 27, 22, 23, 24};

void uwb_gpio_config_defaults(struct uwb_gpio_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    snprintf(cfg->backend, sizeof cfg->backend, "libgpiod");
    snprintf(cfg->chip, sizeof cfg->chip, "gpiochip0");
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        cfg->offset[i] = i < UWB_LINE_RIG ? rpi4_offsets[i] : -1;
    cfg->lines = UWB_GPIO_RIG_LINES;
    cfg->home_active_low = 1;
    cfg->home_pull_up = 1;
    cfg->enable_active_low = 1;
}

const char *uwb_gpio_line_name(enum uwb_gpio_line line)
{
    if ((int)line < 0 || line >= UWB_LINE_COUNT)
        return "?";
    return line_names[line];
}

int uwb_gpio_line_is_input(enum uwb_gpio_line line)
{
    return line == UWB_LINE_HOME || line == UWB_LINE_EVENT;
}

/* Only the lines a handle opened may be used through it. */
static int opened(const struct uwb_gpio *gpio, enum uwb_gpio_line line, char *err, size_t errlen)
{
    if (gpio->cfg.lines & UWB_GPIO_LINE_BIT(line))
        return 1;
    snprintf(err, errlen, "gpio: line %s is not opened by this handle", uwb_gpio_line_name(line));
    return 0;
}

int uwb_gpio_open(const struct uwb_gpio_config *cfg, struct uwb_gpio **gpio, char *err, size_t errlen)
{
    *gpio = NULL;
    const struct uwb_gpio_ops *ops = NULL;
    for (size_t i = 0; i < sizeof backends / sizeof backends[0]; i++)
        if (strcmp(cfg->backend, backends[i]->name) == 0)
            ops = backends[i];
    if (!ops) {
        snprintf(err, errlen, "gpio backend '%s' unknown (expected libgpiod or emulated)", cfg->backend);
        return UWB_GPIO_ERR_CONFIG;
    }
    struct uwb_gpio *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(err, errlen, "gpio: out of memory");
        return UWB_GPIO_ERR_CONFIG;
    }
    g->ops = ops;
    g->cfg = *cfg;
    int rc = ops->open(g, cfg, err, errlen);
    if (rc != UWB_GPIO_OK) {
        free(g);
        return rc;
    }
    *gpio = g;
    return UWB_GPIO_OK;
}

int uwb_gpio_set(struct uwb_gpio *gpio, enum uwb_gpio_line line, int value, char *err, size_t errlen)
{
    if ((int)line < 0 || line >= UWB_LINE_COUNT || uwb_gpio_line_is_input(line)) {
        snprintf(err, errlen, "gpio: line %s is not an output", uwb_gpio_line_name(line));
        return UWB_GPIO_ERR_LINE;
    }
    if (!opened(gpio, line, err, errlen))
        return UWB_GPIO_ERR_LINE;
    return gpio->ops->set(gpio, line, value ? 1 : 0, err, errlen);
}

int uwb_gpio_get(struct uwb_gpio *gpio, enum uwb_gpio_line line, int *value, char *err, size_t errlen)
{
    if ((int)line < 0 || line >= UWB_LINE_COUNT) {
        snprintf(err, errlen, "gpio: no line %d", (int)line);
        return UWB_GPIO_ERR_LINE;
    }
    if (!opened(gpio, line, err, errlen))
        return UWB_GPIO_ERR_LINE;
    return gpio->ops->get(gpio, line, value, err, errlen);
}

void uwb_gpio_close(struct uwb_gpio *gpio)
{
    if (!gpio)
        return;
    gpio->ops->close(gpio);
    free(gpio);
}
