/* The hardware backends' failures, as an engineer meets them on a board
 * that lacks the chip or the port: a distinct error class and a message
 * naming what is missing. This machine has no /dev/gpiochip*. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "unity.h"
#include "uwb/digitiser.h"
#include "uwb/gpio.h"
#include "uwb/link.h"
#include "uwb/rig.h"

static char err[1024];

void setUp(void)
{
}
void tearDown(void)
{
}

#define MISSING_CHIP "gpiochip-uwb-test-absent"

static void test_missing_gpio_chip_is_a_chip_error_naming_it(void)
{
    struct uwb_gpio_config cfg;
    uwb_gpio_config_defaults(&cfg);
    TEST_ASSERT_EQUAL_STRING("libgpiod", cfg.backend);
    snprintf(cfg.chip, sizeof cfg.chip, "%s", MISSING_CHIP);
    struct uwb_gpio *gpio = NULL;
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CHIP, uwb_gpio_open(&cfg, &gpio, err, sizeof err));
    TEST_ASSERT_NULL(gpio);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "'" MISSING_CHIP "'"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "cannot open"), err);
    /* by path too */
    snprintf(cfg.chip, sizeof cfg.chip, "/dev/%s", MISSING_CHIP);
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CHIP, uwb_gpio_open(&cfg, &gpio, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "/dev/" MISSING_CHIP), err);
}

static void test_unknown_backend_and_empty_chip_are_config_errors(void)
{
    struct uwb_gpio_config cfg;
    uwb_gpio_config_defaults(&cfg);
    snprintf(cfg.backend, sizeof cfg.backend, "sysfs");
    struct uwb_gpio *gpio;
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CONFIG, uwb_gpio_open(&cfg, &gpio, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "'sysfs'"), err);
    uwb_gpio_config_defaults(&cfg);
    cfg.chip[0] = '\0';
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CONFIG, uwb_gpio_open(&cfg, &gpio, err, sizeof err));
    snprintf(cfg.backend, sizeof cfg.backend, "emulated");
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CONFIG, uwb_gpio_open(&cfg, &gpio, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no endpoint"), err);
}

static void test_emulated_gpio_without_a_board_is_a_chip_error_naming_the_endpoint(void)
{
    struct uwb_gpio_config cfg;
    uwb_gpio_config_defaults(&cfg);
    snprintf(cfg.backend, sizeof cfg.backend, "emulated");
    snprintf(cfg.endpoint, sizeof cfg.endpoint, "unix:/tmp/uwb-test-no-board-%d.sock", (int)getpid());
    struct uwb_gpio *gpio;
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CHIP, uwb_gpio_open(&cfg, &gpio, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, cfg.endpoint), err);
}

static void test_missing_serial_port_is_an_open_error_naming_it(void)
{
    struct uwb_link *link = NULL;
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_OPEN,
                          uwb_link_open("serial:/dev/ttyUWBTEST9?baud=921600", &link, err, sizeof err));
    TEST_ASSERT_NULL(link);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "/dev/ttyUWBTEST9"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "No such file"), err);
}

static void test_a_file_that_is_no_serial_port_is_refused(void)
{
    struct uwb_link *link = NULL;
    /* /dev/null exists but is no tty: libserialport refuses it */
    int rc = uwb_link_open("serial:/dev/null", &link, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_ERR_OPEN, rc, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "/dev/null"), err);
}

static void test_rig_open_reports_the_gpio_class_in_detail(void)
{
    struct uwb_rig_config cfg;
    uwb_rig_config_defaults(&cfg);
    snprintf(cfg.gpio.chip, sizeof cfg.gpio.chip, "%s", MISSING_CHIP);
    snprintf(cfg.digitiser.endpoint, sizeof cfg.digitiser.endpoint, "serial:/dev/ttyUWBTEST9?baud=921600");
    struct uwb_rig *rig = NULL;
    int detail = 0;
    TEST_ASSERT_EQUAL_INT(UWB_RIG_ERR_GPIO, uwb_rig_open(&cfg, &rig, &detail, err, sizeof err));
    TEST_ASSERT_NULL(rig);
    TEST_ASSERT_EQUAL_INT(UWB_GPIO_ERR_CHIP, detail);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, MISSING_CHIP), err);
}

static void test_digitiser_on_a_missing_port_is_a_link_error(void)
{
    struct uwb_rig_config cfg;
    uwb_rig_config_defaults(&cfg);
    snprintf(cfg.digitiser.endpoint, sizeof cfg.digitiser.endpoint, "serial:/dev/ttyUWBTEST9");
    struct uwb_digitiser *dig = NULL;
    int detail = 0;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_LINK,
                          uwb_digitiser_open(&cfg.digitiser, &dig, &detail, err, sizeof err));
    TEST_ASSERT_NULL(dig);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_OPEN, detail);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "/dev/ttyUWBTEST9"), err);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_missing_gpio_chip_is_a_chip_error_naming_it);
    RUN_TEST(test_unknown_backend_and_empty_chip_are_config_errors);
    RUN_TEST(test_emulated_gpio_without_a_board_is_a_chip_error_naming_the_endpoint);
    RUN_TEST(test_missing_serial_port_is_an_open_error_naming_it);
    RUN_TEST(test_a_file_that_is_no_serial_port_is_refused);
    RUN_TEST(test_rig_open_reports_the_gpio_class_in_detail);
    RUN_TEST(test_digitiser_on_a_missing_port_is_a_link_error);
    return UNITY_END();
}
