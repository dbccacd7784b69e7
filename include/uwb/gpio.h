/* The five GPIO lines the appliance drives or reads, behind one small
 * function table so that logic never sees which backend serves them:
 * "libgpiod" (src/hw/, a real /dev/gpiochip*) or "emulated" (a socket to
 * the emulated board, protocol in board/emulated-gpio.md). */
#ifndef UWB_GPIO_H
#define UWB_GPIO_H

#include <stddef.h>

#include "uwb/link.h" /* UWB_ENDPOINT_MAX: the emulated backend's endpoint is a link's */

enum uwb_gpio_line {
    UWB_LINE_TRIGGER, /* out: pulser trigger, a pulse fires on the rising edge */
    UWB_LINE_STEP,    /* out: stepper driver STEP, one microstep per rising edge */
    UWB_LINE_DIR,     /* out: stepper direction, 1 = up (towards larger y) */
    UWB_LINE_ENABLE,  /* out: stepper driver enable, 1 = energised */
    UWB_LINE_HOME,    /* in:  home switch, 1 = carriage at home (after active-low mapping) */
    /* The site's lines (src/integrations/), opened by a handle of their own: */
    UWB_LINE_WATCH, /* out: `watch` alarm contact, 1 = relay energised */
    UWB_LINE_ALARM, /* out: `alarm` alarm contact, 1 = relay energised */
    UWB_LINE_FAULT, /* out: device-fault contact, 1 = energised = healthy (fail-safe) */
    UWB_LINE_EVENT, /* in:  event input (protection relay trip), 1 = active */
    UWB_LINE_COUNT
};

/* The rig's five lines, trigger to home: what uwb_gpio_config_defaults opens. */
#define UWB_LINE_RIG (UWB_LINE_HOME + 1)
#define UWB_GPIO_RIG_LINES 0x1fu
#define UWB_GPIO_LINE_BIT(line) (1u << (line))

#define UWB_GPIO_NAME_MAX 64

struct uwb_gpio_config {
    char backend[16];                /* "libgpiod" or "emulated" */
    char chip[UWB_GPIO_NAME_MAX];    /* libgpiod: chip label, name (gpiochip0) or path */
    char endpoint[UWB_ENDPOINT_MAX]; /* emulated: unix:PATH, tcp:HOST:PORT or serial:DEV?baud=N */
    int offset[UWB_LINE_COUNT];      /* line offsets, -1 = look up by name */
    char name[UWB_LINE_COUNT][UWB_GPIO_NAME_MAX]; /* line names, used when offset is -1 */
    int home_active_low;                          /* switch pulls the line low when closed */
    int home_pull_up;                             /* request the internal pull-up (libgpiod >= 1.5 bias) */
    int enable_active_low;                        /* driver's EN pin energises the motor when low
                                                     (A4988, TMC2209): ENABLE 1 drives it low */
    unsigned lines;                               /* UWB_GPIO_LINE_BIT of each line this handle opens */
    int active_low[UWB_LINE_COUNT];               /* site lines: active (1) when the pin is low (libgpiod) */
};

/* Distinct failure classes, so the daemon can map them to distinct exit codes. */
enum uwb_gpio_error {
    UWB_GPIO_OK = 0,
    UWB_GPIO_ERR_CHIP = -1,   /* chip / endpoint missing or unreachable */
    UWB_GPIO_ERR_LINE = -2,   /* line offset or name not on the chip */
    UWB_GPIO_ERR_BUSY = -3,   /* line already requested by another consumer */
    UWB_GPIO_ERR_IO = -4,     /* set/get failed after open (link lost, ...) */
    UWB_GPIO_ERR_CONFIG = -5, /* unknown backend, bad config */
};

struct uwb_gpio;

void uwb_gpio_config_defaults(struct uwb_gpio_config *cfg);
const char *uwb_gpio_line_name(enum uwb_gpio_line line);
int uwb_gpio_line_is_input(enum uwb_gpio_line line);

/* Open the backend cfg->backend names. Returns UWB_GPIO_OK or an
 * enum uwb_gpio_error with err naming the chip/line/endpoint and problem.
 * Outputs start low (pulser idle, motor disabled). */
int uwb_gpio_open(const struct uwb_gpio_config *cfg, struct uwb_gpio **gpio, char *err, size_t errlen);
int uwb_gpio_set(struct uwb_gpio *gpio, enum uwb_gpio_line line, int value, char *err, size_t errlen);
int uwb_gpio_get(struct uwb_gpio *gpio, enum uwb_gpio_line line, int *value, char *err, size_t errlen);
/* Drives outputs low, releases the lines. NULL is a no-op. */
void uwb_gpio_close(struct uwb_gpio *gpio);

#endif
