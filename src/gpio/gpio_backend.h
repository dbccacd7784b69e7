/* What a GPIO backend (src/gpio/gpio_emulated.c, src/hw/gpio_libgpiod.c)
 * sees of a struct uwb_gpio; nothing above the backends includes this. */
#ifndef UWB_GPIO_BACKEND_H
#define UWB_GPIO_BACKEND_H

#include "uwb/gpio.h"

struct uwb_gpio_ops {
    const char *name; /* what cfg->backend says to choose this backend */
    int (*open)(struct uwb_gpio *gpio, const struct uwb_gpio_config *cfg, char *err, size_t errlen);
    int (*set)(struct uwb_gpio *gpio, enum uwb_gpio_line line, int value, char *err, size_t errlen);
    int (*get)(struct uwb_gpio *gpio, enum uwb_gpio_line line, int *value, char *err, size_t errlen);
    void (*close)(struct uwb_gpio *gpio);
};

struct uwb_gpio {
    const struct uwb_gpio_ops *ops;
    struct uwb_gpio_config cfg;
    void *state; /* the backend's own */
};

extern const struct uwb_gpio_ops uwb_gpio_libgpiod_ops;
extern const struct uwb_gpio_ops uwb_gpio_emulated_ops;

#endif
