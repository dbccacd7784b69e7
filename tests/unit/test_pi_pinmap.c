/* The Raspberry Pi 4 sample config and its pin map agree: every GPIO line
 * the config names (rig and site) is a row of pinmap.md's table with the
 * same BCM offset, each row's header pin is where that BCM GPIO sits on the
 * Pi 4's 40-pin header, and no two functions (lines, UARTs) share a GPIO. */
#include "unity.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scratch_support.h"
#include "config/config_load.h"

#define SAMPLE_RPI4 "board/raspberry-pi-4/uwbd.json"
#define PINMAP_RPI4 "board/raspberry-pi-4/pinmap.md"
#define MAX_ROWS 40
#define MAX_GPIOS 10

/* The Pi 4 header: physical pin of each BCM GPIO 0-27. */
static const int header_pin_of_bcm[28] = {27, 28, 3,  5,  7,  29, 31, 26, 24, 21, 19, 23, 32, 33,
                                          8,  10, 36, 11, 12, 35, 38, 40, 15, 16, 18, 22, 37, 13};

struct pin_row {
    char function[64];
    int bcm[MAX_GPIOS], pin[MAX_GPIOS];
    int gpios, pins;
};

static struct pin_row rows[MAX_ROWS];
static int row_count;
static struct uwbd_config cfg;
static char err[1024];

/* Numbers in a cell ("14 / 15", "—" has none). */
static int cell_numbers(const char *cell, size_t len, int *out, int max)
{
    int n = 0;
    for (size_t i = 0; i < len;) {
        if (!isdigit((unsigned char)cell[i])) {
            i++;
            continue;
        }
        int v = 0;
        while (i < len && isdigit((unsigned char)cell[i]))
            v = v * 10 + (cell[i++] - '0');
        TEST_ASSERT_LESS_THAN_INT_MESSAGE(max, n, "too many numbers in a pin map cell");
        out[n++] = v;
    }
    return n;
}

/* The first table: | function | BCM offset | header pin | ... */
static void read_pinmap(void)
{
    char *text = scratch_slurp(PINMAP_RPI4, NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(text, PINMAP_RPI4);
    const char *line = strstr(text, "| line | BCM offset | header pin |");
    TEST_ASSERT_NOT_NULL_MESSAGE(line, PINMAP_RPI4 ": no table headed | line | BCM offset | header pin |");
    row_count = 0;
    for (line = strchr(line, '\n'); line && line[1] == '|'; line = strchr(line + 1, '\n')) {
        const char *cell[4];
        size_t cell_len[3];
        cell[0] = line + 2;
        while (*cell[0] == ' ')
            cell[0]++;
        for (int c = 1; c < 4; c++) {
            cell[c] = strchr(cell[c - 1], '|');
            if (!cell[c]) {
                free(text);
                TEST_FAIL_MESSAGE(PINMAP_RPI4 ": a table row with fewer than 3 cells");
                return; /* not reached: the analyser does not know Unity's longjmp */
            }
            cell_len[c - 1] = (size_t)(cell[c] - cell[c - 1]);
            cell[c]++;
        }
        if (strncmp(cell[0], "---", 3) == 0)
            continue;
        TEST_ASSERT_LESS_THAN_INT(MAX_ROWS, row_count);
        struct pin_row *r = &rows[row_count++];
        size_t n = cell_len[0] < sizeof r->function ? cell_len[0] : sizeof r->function - 1;
        memcpy(r->function, cell[0], n);
        while (n > 0 && r->function[n - 1] == ' ')
            n--;
        r->function[n] = '\0';
        r->gpios = cell_numbers(cell[1], cell_len[1], r->bcm, MAX_GPIOS);
        r->pins = cell_numbers(cell[2], cell_len[2], r->pin, MAX_GPIOS);
    }
    free(text);
    TEST_ASSERT_GREATER_THAN_INT_MESSAGE(0, row_count, PINMAP_RPI4 ": the table has no rows");
}

void setUp(void)
{
    err[0] = '\0';
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_config_load(SAMPLE_RPI4, NULL, 0, &cfg, err, sizeof err), err);
    read_pinmap();
}

void tearDown(void)
{
}

static const struct pin_row *row_named(const char *function)
{
    for (int i = 0; i < row_count; i++)
        if (strcmp(rows[i].function, function) == 0)
            return &rows[i];
    return NULL;
}

/* The rig's five lines and the site's four (contacts, event input). */
static int config_offset(int line)
{
    return line < UWB_LINE_RIG ? cfg.rig.gpio.offset[line] : cfg.site.io.offset[line];
}

static void test_every_line_of_the_config_is_in_the_pin_map(void)
{
    for (int line = 0; line < UWB_LINE_COUNT; line++) {
        char function[32], msg[200];
        const char *name = uwb_gpio_line_name((enum uwb_gpio_line)line);
        for (size_t i = 0; i <= strlen(name); i++)
            function[i] = (char)toupper((unsigned char)name[i]);
        snprintf(msg, sizeof msg, "%s: the %s line is not given by a BCM offset", SAMPLE_RPI4, name);
        TEST_ASSERT_TRUE_MESSAGE(config_offset(line) >= 0, msg);
        const struct pin_row *r = row_named(function);
        snprintf(msg, sizeof msg, "%s: no row %s in the table", PINMAP_RPI4, function);
        TEST_ASSERT_NOT_NULL_MESSAGE(r, msg);
        snprintf(msg, sizeof msg, "%s row %s against %s", PINMAP_RPI4, function, SAMPLE_RPI4);
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, r->gpios, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(config_offset(line), r->bcm[0], msg);
    }
}

static void test_header_pins_are_where_the_gpios_are(void)
{
    int checked = 0;
    for (int i = 0; i < row_count; i++) {
        const struct pin_row *r = &rows[i];
        if (r->gpios == 0)
            continue; /* ground and supply rows */
        char msg[200];
        snprintf(msg, sizeof msg, "%s row %.60s: BCM offsets and header pins", PINMAP_RPI4, r->function);
        TEST_ASSERT_EQUAL_INT_MESSAGE(r->gpios, r->pins, msg);
        for (int g = 0; g < r->gpios; g++) {
            TEST_ASSERT_LESS_THAN_INT_MESSAGE(28, r->bcm[g], msg);
            TEST_ASSERT_EQUAL_INT_MESSAGE(header_pin_of_bcm[r->bcm[g]], r->pin[g], msg);
            checked++;
        }
    }
    TEST_ASSERT_GREATER_OR_EQUAL_INT(UWB_LINE_COUNT, checked);
}

static void test_no_two_functions_share_a_gpio(void)
{
    for (int i = 0; i < row_count; i++)
        for (int g = 0; g < rows[i].gpios; g++)
            for (int j = i; j < row_count; j++)
                for (int h = j == i ? g + 1 : 0; h < rows[j].gpios; h++) {
                    char msg[200];
                    snprintf(msg, sizeof msg, "%s: %.60s and %.60s both on BCM %d", PINMAP_RPI4,
                             rows[i].function, rows[j].function, rows[i].bcm[g]);
                    TEST_ASSERT_TRUE_MESSAGE(rows[i].bcm[g] != rows[j].bcm[h], msg);
                }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_line_of_the_config_is_in_the_pin_map);
    RUN_TEST(test_header_pins_are_where_the_gpios_are);
    RUN_TEST(test_no_two_functions_share_a_gpio);
    return UNITY_END();
}
