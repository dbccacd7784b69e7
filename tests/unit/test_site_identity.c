/* site.phase and site.label: keys of the configuration table, shown in the
 * `status` reply and in the trend image's caption and its Asset text. */
#include "unity.h"

#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scratch_support.h"
#include "config/config_load.h"
#include "control/reply.h"
#include "state/store.h"
#include "daemon/trend.h"
#include "output/render_trend.h"

#define SAMPLE "board/emulated/uwbd.json"

static struct uwbd_config cfg;
static char err[1024];
static char dir[256];

void setUp(void)
{
    memset(&cfg, 0, sizeof cfg);
    dir[0] = '\0';
}

void tearDown(void)
{
    if (dir[0])
        scratch_remove_tree(dir);
}

static int load(const char *phase, const char *label)
{
    struct uwbd_override o[2] = {{NULL, NULL}, {NULL, NULL}};
    size_t n = 0;
    if (phase)
        o[n++] = (struct uwbd_override){"site.phase", phase};
    if (label)
        o[n++] = (struct uwbd_override){"site.label", label};
    return uwbd_config_load(SAMPLE, o, n, &cfg, err, sizeof err);
}

static void test_phase_and_label_load_and_default_to_none(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, load(NULL, NULL), err);
    TEST_ASSERT_EQUAL_STRING("", cfg.site_phase);
    TEST_ASSERT_EQUAL_STRING("", cfg.site_label);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, load("L2", "\"Hillside GT2, north window\""), err);
    TEST_ASSERT_EQUAL_STRING("L2", cfg.site_phase);
    TEST_ASSERT_EQUAL_STRING("Hillside GT2, north window", cfg.site_label);
}

static void test_bad_values_name_the_key(void)
{
    TEST_ASSERT_EQUAL_INT(-1, load("ABCDEFGH", NULL));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `site.phase`: too long (8 bytes, at most 7)"), err);
    TEST_ASSERT_EQUAL_INT(-1, load(NULL, "\"tab\\there\""));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `site.label`: contains a control character"), err);
    TEST_ASSERT_EQUAL_INT(-1, load(NULL, "3"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `site.label`: expected a string"), err);
}

static char *status_with(const char *phase, const char *label)
{
    struct uwbd_status st = {
        .version = "test",
        .state = "idle",
        .state_dir = "/var/lib/uwbd",
        .rig = "ready",
        .site_phase = phase,
        .site_label = label,
    };
    char *line = uwbd_reply_status(&st);
    TEST_ASSERT_NOT_NULL(line);
    return line;
}

static void test_status_shows_the_site(void)
{
    char *line = status_with("B", "Hillside GT2");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "\"site\":{\"phase\":\"B\",\"label\":\"Hillside GT2\"}"), line);
    free(line);
    line = status_with("", "Hillside GT2");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "\"site\":{\"label\":\"Hillside GT2\"}"), line);
    free(line);
    line = status_with("", NULL);
    TEST_ASSERT_NULL_MESSAGE(strstr(line, "\"site\""), line);
    free(line);
}

static void test_trend_caption_names_the_site(void)
{
    char text[128];
    snprintf(cfg.site_phase, sizeof cfg.site_phase, "B");
    snprintf(cfg.site_label, sizeof cfg.site_label, "Hillside GT2");
    uwbd_trend_site_text(&cfg, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("phase B, Hillside GT2", text);
    cfg.site_label[0] = '\0';
    uwbd_trend_site_text(&cfg, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("phase B", text);
    cfg.site_phase[0] = '\0';
    snprintf(cfg.site_label, sizeof cfg.site_label, "Hillside GT2");
    uwbd_trend_site_text(&cfg, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("Hillside GT2", text);
    cfg.site_label[0] = '\0';
    uwbd_trend_site_text(&cfg, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("", text);
    /* The asset id first, when set. */
    snprintf(cfg.site.asset_id, sizeof cfg.site.asset_id, "T3-north");
    uwbd_trend_site_text(&cfg, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("T3-north", text);
    snprintf(cfg.site_phase, sizeof cfg.site_phase, "B");
    snprintf(cfg.site_label, sizeof cfg.site_label, "Hillside GT2");
    uwbd_trend_site_text(&cfg, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("T3-north, phase B, Hillside GT2", text);
}

/* The Asset text chunk of a PNG, "" when there is none. */
static void asset_text(const char *path, char *out, size_t n)
{
    out[0] = '\0';
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, path);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    TEST_ASSERT_EQUAL_INT(0, setjmp(png_jmpbuf(png)));
    png_init_io(png, fp);
    png_read_info(png, info);
    png_textp texts;
    int count = 0;
    png_get_text(png, info, &texts, &count);
    for (int i = 0; i < count; i++)
        if (!strcmp(texts[i].key, "Asset"))
            snprintf(out, n, "%s", texts[i].text);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
}

static void test_trend_png_carries_the_asset_and_site(void)
{
    scratch_scratch_dir(dir, sizeof dir, "site");
    struct uwbd_store store;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, NULL, err, sizeof err), err);
    scratch_spit(store.verdict_log,
                 "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"S1\",\"created\":"
                 "\"2026-03-02T06:00:00Z\",\"axial_displacement_mm\":0.1,\"uncertainty_mm\":0.3}\n");
    cfg.evaluate.compare.thresholds.watch_m = 2e-3;
    cfg.evaluate.compare.thresholds.alarm_m = 5e-3;
    char path[1100], asset[256];
    uwbd_trend_png_path(&store, path, sizeof path);
    /* The asset id leads, and a UTF-8 label stays UTF-8 (in an iTXt
     * chunk: tEXt is Latin-1). */
    snprintf(cfg.site.asset_id, sizeof cfg.site.asset_id, "T3-north");
    snprintf(cfg.site_phase, sizeof cfg.site_phase, "B");
    snprintf(cfg.site_label, sizeof cfg.site_label, "S\u00fcd GT2");
    char site[256];
    uwbd_trend_site_text(&cfg, site, sizeof site);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_trend_png_update(&cfg, &store, site, err, sizeof err), err);
    asset_text(path, asset, sizeof asset);
    TEST_ASSERT_EQUAL_STRING("T3-north, phase B, S\u00fcd GT2", asset);
    TEST_ASSERT_EQUAL_INT(0, uwbd_trend_png_update(&cfg, &store, NULL, err, sizeof err));
    asset_text(path, asset, sizeof asset);
    TEST_ASSERT_EQUAL_STRING("", asset);

    /* The caption gets a line for it. */
    struct uwb_trend t = {0};
    struct uwb_trend_layout with, without;
    uwb_render_trend_layout(&t, &cfg.evaluate.compare.thresholds, "phase B", &with);
    uwb_render_trend_layout(&t, &cfg.evaluate.compare.thresholds, NULL, &without);
    TEST_ASSERT_EQUAL_INT(UWB_FONT_LINE_HEIGHT * 2 + 3, with.caption_h - without.caption_h);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_phase_and_label_load_and_default_to_none);
    RUN_TEST(test_bad_values_name_the_key);
    RUN_TEST(test_status_shows_the_site);
    RUN_TEST(test_trend_caption_names_the_site);
    RUN_TEST(test_trend_png_carries_the_asset_and_site);
    return UNITY_END();
}
