/* The libgpiod backend against a real kernel GPIO driver: the PL061 of
 * qemu's virt machine, inside the emulated board (tools/board-in-loop/).
 * Every claim the backend makes is checked against the kernel's own view
 * of the lines (debugfs: consumer, direction, level) or against the chip's
 * output latch read through sysfs after the lines are released, never only
 * against what the backend itself reports. Runs as root in the guest. */
#include "unity.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "uwb/gpio.h"

#define CHIP_LABEL "9030000.pl061"
#define DEBUGFS_GPIO "/sys/kernel/debug/gpio"

/* Where the appliance's lines sit on the PL061 for these tests. */
static const int line_offset[UWB_LINE_RIG] = {
    [UWB_LINE_TRIGGER] = 0, [UWB_LINE_STEP] = 1, [UWB_LINE_DIR] = 2,
    [UWB_LINE_ENABLE] = 4,  [UWB_LINE_HOME] = 5,
};

static int chip_base = -1; /* global (sysfs) number of offset 0 */
static int chip_lines = 0;
static char err[512];

struct kernel_line {
    int requested;
    int is_out;
    int high; /* raw level the chip reports */
    char consumer[32];
};

static int read_text(const char *path, char *buf, size_t len)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    size_t n = fread(buf, 1, len - 1, f);
    fclose(f);
    buf[n] = '\0';
    while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == ' '))
        buf[--n] = '\0';
    return 0;
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    int ok = fputs(text, f) >= 0;
    return (fclose(f) == 0 && ok) ? 0 : -1;
}

/* The PL061's global number base and line count, found by its label in
 * sysfs, so the test does not depend on probe order. */
static void find_chip(void)
{
    DIR *d = opendir("/sys/class/gpio");
    TEST_ASSERT_NOT_NULL_MESSAGE(d, "/sys/class/gpio missing (CONFIG_GPIO_SYSFS)");
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strncmp(e->d_name, "gpiochip", 8) != 0)
            continue;
        char path[300], text[64];
        snprintf(path, sizeof path, "/sys/class/gpio/%s/label", e->d_name);
        if (read_text(path, text, sizeof text) != 0 || strcmp(text, CHIP_LABEL) != 0)
            continue;
        snprintf(path, sizeof path, "/sys/class/gpio/%s/base", e->d_name);
        TEST_ASSERT_EQUAL_INT(0, read_text(path, text, sizeof text));
        chip_base = atoi(text);
        snprintf(path, sizeof path, "/sys/class/gpio/%s/ngpio", e->d_name);
        TEST_ASSERT_EQUAL_INT(0, read_text(path, text, sizeof text));
        chip_lines = atoi(text);
    }
    closedir(d);
    TEST_ASSERT_TRUE_MESSAGE(chip_base >= 0, "no gpiochip labelled " CHIP_LABEL " in /sys/class/gpio");
}

/* One line as the kernel lists it in debugfs:
 *  " gpio-504 (                    |uwbd                ) out hi "
 * Only requested lines are listed. */
static struct kernel_line kernel_view(int offset)
{
    struct kernel_line line = {0};
    FILE *f = fopen(DEBUGFS_GPIO, "r");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, DEBUGFS_GPIO " missing (debugfs not mounted?)");
    char text[256], want[32];
    snprintf(want, sizeof want, " gpio-%d ", chip_base + offset);
    while (fgets(text, sizeof text, f)) {
        if (strncmp(text, want, strlen(want)) != 0)
            continue;
        const char *bar = strchr(text, '|'), *close = bar ? strchr(bar, ')') : NULL;
        TEST_ASSERT_NOT_NULL_MESSAGE(close, text);
        size_t n = (size_t)(close - bar - 1);
        while (n > 0 && bar[n] == ' ')
            n--;
        snprintf(line.consumer, sizeof line.consumer, "%.*s", (int)n, bar + 1);
        line.requested = 1;
        line.is_out = strstr(close, " out ") != NULL;
        line.high = strstr(close, " hi") != NULL;
    }
    fclose(f);
    return line;
}

static int requested_line_count(void)
{
    int count = 0;
    for (int offset = 0; offset < chip_lines; offset++)
        count += kernel_view(offset).requested;
    return count;
}

/* The chip's latch for an unrequested line, through the sysfs interface
 * (export does not change direction or level). */
static void sysfs_line(int offset, char *direction, size_t dlen, int *high)
{
    char number[16], path[96], value[8];
    snprintf(number, sizeof number, "%d", chip_base + offset);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, write_text("/sys/class/gpio/export", number), "sysfs export");
    snprintf(path, sizeof path, "/sys/class/gpio/gpio%d/direction", chip_base + offset);
    TEST_ASSERT_EQUAL_INT(0, read_text(path, direction, dlen));
    snprintf(path, sizeof path, "/sys/class/gpio/gpio%d/value", chip_base + offset);
    TEST_ASSERT_EQUAL_INT(0, read_text(path, value, sizeof value));
    *high = value[0] == '1';
    TEST_ASSERT_EQUAL_INT(0, write_text("/sys/class/gpio/unexport", number));
}

/* Drives an unrequested line to a level through sysfs. */
static void sysfs_drive(int offset, int high)
{
    char number[16], path[96];
    snprintf(number, sizeof number, "%d", chip_base + offset);
    TEST_ASSERT_EQUAL_INT(0, write_text("/sys/class/gpio/export", number));
    snprintf(path, sizeof path, "/sys/class/gpio/gpio%d/direction", chip_base + offset);
    TEST_ASSERT_EQUAL_INT(0, write_text(path, high ? "high" : "low"));
    TEST_ASSERT_EQUAL_INT(0, write_text("/sys/class/gpio/unexport", number));
}

static void pl061_config(struct uwb_gpio_config *cfg, const char *chip)
{
    uwb_gpio_config_defaults(cfg);
    snprintf(cfg->backend, sizeof cfg->backend, "libgpiod");
    snprintf(cfg->chip, sizeof cfg->chip, "%s", chip);
    for (int line = 0; line < UWB_LINE_RIG; line++)
        cfg->offset[line] = line_offset[line];
    cfg->home_active_low = 1;
    cfg->home_pull_up = 1;
    /* Logical levels equal the kernel's raw ones on the outputs; the
     * active-low ENABLE has its own test. */
    cfg->enable_active_low = 0;
}

static struct uwb_gpio *open_ok(const struct uwb_gpio_config *cfg)
{
    struct uwb_gpio *gpio = NULL;
    err[0] = '\0';
    int rc = uwb_gpio_open(cfg, &gpio, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, rc, err);
    TEST_ASSERT_NOT_NULL(gpio);
    return gpio;
}

/* An open that must fail with `want`, leaving no line requested. */
static void expect_open_error(const struct uwb_gpio_config *cfg, int want, const char *must_mention)
{
    struct uwb_gpio *gpio = NULL;
    int before = requested_line_count();
    err[0] = '\0';
    int rc = uwb_gpio_open(cfg, &gpio, err, sizeof err);
    printf("# open error (expected): %s\n", err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, rc, err);
    TEST_ASSERT_NULL(gpio);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, must_mention), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(before, requested_line_count(), "a failed open left lines requested");
}

void setUp(void)
{
    if (chip_base < 0)
        find_chip();
}

void tearDown(void)
{
}

static void test_open_by_label_requests_every_line_with_outputs_low(void)
{
    /* Leave the outputs' latches high first, so "low after open" is the
     * backend's doing. */
    for (int line = 0; line < UWB_LINE_RIG; line++)
        if (line != UWB_LINE_HOME)
            sysfs_drive(line_offset[line], 1);
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    struct uwb_gpio *gpio = open_ok(&cfg);
    for (int line = 0; line < UWB_LINE_RIG; line++) {
        struct kernel_line k = kernel_view(line_offset[line]);
        TEST_ASSERT_TRUE_MESSAGE(k.requested, uwb_gpio_line_name(line));
        TEST_ASSERT_TRUE_MESSAGE(k.consumer[0] != '\0', "the line has no consumer label");
        TEST_ASSERT_EQUAL_INT_MESSAGE(line != UWB_LINE_HOME, k.is_out, uwb_gpio_line_name(line));
        if (line != UWB_LINE_HOME) {
            TEST_ASSERT_FALSE_MESSAGE(k.high, uwb_gpio_line_name(line));
        }
    }
    TEST_ASSERT_EQUAL_INT(UWB_LINE_RIG, requested_line_count());
    uwb_gpio_close(gpio);
}

static void test_set_drives_the_kernel_line_and_get_reads_it_back(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    struct uwb_gpio *gpio = open_ok(&cfg);
    static const enum uwb_gpio_line outputs[] = {UWB_LINE_TRIGGER, UWB_LINE_STEP, UWB_LINE_DIR,
                                                 UWB_LINE_ENABLE};
    for (size_t i = 0; i < sizeof outputs / sizeof outputs[0]; i++) {
        enum uwb_gpio_line line = outputs[i];
        for (int level = 1; level >= 0; level--) {
            TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_set(gpio, line, level, err, sizeof err), err);
            TEST_ASSERT_EQUAL_INT_MESSAGE(level, kernel_view(line_offset[line]).high,
                                          uwb_gpio_line_name(line));
            /* The other outputs stay where they were: no cross-talk between lines. */
            for (size_t j = 0; j < sizeof outputs / sizeof outputs[0]; j++) {
                if (j != i) {
                    TEST_ASSERT_FALSE_MESSAGE(kernel_view(line_offset[outputs[j]]).high,
                                              uwb_gpio_line_name(outputs[j]));
                }
            }
            int value = -1;
            TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_get(gpio, line, &value, err, sizeof err),
                                          err);
            TEST_ASSERT_EQUAL_INT(level, value);
        }
    }
    uwb_gpio_close(gpio);
}

/* The home switch is active low: the backend's value is the inverse of the
 * level the kernel reads; with active_low off it is the level itself. */
static void test_home_input_follows_the_active_low_mapping(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    for (int active_low = 0; active_low <= 1; active_low++) {
        cfg.home_active_low = active_low;
        struct uwb_gpio *gpio = open_ok(&cfg);
        struct kernel_line k = kernel_view(line_offset[UWB_LINE_HOME]);
        TEST_ASSERT_TRUE(k.requested);
        TEST_ASSERT_FALSE(k.is_out);
        int value = -1;
        TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_get(gpio, UWB_LINE_HOME, &value, err, sizeof err),
                                      err);
        TEST_ASSERT_EQUAL_INT_MESSAGE(active_low ? !k.high : k.high, value,
                                      active_low ? "active low" : "active high");
        uwb_gpio_close(gpio);
    }
}

static void test_close_drives_outputs_low_and_releases_every_line(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    struct uwb_gpio *gpio = open_ok(&cfg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_set(gpio, UWB_LINE_ENABLE, 1, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_set(gpio, UWB_LINE_TRIGGER, 1, err, sizeof err), err);
    TEST_ASSERT_TRUE(kernel_view(line_offset[UWB_LINE_ENABLE]).high);
    uwb_gpio_close(gpio);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, requested_line_count(), "lines still requested after close");
    /* Released lines keep their last state in the chip: it must be the
     * safe one (motor disabled, pulser idle). */
    char direction[16];
    int high = -1;
    sysfs_line(line_offset[UWB_LINE_ENABLE], direction, sizeof direction, &high);
    TEST_ASSERT_EQUAL_STRING("out", direction);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, high, "ENABLE left high after close");
    sysfs_line(line_offset[UWB_LINE_TRIGGER], direction, sizeof direction, &high);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, high, "TRIGGER left high after close");
    uwb_gpio_close(NULL);
}

/* A stepper driver's EN pin energises the motor when low: logical 1 must
 * put the pin low, and the safe state (logical 0, at open and after close)
 * leaves it high. */
static void test_active_low_enable_is_high_when_the_motor_is_off(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    cfg.enable_active_low = 1;
    sysfs_drive(line_offset[UWB_LINE_ENABLE], 0);
    struct uwb_gpio *gpio = open_ok(&cfg);
    TEST_ASSERT_TRUE_MESSAGE(kernel_view(line_offset[UWB_LINE_ENABLE]).high, "motor energised at open");
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_set(gpio, UWB_LINE_ENABLE, 1, err, sizeof err), err);
    TEST_ASSERT_FALSE_MESSAGE(kernel_view(line_offset[UWB_LINE_ENABLE]).high,
                              "EN not pulled low by enable=1");
    uwb_gpio_close(gpio);
    char direction[16];
    int high = -1;
    sysfs_line(line_offset[UWB_LINE_ENABLE], direction, sizeof direction, &high);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, high, "EN left low (motor energised) after close");
}

static void test_chip_found_by_device_name_and_by_path(void)
{
    static const char *const names[] = {"gpiochip0", "/dev/gpiochip0"};
    for (size_t i = 0; i < 2; i++) {
        struct uwb_gpio_config cfg;
        pl061_config(&cfg, names[i]);
        struct uwb_gpio *gpio = open_ok(&cfg);
        TEST_ASSERT_TRUE_MESSAGE(kernel_view(line_offset[UWB_LINE_STEP]).requested, names[i]);
        uwb_gpio_close(gpio);
    }
}

static void test_missing_chip_is_a_chip_error_naming_it(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, "no-such-gpio-chip");
    expect_open_error(&cfg, UWB_GPIO_ERR_CHIP, "no-such-gpio-chip");
}

static void test_offset_beyond_the_chip_is_a_line_error(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    cfg.offset[UWB_LINE_DIR] = chip_lines; /* one past the last line */
    expect_open_error(&cfg, UWB_GPIO_ERR_LINE, uwb_gpio_line_name(UWB_LINE_DIR));
}

static void test_unknown_line_name_is_a_line_error(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    cfg.offset[UWB_LINE_HOME] = -1;
    snprintf(cfg.name[UWB_LINE_HOME], sizeof cfg.name[UWB_LINE_HOME], "NO_SUCH_LINE");
    expect_open_error(&cfg, UWB_GPIO_ERR_LINE, "NO_SUCH_LINE");
}

/* A second consumer of the same lines is refused, the first keeps them. */
static void test_line_held_by_another_consumer_is_busy(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    struct uwb_gpio *first = open_ok(&cfg);
    expect_open_error(&cfg, UWB_GPIO_ERR_BUSY, uwb_gpio_line_name(UWB_LINE_TRIGGER));
    TEST_ASSERT_EQUAL_INT(UWB_LINE_RIG, requested_line_count());
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_GPIO_OK, uwb_gpio_set(first, UWB_LINE_STEP, 1, err, sizeof err), err);
    TEST_ASSERT_TRUE(kernel_view(line_offset[UWB_LINE_STEP]).high);
    uwb_gpio_close(first);
    TEST_ASSERT_EQUAL_INT(0, requested_line_count());
}

/* Only the last line collides: the lines requested before it must be
 * given back when the open fails. */
static void test_partly_busy_open_gives_back_what_it_took(void)
{
    struct uwb_gpio_config other;
    pl061_config(&other, CHIP_LABEL);
    other.offset[UWB_LINE_TRIGGER] = 3;
    other.offset[UWB_LINE_STEP] = 6;
    other.offset[UWB_LINE_DIR] = 1;
    other.offset[UWB_LINE_ENABLE] = 2;
    other.offset[UWB_LINE_HOME] = 7;
    struct uwb_gpio *first = open_ok(&other);
    int before = requested_line_count();
    TEST_ASSERT_EQUAL_INT(UWB_LINE_RIG, before);

    struct uwb_gpio_config second;
    pl061_config(&second, CHIP_LABEL);
    second.offset[UWB_LINE_TRIGGER] = 0;
    second.offset[UWB_LINE_STEP] = 4;
    second.offset[UWB_LINE_DIR] = 5;
    second.offset[UWB_LINE_ENABLE] = 3; /* taken: first's TRIGGER */
    second.offset[UWB_LINE_HOME] = 7;
    expect_open_error(&second, UWB_GPIO_ERR_BUSY, uwb_gpio_line_name(UWB_LINE_ENABLE));
    TEST_ASSERT_FALSE_MESSAGE(kernel_view(0).requested, "offset 0 kept after the failed open");
    TEST_ASSERT_FALSE_MESSAGE(kernel_view(4).requested, "offset 4 kept after the failed open");
    uwb_gpio_close(first);
}

static void test_unknown_backend_is_a_config_error(void)
{
    struct uwb_gpio_config cfg;
    pl061_config(&cfg, CHIP_LABEL);
    snprintf(cfg.backend, sizeof cfg.backend, "sysfs");
    expect_open_error(&cfg, UWB_GPIO_ERR_CONFIG, "sysfs");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_open_by_label_requests_every_line_with_outputs_low);
    RUN_TEST(test_set_drives_the_kernel_line_and_get_reads_it_back);
    RUN_TEST(test_home_input_follows_the_active_low_mapping);
    RUN_TEST(test_close_drives_outputs_low_and_releases_every_line);
    RUN_TEST(test_active_low_enable_is_high_when_the_motor_is_off);
    RUN_TEST(test_chip_found_by_device_name_and_by_path);
    RUN_TEST(test_missing_chip_is_a_chip_error_naming_it);
    RUN_TEST(test_offset_beyond_the_chip_is_a_line_error);
    RUN_TEST(test_unknown_line_name_is_a_line_error);
    RUN_TEST(test_line_held_by_another_consumer_is_busy);
    RUN_TEST(test_partly_busy_open_gives_back_what_it_took);
    RUN_TEST(test_unknown_backend_is_a_config_error);
    return UNITY_END();
}
