/* The trend: verdicts.jsonl read back as a displacement series with its
 * rate, `trend [N]` parsed, its TREND reply as text for people, and
 * trend.png read back with libpng (size, text chunks, an error bar's
 * pixels, a threshold line, the mark of a verdict without a figure). */
#include "unity.h"

#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "png_text_support.h"
#include "scratch_support.h"
#include "uwb/reply_text.h"
#include "uwb/cli.h"
#include "control/command.h"
#include "state/store.h"
#include "daemon/trend.h"
#include "output/render_trend.h"
#include "uwb/verdict_json.h"

static char dir[256];

void setUp(void)
{
    dir[0] = '\0';
}

void tearDown(void)
{
    if (dir[0])
        scratch_remove_tree(dir);
}

/* Ten days of verdicts: a baseline, figures growing by 0.1 mm/day against
 * it, an inconclusive one (which must not become a figure even though it
 * carries numbers), an error, a line that is not a verdict, then a new
 * baseline and two figures against it. */
static const char *const log_lines[] = {
    "{\"class\":\"VERDICT\",\"status\":\"edges\",\"scan_id\":\"B1\",\"created\":\"2026-03-01T06:00:00Z\","
    "\"baseline_set\":true,\"lower_edge_mm\":200,\"upper_edge_mm\":600}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"S2\",\"created\":\"2026-03-02T06:00:00Z\","
    "\"axial_displacement_mm\":0.1,\"uncertainty_mm\":0.3,\"height_change_mm\":0.05,\"baseline\":{\"scan_"
    "id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"S3\",\"created\":\"2026-03-03T06:00:00Z\","
    "\"axial_displacement_mm\":0.2,\"uncertainty_mm\":0.3,\"baseline\":{\"scan_id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"scan_id\":\"S4\",\"created\":\"2026-03-04T06:00:"
    "00Z\","
    "\"reason\":\"face echo too weak (SNR 3 dB)\",\"axial_displacement_mm\":9.9,\"uncertainty_mm\":0.1}",
    "not a verdict",
    "{\"class\":\"VERDICT\",\"status\":\"error\",\"scan_id\":\"S5\",\"created\":\"2026-03-05T06:00:00Z\","
    "\"reason\":\"digitiser did not answer\"}",
    "{\"class\":\"VERDICT\",\"status\":\"watch\",\"scan_id\":\"S6\",\"created\":\"2026-03-06T06:00:00Z\","
    "\"axial_displacement_mm\":3.0,\"uncertainty_mm\":0.5,\"height_change_mm\":-0.2,\"baseline\":{\"scan_"
    "id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"S7\",\"created\":\"2026-03-08T06:00:00Z\","
    "\"axial_displacement_mm\":0.0,\"uncertainty_mm\":0.2,\"baseline\":{\"scan_id\":\"B2\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"S8\",\"created\":\"2026-03-10T06:00:00Z\","
    "\"axial_displacement_mm\":-0.4,\"uncertainty_mm\":0.2,\"baseline\":{\"scan_id\":\"B2\"}}",
};
#define N_LINES ((int)(sizeof log_lines / sizeof log_lines[0]))

static void read_lines(struct uwb_trend *t)
{
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines((char *const *)log_lines, N_LINES, t));
}

static char *entry_text(const struct uwb_trend *t, int i)
{
    cJSON *o = uwb_record_trend_entry(&t->entries[i].summary, t->entries[i].became_baseline);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

/* The TREND reply's entry is the record's trend summary: what the line
 * said, a figure only where the verdict made one, the reason only without
 * one; and it reads back into the record. */
static void test_a_trend_entry_is_the_records_summary_and_reads_back(void)
{
    struct uwb_trend t;
    read_lines(&t);
    const char *const want[] = {
        "{\"created\":\"2026-03-01T06:00:00Z\",\"scan_id\":\"B1\",\"status\":\"edges\",\"baseline_set\":"
        "true}",
        "{\"created\":\"2026-03-02T06:00:00Z\",\"scan_id\":\"S2\",\"status\":\"ok\",\"axial_displacement_"
        "mm\":0.1,\"uncertainty_mm\":0.3,\"height_change_mm\":0.05,\"baseline\":\"B1\"}",
        NULL,
        "{\"created\":\"2026-03-04T06:00:00Z\",\"scan_id\":\"S4\",\"status\":\"inconclusive\",\"reason\":"
        "\"face echo too weak (SNR 3 dB)\"}",
    };
    for (int i = 0; i < 4; i++) {
        if (!want[i])
            continue;
        char *text = entry_text(&t, i);
        TEST_ASSERT_EQUAL_STRING(want[i], text);
        free(text);
    }
    cJSON *o = uwb_record_trend_entry(&t.entries[1].summary, t.entries[1].became_baseline);
    struct uwb_verdict_record *back = malloc(sizeof *back);
    char err[160] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_trend_entry(o, back, err, sizeof err), err);
    TEST_ASSERT_TRUE(back->has_displacement);
    TEST_ASSERT_EQUAL_DOUBLE(0.1, back->axial_displacement_mm);
    TEST_ASSERT_EQUAL_DOUBLE(0.3, back->uncertainty_mm);
    TEST_ASSERT_TRUE(back->has_height_change);
    TEST_ASSERT_EQUAL_STRING("B1", back->baseline_scan_id);
    TEST_ASSERT_FALSE(back->has_radial);
    cJSON_Delete(o);
    free(back);
    uwb_trend_free(&t);
}

static void test_verdicts_become_figures_only_where_the_verdict_made_one(void)
{
    struct uwb_trend t;
    read_lines(&t);
    TEST_ASSERT_EQUAL_INT(N_LINES - 1, t.count);
    TEST_ASSERT_EQUAL_INT(1, t.unreadable);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_EDGES, t.entries[0].summary.status);
    TEST_ASSERT_FALSE(t.entries[0].summary.has_displacement);
    TEST_ASSERT_TRUE(t.entries[1].summary.has_displacement);
    TEST_ASSERT_EQUAL_DOUBLE(0.1, t.entries[1].summary.axial_displacement_mm);
    TEST_ASSERT_EQUAL_DOUBLE(0.3, t.entries[1].summary.uncertainty_mm);
    TEST_ASSERT_TRUE(t.entries[1].summary.has_height_change);
    TEST_ASSERT_FALSE(t.entries[2].summary.has_height_change);
    /* The inconclusive verdict's numbers are not a figure. */
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_INCONCLUSIVE, t.entries[3].summary.status);
    TEST_ASSERT_FALSE(t.entries[3].summary.has_displacement);
    TEST_ASSERT_EQUAL_STRING("face echo too weak (SNR 3 dB)", t.entries[3].summary.reason);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ERROR, t.entries[4].summary.status);
    TEST_ASSERT_FALSE(t.entries[4].summary.has_displacement);
    TEST_ASSERT_TRUE(t.entries[1].has_time);
    TEST_ASSERT_EQUAL_INT64(86400, (long long)(t.entries[2].t - t.entries[1].t));
    uwb_trend_free(&t);
}

static void test_baseline_changes_are_marked(void)
{
    struct uwb_trend t;
    read_lines(&t);
    TEST_ASSERT_TRUE(t.entries[0].became_baseline);
    TEST_ASSERT_TRUE(t.entries[0].baseline_change);
    for (int i = 1; i < 6; i++)
        TEST_ASSERT_FALSE_MESSAGE(t.entries[i].baseline_change, t.entries[i].summary.scan_id);
    /* S7 is against B2, the scans before against B1. */
    TEST_ASSERT_TRUE(t.entries[6].baseline_change);
    TEST_ASSERT_FALSE(t.entries[6].became_baseline);
    TEST_ASSERT_FALSE(t.entries[7].baseline_change);
    uwb_trend_free(&t);
}

static void test_rate_counts_figures_since_the_last_baseline_change(void)
{
    struct uwb_trend t;
    read_lines(&t);
    /* Since B2: 0.0 then -0.4 two days later (over all figures it would
     * be three figures of a rising series): two figures, too few and too
     * short a span for a rate. */
    TEST_ASSERT_EQUAL_INT(2, t.rate.points);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 2.0, t.rate.days);
    TEST_ASSERT_FALSE(t.rate.known);
    TEST_ASSERT_EQUAL_STRING("2 figures over 2.0 days since the last baseline change; a rate needs at "
                             "least 4 figures over 7 days",
                             t.rate.withheld);
    uwb_trend_free(&t);

    /* Without the new baseline: the three B1 figures over four days. */
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines((char *const *)log_lines, 7, &t));
    TEST_ASSERT_FALSE(t.rate.known);
    TEST_ASSERT_EQUAL_INT(3, t.rate.points);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 4.0, t.rate.days);
    uwb_trend_free(&t);
}

static void test_one_figure_has_no_rate(void)
{
    struct uwb_trend t;
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines((char *const *)log_lines, 2, &t));
    TEST_ASSERT_FALSE(t.rate.known);
    TEST_ASSERT_EQUAL_INT(1, t.rate.points);
    TEST_ASSERT_EQUAL_STRING("1 figure since the last baseline change; a rate needs at least 4 figures over "
                             "7 days",
                             t.rate.withheld);
    uwb_trend_free(&t);
}

static void test_trend_command_parses_its_count(void)
{
    struct uwb_command cmd;
    char err[160];
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_OK, uwb_command_parse("trend", 5, &cmd, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_TREND, cmd.kind);
    TEST_ASSERT_EQUAL_INT(UWB_TREND_DEFAULT, cmd.count);
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_OK, uwb_command_parse("trend 7\r\n", 9, &cmd, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(7, cmd.count);
    TEST_ASSERT_EQUAL_STRING("trend", uwb_command_name(cmd.kind));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID, uwb_command_parse("trend 0", 7, &cmd, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "trend: N must be"));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID, uwb_command_parse("trend 101", 9, &cmd, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID, uwb_command_parse("trend 5 6", 9, &cmd, err, sizeof err));
}

static char *memstream_text;
static size_t memstream_len;

static char *trend_as_text(const char *reply)
{
    memstream_text = NULL;
    FILE *out = open_memstream(&memstream_text, &memstream_len);
    TEST_ASSERT_NOT_NULL(out);
    TEST_ASSERT_EQUAL_INT(0, uwbd_trend_text(reply, out));
    fclose(out);
    return memstream_text;
}

/* Terminal column (characters, not bytes) of `at` in its line. */
static int column_of(const char *text, const char *at)
{
    const char *line = at;
    while (line > text && line[-1] != '\n')
        line--;
    int col = 0;
    for (const unsigned char *c = (const unsigned char *)line; c < (const unsigned char *)at; c++)
        col += (*c & 0xC0) != 0x80;
    return col;
}

static void test_trend_reply_reads_as_a_table(void)
{
    struct uwb_trend t;
    read_lines(&t);
    struct uwb_thresholds th = {.watch_m = 2e-3, .alarm_m = 5e-3};
    char *reply = uwbd_reply_trend(&t, 20, &th, "/var/lib/uwbd/trend.png");
    TEST_ASSERT_NOT_NULL(reply);
    TEST_ASSERT_NOT_NULL(strstr(reply, "\"class\":\"TREND\""));
    /* Two figures over two days since B2: no rate, and why. */
    TEST_ASSERT_NULL(strstr(reply, "mm_per_year"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reply,
                                        "\"withheld\":\"2 figures over 2.0 days since the last "
                                        "baseline change; a rate needs at least 4 figures over 7 days\""),
                                 reply);
    char *text = trend_as_text(reply);
    /* One line per verdict, oldest first, with what a person needs. */
    const char *ok = strstr(text, "2026-03-02T06:00:00Z");
    const char *inc = strstr(text, "2026-03-04T06:00:00Z");
    TEST_ASSERT_NOT_NULL(ok);
    TEST_ASSERT_NOT_NULL(inc);
    TEST_ASSERT_TRUE(ok < inc);
    TEST_ASSERT_NOT_NULL(strstr(ok, "OK"));
    TEST_ASSERT_NOT_NULL(strstr(ok, "+0.10 \u00b1 0.30 mm"));
    TEST_ASSERT_NOT_NULL(strstr(ok, "+0.05 mm"));
    /* The inconclusive verdict says so and why, with no figure. */
    const char *inc_end = strchr(strchr(inc, '\n') + 1, '\n');
    char row[512];
    snprintf(row, sizeof row, "%.*s", (int)(inc_end - inc), inc);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(row, "INCONCLUSIVE"), row);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(row, "no figure"), row);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(row, "face echo too weak"), row);
    TEST_ASSERT_NULL_MESSAGE(strstr(row, "9.9"), row);
    /* The baseline change is starred on S7's line. */
    const char *s7 = strstr(text, "2026-03-08T06:00:00Z");
    TEST_ASSERT_NOT_NULL(s7);
    TEST_ASSERT_EQUAL_STRING_LEN(" * OK", s7 + 20, 5);
    /* Columns line up on a terminal ("±" and "σ" are two bytes each):
     * every scan id under the header's "scan". */
    int scan_col = column_of(text, strstr(text, "scan\n"));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "S2\n")));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "S3\n")));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "S6\n")));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "S4\n")));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text,
                                        "rate: not known yet (2 figures over 2.0 days since the last "
                                        "baseline change; a rate needs at least 4 figures over 7 days)\n"),
                                 text);
    TEST_ASSERT_NOT_NULL(strstr(text, "watch from 2.00 mm, alarm from 5.00 mm"));
    TEST_ASSERT_NOT_NULL(strstr(text, "1 line of verdicts.jsonl could not be read"));
    TEST_ASSERT_NOT_NULL(strstr(text, "image: /var/lib/uwbd/trend.png"));
    /* Anything else is not a trend. */
    TEST_ASSERT_EQUAL_INT(-1, uwbd_trend_text("{\"class\":\"HISTORY\",\"verdicts\":[]}", stdout));
    free(text);
    free(reply);
    uwb_trend_free(&t);
}

/* ---- trend.png, written from a state directory's verdicts.jsonl ---- */

struct png_read {
    int w, h;
    unsigned char *px;
    char description[2048];
    int text_ascii;
};

static struct png_read read_png(const char *path)
{
    struct png_read out;
    memset(&out, 0, sizeof out);
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, path);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    TEST_ASSERT_EQUAL_INT(0, setjmp(png_jmpbuf(png)));
    png_init_io(png, fp);
    png_read_info(png, info);
    out.w = (int)png_get_image_width(png, info);
    out.h = (int)png_get_image_height(png, info);
    TEST_ASSERT_EQUAL_INT(PNG_COLOR_TYPE_RGB, png_get_color_type(png, info));
    TEST_ASSERT_EQUAL_INT(8, png_get_bit_depth(png, info));
    png_textp texts;
    int n = 0;
    png_get_text(png, info, &texts, &n);
    out.text_ascii = 1;
    for (int i = 0; i < n; i++) {
        for (const unsigned char *c = (const unsigned char *)texts[i].text; *c; c++)
            out.text_ascii &= *c < 0x80;
        if (!strcmp(texts[i].key, "Description"))
            snprintf(out.description, sizeof out.description, "%s", texts[i].text);
    }
    size_t row_bytes = (size_t)out.w * 3;
    out.px = malloc(row_bytes * (size_t)out.h);
    TEST_ASSERT_NOT_NULL(out.px);
    for (int y = 0; y < out.h; y++)
        png_read_row(png, out.px + row_bytes * (size_t)y, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return out;
}

static struct uwb_rgb pixel(const struct png_read *p, int x, int y)
{
    TEST_ASSERT_TRUE(x >= 0 && y >= 0 && x < p->w && y < p->h);
    const unsigned char *q = p->px + ((size_t)y * (size_t)p->w + (size_t)x) * 3;
    struct uwb_rgb c = {q[0], q[1], q[2]};
    return c;
}

static int is(struct uwb_rgb a, struct uwb_rgb b)
{
    return a.r == b.r && a.g == b.g && a.b == b.b;
}

/* Row of a displacement from the documented mapping (top row y_max). */
static int row_of(const struct uwb_plot *p, double y)
{
    return p->y + (int)lround((p->y_max - y) / (p->y_max - p->y_min) * (p->h - 1));
}

static void write_state(struct uwbd_store *store, int lines)
{
    scratch_scratch_dir(dir, sizeof dir, "trend");
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(store, dir, NULL, err, sizeof err), err);
    size_t len = 0;
    for (int i = 0; i < lines; i++)
        len += strlen(log_lines[i]) + 1;
    char *text = calloc(len + 1, 1);
    TEST_ASSERT_NOT_NULL(text);
    for (int i = 0; i < lines; i++) {
        strcat(text, log_lines[i]);
        strcat(text, "\n");
    }
    scratch_spit(store->verdict_log, text);
    free(text);
}

/* Issue 48, finding 9: the rate is the log's, not the table's. On the
 * same log `trend 1` said "1 figure since the last baseline change" and
 * `trend` 2: the count (and the rate) must not depend on how many rows
 * were asked for. S7 and S8 are the figures since B2. */
static void test_rate_does_not_depend_on_how_many_rows_are_asked_for(void)
{
    struct uwbd_store store;
    write_state(&store, N_LINES);
    char err[512];
    struct uwb_trend all, one;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_trend_read(&store, 20, &all, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_trend_read(&store, 1, &one, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(N_LINES - 1, all.count);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, one.count, "the table keeps the rows asked for");
    TEST_ASSERT_EQUAL_STRING("S8", one.entries[0].summary.scan_id);
    TEST_ASSERT_EQUAL_INT(2, all.rate.points);
    TEST_ASSERT_EQUAL_INT(all.rate.points, one.rate.points);
    TEST_ASSERT_EQUAL_INT(all.rate.known, one.rate.known);
    TEST_ASSERT_EQUAL_STRING(all.rate.withheld, one.rate.withheld);
    uwb_trend_free(&all);
    uwb_trend_free(&one);
}

/* Issue 48, findings 5 and 6: `trend` cuts no reason (it lost "axial
 * figure withheld" at 160 bytes) and in ASCII writes "+/-" and "sigma". */
static void test_trend_text_keeps_the_whole_reason_and_can_be_ascii(void)
{
    static const char reason[] =
        "the face changed shape (the ends moved apart by 4 mm and the echo weakened at 420 mm, not a "
        "shift without its changed rows): radial change read where its rows still match, axial figure "
        "withheld";
    char line[1024];
    snprintf(line, sizeof line,
             "{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"scan_id\":\"S9\",\"created\":"
             "\"2026-03-11T06:00:00Z\",\"reason\":\"%s\"}",
             reason);
    char *lines[N_LINES + 1];
    for (int i = 0; i < N_LINES; i++)
        lines[i] = (char *)log_lines[i];
    lines[N_LINES] = line;
    struct uwb_trend t;
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines(lines, N_LINES + 1, &t));
    struct uwb_thresholds th = {.watch_m = 2e-3, .alarm_m = 5e-3};
    char *reply = uwbd_reply_trend(&t, 20, &th, NULL);
    TEST_ASSERT_NOT_NULL(reply);
    for (int charset = UWBD_CHARSET_UTF8; charset <= UWBD_CHARSET_ASCII; charset++) {
        char *text = NULL;
        size_t n = 0;
        FILE *f = open_memstream(&text, &n);
        TEST_ASSERT_EQUAL_INT(0, uwbd_trend_text_in(reply, f, (enum uwbd_charset)charset));
        fclose(f);
        TEST_ASSERT_TRUE_MESSAGE(strstr(text, "axial figure\n") || strstr(text, "axial figure withheld"),
                                 text);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "withheld\n"), text);
        /* The reason's lines stay within 79 columns, words whole. */
        const char *r = strstr(text, "the face changed shape");
        TEST_ASSERT_NOT_NULL_MESSAGE(r, text);
        while (r > text && r[-1] != '\n')
            r--;
        for (const char *l = r; *l && strncmp(l, "rate:", 5) != 0; l += strcspn(l, "\n") + 1)
            TEST_ASSERT_TRUE_MESSAGE(strcspn(l, "\n") <= 79, text);
        int ascii = 1;
        for (const char *c = text; *c; c++)
            ascii &= (unsigned char)*c < 0x80;
        /* The height column says what it holds, as history's does. */
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "  height change  "), text);
        if (charset == UWBD_CHARSET_ASCII) {
            TEST_ASSERT_TRUE_MESSAGE(ascii, text);
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "displacement +/- 1 sigma"), text);
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "+3.00 +/- 0.50 mm"), text);
        } else {
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "+3.00 \u00b1 0.50 mm"), text);
        }
        free(text);
    }
    free(reply);
    uwb_trend_free(&t);
}

static void test_trend_png_shows_bars_thresholds_and_no_figure_marks(void)
{
    struct uwbd_store store;
    write_state(&store, N_LINES);
    struct uwbd_config cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.evaluate.compare.thresholds.watch_m = 2e-3;
    cfg.evaluate.compare.thresholds.alarm_m = 5e-3;
    char err[512], path[1100];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_trend_png_update(&cfg, &store, NULL, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, uwbd_trend_png_path(&store, path, sizeof path));
    TEST_ASSERT_NOT_NULL(strstr(path, "/trend.png"));
    struct png_read png = read_png(path);
    TEST_ASSERT_EQUAL_INT(UWB_TREND_PNG_WIDTH, png.w);
    TEST_ASSERT_EQUAL_INT(UWB_TREND_PNG_HEIGHT, png.h);
    TEST_ASSERT_TRUE_MESSAGE(png.text_ascii, "tEXt is Latin-1: ASCII only");
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(png.description, "8 verdicts: 5 with a figure, 1 inconclusive, 1 error, 1 edges"),
        png.description);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(png.description, "bars +/-2 sigma"), png.description);

    struct uwb_trend t;
    TEST_ASSERT_EQUAL_INT(0, uwbd_trend_read(&store, UWBD_TREND_PNG_VERDICTS, &t, err, sizeof err));
    struct uwb_trend_layout l;
    uwb_render_trend_layout(&t, &cfg.evaluate.compare.thresholds, NULL, &l);
    const struct uwb_plot *p = &l.plot;
    const struct uwb_rgb ink = {25, 25, 25}, white = {255, 255, 255};

    /* S6: +3.0 mm, sigma 0.5: its bar runs from +2.0 to +4.0 mm in its
     * column; between the marker and the cap the column is the bar's ink
     * and the columns beside it are not. */
    const struct uwb_trend_entry *s6 = &t.entries[5];
    TEST_ASSERT_EQUAL_STRING("S6", s6->summary.scan_id);
    int col = uwb_trend_col(&l, s6->t);
    int row = row_of(p, 3.0 + 1.5 * 0.5);
    TEST_ASSERT_TRUE_MESSAGE(row < row_of(p, 3.0) - 6, "the bar reaches past the marker");
    TEST_ASSERT_TRUE(is(pixel(&png, col, row), ink));
    TEST_ASSERT_FALSE(is(pixel(&png, col + 2, row), ink));
    TEST_ASSERT_FALSE(is(pixel(&png, col - 2, row), ink));
    /* The cap at +2 sigma (4.0 mm), and nothing of the bar above it: the
     * page there is as it is beside the bar (tinted: the watch zone). */
    int cap = row_of(p, 3.0 + 2.0 * 0.5);
    TEST_ASSERT_TRUE(is(pixel(&png, col + 4, cap), ink));
    TEST_ASSERT_TRUE(is(pixel(&png, col, cap - 3), pixel(&png, col + 30, cap - 3)));
    TEST_ASSERT_FALSE(is(pixel(&png, col, cap - 3), ink));
    /* Its marker is in the watch colour. */
    TEST_ASSERT_TRUE(is(pixel(&png, col, row_of(p, 3.0)), uwb_status_colour(UWB_STATUS_WATCH)));

    /* The alarm threshold: a solid line at +5 mm and -5 mm. */
    int alarm_rows[2] = {row_of(p, 5.0), row_of(p, -5.0)};
    for (int k = 0; k < 2; k++)
        TEST_ASSERT_TRUE(is(pixel(&png, p->x + 5, alarm_rows[k]), uwb_status_colour(UWB_STATUS_ALARM)));
    /* The zones between the lines are tinted: watch (2..5 mm either way)
     * and alarm (beyond 5 mm) in their colours over the page, ok not. */
    int clear = p->x + 3;
    TEST_ASSERT_TRUE(is(pixel(&png, clear, row_of(p, 1.0)), white));
    TEST_ASSERT_TRUE(is(pixel(&png, clear, row_of(p, -1.0)), white));
    for (int sign = -1; sign <= 1; sign += 2) {
        TEST_ASSERT_TRUE(is(pixel(&png, clear, row_of(p, sign * 3.5)),
                            uwb_rgb_blend(white, uwb_status_colour(UWB_STATUS_WATCH), 0.12)));
        TEST_ASSERT_TRUE(is(pixel(&png, clear, row_of(p, sign * 5.6)),
                            uwb_rgb_blend(white, uwb_status_colour(UWB_STATUS_ALARM), 0.12)));
    }

    /* S4, inconclusive with numbers in its line: nothing in the plot at
     * its time (no marker, no bar), a grey mark in the strip above. */
    const struct uwb_trend_entry *s4 = &t.entries[3];
    int c4 = uwb_trend_col(&l, s4->t);
    for (int y = p->y; y <= row_of(p, 0.5); y++)
        TEST_ASSERT_FALSE(is(pixel(&png, c4, y), ink));
    int marked = 0;
    for (int y = l.strip_y; y < l.strip_y + l.strip_h; y++)
        for (int x = c4 - 6; x <= c4 + 6; x++)
            marked += is(pixel(&png, x, y), uwb_status_colour(UWB_STATUS_INCONCLUSIVE));
    TEST_ASSERT_TRUE_MESSAGE(marked > 5, "the inconclusive verdict's mark");

    free(png.px);
    uwb_trend_free(&t);
}

static void test_trend_png_of_an_empty_log_still_draws(void)
{
    struct uwbd_store store;
    write_state(&store, 0);
    struct uwbd_config cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.evaluate.compare.thresholds.watch_m = 2e-3;
    cfg.evaluate.compare.thresholds.alarm_m = 5e-3;
    char err[512], path[1100];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_trend_png_update(&cfg, &store, "T1 phase B", err, sizeof err), err);
    uwbd_trend_png_path(&store, path, sizeof path);
    struct png_read png = read_png(path);
    TEST_ASSERT_EQUAL_INT(UWB_TREND_PNG_WIDTH, png.w);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(png.description, "0 verdicts"), png.description);
    free(png.px);
}

static void test_trend_png_failure_names_the_file_and_leaves_no_temporary(void)
{
    struct uwbd_store store;
    write_state(&store, 3);
    struct uwbd_config cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.evaluate.compare.thresholds.watch_m = 2e-3;
    cfg.evaluate.compare.thresholds.alarm_m = 5e-3;
    char err[512], path[1100], inside[1200];
    /* Something that is not ours where trend.png goes (a directory with a
     * file in it; modes would not stop root): the update fails and says
     * where, and leaves that alone and no temporary behind. */
    uwbd_trend_png_path(&store, path, sizeof path);
    TEST_ASSERT_EQUAL_INT(0, mkdir(path, 0755));
    snprintf(inside, sizeof inside, "%s/keep", path);
    scratch_spit(inside, "mine");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_trend_png_update(&cfg, &store, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "trend.png"), err);
    TEST_ASSERT_TRUE(scratch_file_exists(inside));
    DIR *d = opendir(dir);
    TEST_ASSERT_NOT_NULL(d);
    struct dirent *e;
    int entries = 0;
    while ((e = readdir(d)) != NULL)
        entries += e->d_name[0] != '.';
    closedir(d);
    /* archive, baseline, verdicts.jsonl, trend.png (the directory) */
    TEST_ASSERT_EQUAL_INT(4, entries);
}

/* ---- the rate only where the span and the figures support it ---- */

#define SERIES_MAX 16
static char series_text[SERIES_MAX][400];
static char *series_lines[SERIES_MAX];

/* n ok verdicts against one baseline, step_s apart from 2026-05-01
 * 08:00:00Z, figure i mm[i] with 1-sigma sigma[i]. */
static void series(struct uwb_trend *t, int n, long step_s, const double *mm, const double *sigma)
{
    TEST_ASSERT_TRUE(n <= SERIES_MAX);
    for (int i = 0; i < n; i++) {
        time_t when = (time_t)1777622400 + (time_t)(step_s * i);
        struct tm tm;
        char created[32];
        gmtime_r(&when, &tm);
        strftime(created, sizeof created, "%Y-%m-%dT%H:%M:%SZ", &tm);
        snprintf(series_text[i], sizeof series_text[i],
                 "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"R%d\",\"created\":\"%s\","
                 "\"axial_displacement_mm\":%.2f,\"uncertainty_mm\":%.2f,\"baseline\":{\"scan_id\":\"B1\"}}",
                 i, created, mm[i], sigma[i]);
        series_lines[i] = series_text[i];
    }
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines(series_lines, n, t));
    TEST_ASSERT_EQUAL_INT(n, t->rate.points);
}

static const double sigma_03[SERIES_MAX] = {0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3,
                                            0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3};

/* The reply, its text form and trend.png for a series. */
struct trend_forms {
    char *reply, *text;
    struct png_read png;
    struct uwb_trend_layout layout;
};

static struct trend_forms trend_forms(const struct uwb_trend *t)
{
    struct trend_forms f;
    struct uwb_thresholds th = {.watch_m = 2e-3, .alarm_m = 5e-3};
    f.reply = uwbd_reply_trend(t, 20, &th, NULL);
    TEST_ASSERT_NOT_NULL(f.reply);
    f.text = trend_as_text(f.reply);
    scratch_scratch_dir(dir, sizeof dir, "trend-rate");
    char path[512], err[512];
    snprintf(path, sizeof path, "%s/trend.png", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_trend_png(path, t, &th, NULL, err, sizeof err), err);
    f.png = read_png(path);
    uwb_render_trend_layout(t, &th, NULL, &f.layout);
    return f;
}

static void trend_forms_free(struct trend_forms *f)
{
    free(f->reply);
    free(f->text);
    free(f->png.px);
}

/* Nothing of the caption reaches the image's right edge: every line of
 * it ends inside the page. */
static void assert_caption_inside(const struct png_read *png, const struct uwb_trend_layout *l)
{
    const struct uwb_rgb white = {255, 255, 255};
    for (int y = 0; y < l->caption_h - 6; y++)
        for (int x = png->w - 12; x < png->w; x++)
            TEST_ASSERT_TRUE_MESSAGE(is(pixel(png, x, y), white), "the caption runs off the right edge");
}

/* A rate withheld: no figure in the reply, its reason instead, and the
 * same words in the text, the caption and the PNG's Description. */
static void assert_rate_withheld(const struct uwb_trend *t, const char *reason)
{
    TEST_ASSERT_FALSE(t->rate.known);
    TEST_ASSERT_EQUAL_STRING(reason, t->rate.withheld);
    struct trend_forms f = trend_forms(t);
    TEST_ASSERT_NULL_MESSAGE(strstr(f.reply, "mm_per_year"), f.reply);
    char want[400];
    snprintf(want, sizeof want, "\"withheld\":\"%s\"", reason);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.reply, want), f.reply);
    snprintf(want, sizeof want, "rate: not known yet (%s)\n", reason);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.text, want), f.text);
    TEST_ASSERT_NULL_MESSAGE(strstr(f.text, "mm/year"), f.text);
    snprintf(want, sizeof want, "rate not known yet: %s;", reason);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.png.description, want), f.png.description);
    TEST_ASSERT_NULL_MESSAGE(strstr(f.png.description, "mm/year"), f.png.description);
    assert_caption_inside(&f.png, &f.layout);
    trend_forms_free(&f);
}

static void test_two_figures_a_minute_apart_give_no_rate(void)
{
    /* As measured: -167069.65 +/- 971341.11 mm/year "over 0.0 days". */
    const double mm[2] = {0.42, 0.10};
    struct uwb_trend t;
    series(&t, 2, 60, mm, sigma_03);
    assert_rate_withheld(&t, "2 figures over 1 min since the last baseline change; a rate needs at least 4 "
                             "figures over 7 days");
    uwb_trend_free(&t);
}

static void test_nine_figures_in_four_minutes_give_no_rate(void)
{
    /* A steady drift of 0.15 mm every 30 s: as measured, +191765 mm/year
     * at 4 sigma from the figures' own sigmas. */
    double mm[9];
    for (int i = 0; i < 9; i++)
        mm[i] = -0.6 + 0.15 * i;
    struct uwb_trend t;
    series(&t, 9, 30, mm, sigma_03);
    assert_rate_withheld(&t, "9 figures over 4 min since the last baseline change; a rate needs at least 4 "
                             "figures over 7 days");
    uwb_trend_free(&t);
}

static void test_rate_needs_both_the_figures_and_the_span(void)
{
    const double mm[8] = {0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4};
    struct uwb_trend t;
    /* Three figures over eight days: too few. */
    series(&t, 3, 4L * 86400, mm, sigma_03);
    TEST_ASSERT_FALSE(t.rate.known);
    TEST_ASSERT_EQUAL_STRING("3 figures over 8.0 days since the last baseline change; a rate needs at least "
                             "4 figures over 7 days",
                             t.rate.withheld);
    uwb_trend_free(&t);
    /* Eight figures over 6.9 days: too short. */
    series(&t, 8, (long)(6.9 * 86400 / 7), mm, sigma_03);
    TEST_ASSERT_FALSE(t.rate.known);
    TEST_ASSERT_EQUAL_STRING("8 figures over 6.9 days since the last baseline change; a rate needs at least "
                             "4 figures over 7 days",
                             t.rate.withheld);
    uwb_trend_free(&t);
    /* Four figures over seven days: both met. */
    series(&t, 4, 7L * 86400 / 3, mm, sigma_03);
    TEST_ASSERT_TRUE(t.rate.known);
    TEST_ASSERT_EQUAL_STRING("", t.rate.withheld);
    uwb_trend_free(&t);
}

/* Weighted least squares by hand: slope and its 1-sigma from the
 * figures' sigmas, and the reduced chi-square about the line. */
static void fit(int n, const double *x, const double *y, const double *s, double *slope, double *sigma,
                double *chi2_per_dof)
{
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < n; i++) {
        double w = 1.0 / (s[i] * s[i]);
        sw += w;
        sx += w * x[i];
        sy += w * y[i];
        sxx += w * x[i] * x[i];
        sxy += w * x[i] * y[i];
    }
    double det = sw * sxx - sx * sx;
    *slope = (sw * sxy - sx * sy) / det;
    *sigma = sqrt(sw / det);
    double a = (sy - *slope * sx) / sw, chi2 = 0;
    for (int i = 0; i < n; i++) {
        double r = (y[i] - a - *slope * x[i]) / s[i];
        chi2 += r * r;
    }
    *chi2_per_dof = chi2 / (n - 2);
}

static void test_rate_over_a_week_is_given_with_its_sigma(void)
{
    /* Eight daily figures, 0.2 mm/day, scattering less than their
     * unequal sigmas say: the weighted slope and its sigma as they are. */
    const double mm[8] = {0.0, 0.25, 0.35, 0.6, 0.85, 0.95, 1.2, 1.45};
    const double sig[8] = {0.3, 0.3, 0.3, 0.5, 0.5, 0.3, 0.3, 0.2};
    double x[8], slope, sigma, chi2;
    for (int i = 0; i < 8; i++)
        x[i] = i;
    fit(8, x, mm, sig, &slope, &sigma, &chi2);
    TEST_ASSERT_TRUE(chi2 < 1.0);
    struct uwb_trend t;
    series(&t, 8, 86400, mm, sig);
    TEST_ASSERT_TRUE_MESSAGE(t.rate.known, t.rate.withheld);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 7.0, t.rate.days);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, slope, t.rate.mm_per_day);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, sigma, t.rate.sigma_mm_per_day);
    struct trend_forms f = trend_forms(&t);
    char want[200];
    snprintf(want, sizeof want, "\"mm_per_year\":%.2f,\"sigma_mm_per_year\":%.2f", slope * 365.25,
             sigma * 365.25);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.reply, want), f.reply);
    TEST_ASSERT_NULL_MESSAGE(strstr(f.reply, "withheld"), f.reply);
    snprintf(want, sizeof want, "rate: %+.2f \u00b1 %.2f mm/year (1\u03c3) over 7.0 days, 8 figures",
             slope * 365.25, sigma * 365.25);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.text, want), f.text);
    snprintf(want, sizeof want, "rate %+.2f +/- %.2f mm/year (1 sigma), 8 figures over 7.0 days",
             slope * 365.25, sigma * 365.25);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.png.description, want), f.png.description);
    assert_caption_inside(&f.png, &f.layout);
    trend_forms_free(&f);
    uwb_trend_free(&t);

    /* The same drift scattering +/-0.5 mm about it, each figure claiming
     * 0.1 mm: the slope's sigma widens by sqrt(chi2 / (n - 2)). */
    double noisy[8], tight[8];
    for (int i = 0; i < 8; i++) {
        noisy[i] = 0.2 * i + (i % 2 ? 0.5 : -0.5);
        tight[i] = 0.1;
    }
    fit(8, x, noisy, tight, &slope, &sigma, &chi2);
    TEST_ASSERT_TRUE(chi2 > 4.0);
    series(&t, 8, 86400, noisy, tight);
    TEST_ASSERT_TRUE(t.rate.known);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, slope, t.rate.mm_per_day);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, sigma * sqrt(chi2), t.rate.sigma_mm_per_day);
    uwb_trend_free(&t);
}

static void test_a_short_trend_is_drawn_at_its_own_scale(void)
{
    /* Two figures a minute apart: they spread across the plot, not into
     * 1/60 of it (it was padded to an hour), and the time axis says
     * which minute. */
    const double mm[2] = {0.42, 0.10};
    struct uwb_trend t;
    series(&t, 2, 60, mm, sigma_03);
    struct trend_forms f = trend_forms(&t);
    const struct uwb_plot *p = &f.layout.plot;
    int a = uwb_trend_col(&f.layout, t.entries[0].t), b = uwb_trend_col(&f.layout, t.entries[1].t);
    TEST_ASSERT_TRUE_MESSAGE(b - a > p->w / 2, "a minute's figures squeezed together");
    TEST_ASSERT_TRUE(a > p->x && b < p->x + p->w - 1);
    trend_forms_free(&f);
    uwb_trend_free(&t);
}

/* The radial change over time (issue 30): a second series in the reply,
 * its text and trend.png; verdicts without a radial object (older lines)
 * and radial figures withheld are left out of it, never read as 0. */
static const char *const radial_lines[] = {
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"R1\",\"created\":\"2026-03-01T06:00:00Z\","
    "\"axial_displacement_mm\":0.1,\"uncertainty_mm\":0.3,\"baseline\":{\"scan_id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"watch\",\"scan_id\":\"R2\",\"created\":\"2026-03-02T06:00:00Z\","
    "\"axial_displacement_mm\":0.2,\"uncertainty_mm\":0.3,\"radial\":{\"status\":\"watch\",\"max_change_"
    "mm\":3.11,\"at_mm\":267,\"uncertainty_mm\":0.39,\"tilt_mm\":-1.4},\"baseline\":{\"scan_id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"R3\",\"created\":\"2026-03-03T06:00:00Z\","
    "\"axial_displacement_mm\":0.0,\"uncertainty_mm\":0.3,\"radial\":{\"status\":\"inconclusive\","
    "\"withheld\":\"too few rows of the face are bright enough\"},\"baseline\":{\"scan_id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"R4\",\"created\":\"2026-03-04T06:00:00Z\","
    "\"axial_displacement_mm\":-0.1,\"uncertainty_mm\":0.3,\"radial\":{\"status\":\"ok\",\"max_change_mm\":"
    "-0.5,\"at_mm\":300,\"uncertainty_mm\":0.2,\"tilt_mm\":0.1},\"baseline\":{\"scan_id\":\"B1\"}}",
};

/* Pixels of the radial series' ink in a column band around col. */
static int radial_ink_near(const struct png_read *png, const struct uwb_plot *p, int col)
{
    int n = 0;
    for (int y = p->y; y < p->y + p->h; y++)
        for (int x = col - 12; x <= col + 12; x++)
            n += is(pixel(png, x, y), UWB_TREND_RADIAL_INK);
    return n;
}

static void test_radial_change_is_a_second_series(void)
{
    struct uwb_trend t;
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines((char *const *)radial_lines, 4, &t));
    TEST_ASSERT_EQUAL_INT(4, t.count);
    TEST_ASSERT_FALSE(t.entries[0].summary.has_radial);
    TEST_ASSERT_FALSE(t.entries[0].summary.radial_measured);
    TEST_ASSERT_TRUE(t.entries[1].summary.radial_measured);
    TEST_ASSERT_EQUAL_DOUBLE(3.11, t.entries[1].summary.radial_max_change_mm);
    TEST_ASSERT_EQUAL_DOUBLE(0.39, t.entries[1].summary.radial_uncertainty_mm);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_WATCH, t.entries[1].summary.radial_status);
    TEST_ASSERT_TRUE(t.entries[2].summary.has_radial);
    TEST_ASSERT_FALSE(t.entries[2].summary.radial_measured);
    TEST_ASSERT_TRUE(t.entries[3].summary.radial_measured);

    struct uwb_thresholds th = {.watch_m = 2e-3, .alarm_m = 5e-3};
    char *reply = uwbd_reply_trend(&t, 20, &th, NULL);
    TEST_ASSERT_NOT_NULL(reply);
    const char *r1 = strstr(reply, "\"scan_id\":\"R1\""), *r2 = strstr(reply, "\"scan_id\":\"R2\"");
    const char *r3 = strstr(reply, "\"scan_id\":\"R3\"");
    TEST_ASSERT_TRUE(r1 && r2 && r3);
    char one[512];
    snprintf(one, sizeof one, "%.*s", (int)(r2 - r1), r1);
    TEST_ASSERT_NULL_MESSAGE(strstr(one, "radial"), one);
    snprintf(one, sizeof one, "%.*s", (int)(r3 - r2), r2);
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(one,
               "\"radial_status\":\"watch\",\"radial_max_change_mm\":3.11,\"radial_uncertainty_mm\":0.39"),
        one);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r3, "\"radial_status\":\"inconclusive\""), r3);
    snprintf(one, sizeof one, "%.*s", (int)(strstr(r3, "}") - r3), r3);
    TEST_ASSERT_NULL_MESSAGE(strstr(one, "radial_max_change_mm"), one);

    char *text = trend_as_text(reply);
    const char *line1 = strstr(text, "2026-03-01T06:00:00Z"), *line2 = strstr(text, "2026-03-02T06:00:00Z");
    const char *line3 = strstr(text, "2026-03-03T06:00:00Z");
    TEST_ASSERT_TRUE(line1 && line2 && line3);
    TEST_ASSERT_NOT_NULL(strstr(text, "radial \u00b1 1\u03c3"));
    snprintf(one, sizeof one, "%.*s", (int)(strchr(line2, '\n') - line2), line2);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(one, "+3.11 \u00b1 0.39 mm watch"), one);
    snprintf(one, sizeof one, "%.*s", (int)(strchr(line3, '\n') - line3), line3);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(one, "inconclusive"), one);
    /* Scan ids still line up under "scan". */
    int scan_col = column_of(text, strstr(text, "scan\n"));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "R1\n")));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "R2\n")));
    TEST_ASSERT_EQUAL_INT(scan_col, column_of(text, strstr(text, "R3\n")));
    free(text);
    free(reply);

    scratch_scratch_dir(dir, sizeof dir, "trend");
    char path[600], err[512];
    snprintf(path, sizeof path, "%s/trend.png", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_trend_png(path, &t, &th, NULL, err, sizeof err), err);
    struct png_read png = read_png(path);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(png.description, "2 radial figures, latest -0.50 +/- 0.20 mm (ok)"),
                                 png.description);
    struct uwb_trend_layout l;
    uwb_render_trend_layout(&t, &th, NULL, &l);
    TEST_ASSERT_EQUAL_INT(0, radial_ink_near(&png, &l.plot, uwb_trend_col(&l, t.entries[0].t)));
    TEST_ASSERT_TRUE(radial_ink_near(&png, &l.plot, uwb_trend_col(&l, t.entries[1].t)) > 10);
    /* R2's marker: in the watch colour at +3.11 mm, beside the axial one. */
    int col = uwb_trend_col(&l, t.entries[1].t) + UWB_TREND_RADIAL_OFFSET;
    TEST_ASSERT_TRUE(is(pixel(&png, col, row_of(&l.plot, 3.11)), uwb_status_colour(UWB_STATUS_WATCH)));
    free(png.px);
    uwb_trend_free(&t);
}

/* Finding 7 of issue 48, trend.png as an engineer reads it without the
 * manual: a minute-scale morning with a +12 mm figure, an inconclusive
 * verdict, a radial alarm whose axial figure was withheld, a figure of
 * 0 mm, all against one baseline, and last an inconclusive verdict with
 * a long reason. */
static const char *const engineer_lines[] = {
    "{\"class\":\"VERDICT\",\"status\":\"alarm\",\"scan_id\":\"E1\",\"created\":\"2026-12-07T03:20:05Z\","
    "\"axial_displacement_mm\":12.0,\"uncertainty_mm\":0.3,\"baseline\":{\"scan_id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"scan_id\":\"E2\",\"created\":\"2026-12-07T03:21:"
    "10Z\",\"reason\":\"face echo too weak\"}",
    "{\"class\":\"VERDICT\",\"status\":\"alarm\",\"scan_id\":\"E3\",\"created\":\"2026-12-07T03:22:15Z\","
    "\"reason\":\"axial figure withheld: the face changed shape\",\"radial\":{\"status\":\"alarm\","
    "\"max_change_mm\":6.2,\"at_mm\":300,\"uncertainty_mm\":0.4,\"tilt_mm\":0.1},\"baseline\":{\"scan_id\":"
    "\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"E4\",\"created\":\"2026-12-07T03:23:40Z\","
    "\"axial_displacement_mm\":0.0,\"uncertainty_mm\":0.3,\"baseline\":{\"scan_id\":\"B1\"}}",
    "{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"scan_id\":\"E5\",\"created\":\"2026-12-07T03:"
    "23:49Z\",\"reason\":\"the face's lower edge lies outside the antenna travel in this scan, so the "
    "edges cannot be compared with the baseline's and the axial shift reads +3.8 mm only as a guess "
    "ENDWORD\"}",
};

static int colour_in(const struct png_read *png, int x0, int x1, int y0, int y1, struct uwb_rgb colour)
{
    int n = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            if (x >= 0 && y >= 0 && x < png->w && y < png->h)
                n += is(pixel(png, x, y), colour);
    return n;
}

static void test_trend_png_reads_without_the_manual(void)
{
    struct uwb_trend t;
    TEST_ASSERT_EQUAL_INT(0, uwb_trend_from_lines((char *const *)engineer_lines, 5, &t));
    struct uwb_thresholds th = {.watch_m = 2e-3, .alarm_m = 5e-3};
    scratch_scratch_dir(dir, sizeof dir, "trend");
    char path[600], err[512];
    snprintf(path, sizeof path, "%s/trend.png", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_trend_png(path, &t, &th, NULL, err, sizeof err), err);
    struct png_read png = read_png(path);
    struct uwb_trend_layout l;
    uwb_render_trend_layout(&t, &th, NULL, &l);
    const struct uwb_plot *p = &l.plot;
    const struct uwb_rgb ink = {25, 25, 25}, muted = {90, 90, 90};
    const struct uwb_rgb series_grey = {150, 150, 150};

    /* The Description counts what there was: no inconclusive verdict
     * but E2, and E3 as the radial alarm it was. */
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(png.description, "5 verdicts: 2 with a figure, 2 inconclusive, 0 error"), png.description);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(png.description, "1 with the axial figure withheld"),
                                 png.description);

    /* E3's mark in the strip is not the "?" of an inconclusive verdict. */
    int c3 = uwb_trend_col(&l, t.entries[2].t), mx, my;
    int s = 2;
    const unsigned char *strip = png.px + (size_t)l.strip_y * (size_t)png.w * 3;
    TEST_ASSERT_EQUAL_INT(
        0, png_text_find(strip, png.w, l.strip_h, "?", s, uwb_status_colour(UWB_STATUS_ALARM), &mx, &my));
    TEST_ASSERT_EQUAL_INT(2, png_text_find(strip, png.w, l.strip_h, "?", s,
                                           uwb_status_colour(UWB_STATUS_INCONCLUSIVE), &mx, &my));
    TEST_ASSERT_EQUAL_INT(
        1, png_text_find(strip, png.w, l.strip_h, "R", s, uwb_status_colour(UWB_STATUS_ALARM), &mx, &my));
    TEST_ASSERT_INT_WITHIN(8, c3, mx + 5);

    /* The marks are explained on the image: each letter in its words. */
    const char *legend[] = {"inconclusive", "error", "became the baseline", "edges only",
                            "axial figure withheld"};
    for (size_t i = 0; i < sizeof legend / sizeof legend[0]; i++)
        TEST_ASSERT_TRUE_MESSAGE(
            png_text_find(png.px, png.w, l.caption_h, legend[i], s, ink, NULL, NULL) == 1, legend[i]);

    /* The latest line is not cut: the reason's last word is on the page. */
    TEST_ASSERT_TRUE_MESSAGE(png_text_present(png.px, png.w, png.h, "ENDWORD"), "the reason's last word");

    /* "no figure" stands clear: nothing but its own ink and the strip
     * within 3 px of it (the y-axis title ran into it). */
    int nx, ny;
    TEST_ASSERT_EQUAL_INT(1, png_text_find(png.px, png.w, png.h, "no figure", 1, muted, &nx, &ny));
    const struct uwb_rgb strip_fill = {242, 242, 242}, white = {255, 255, 255};
    int foreign = 0, nw = uwb_text_width("no figure", 1);
    for (int y = ny - 3; y < ny + UWB_FONT_CAP_HEIGHT + 3; y++)
        for (int x = nx - 3; x < nx + nw + 3; x++) {
            struct uwb_rgb c = pixel(&png, x, y);
            foreign += !is(c, muted) && !is(c, strip_fill) && !is(c, white);
        }
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, foreign, "pixels of something else touch \"no figure\"");

    /* The grey line does not join +12 mm (E1) to 0 (E4) across the two
     * verdicts without an axial figure between them. */
    int c1 = uwb_trend_col(&l, t.entries[0].t), c4 = uwb_trend_col(&l, t.entries[3].t);
    int mid = (c1 + c4) / 2;
    TEST_ASSERT_EQUAL_INT(0, colour_in(&png, mid - 2, mid + 2, p->y, p->y + p->h - 1, series_grey));

    /* The y tick labels stand apart, half a label's height at the least
     * between two (in the shorter plot 13 labels stood 3 px apart). */
    int runs = 0, gap = -1, closest = 1000;
    for (int y = p->y - 8; y < p->y + p->h + 8; y++) {
        if (colour_in(&png, p->x - 30, p->x - 9, y, y, ink) > 0) {
            if (gap > 0) {
                runs++;
                closest = gap < closest ? gap : closest;
            }
            gap = 0;
        } else if (gap >= 0) {
            gap++;
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(runs >= 2, "y tick labels drawn");
    TEST_ASSERT_TRUE_MESSAGE(closest >= UWB_FONT_CAP_HEIGHT * s / 2, "y tick labels crowd one another");

    /* Every time tick is whole: none runs off the page ("03:23:3"). */
    int right_labels = colour_in(&png, png.w - 3, png.w - 1, p->y + p->h + 6, p->y + p->h + 30, ink);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, right_labels, "a tick label reaches the page's right edge");
    free(png.px);
    uwb_trend_free(&t);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_verdicts_become_figures_only_where_the_verdict_made_one);
    RUN_TEST(test_baseline_changes_are_marked);
    RUN_TEST(test_rate_counts_figures_since_the_last_baseline_change);
    RUN_TEST(test_one_figure_has_no_rate);
    RUN_TEST(test_trend_command_parses_its_count);
    RUN_TEST(test_trend_reply_reads_as_a_table);
    RUN_TEST(test_trend_png_shows_bars_thresholds_and_no_figure_marks);
    RUN_TEST(test_trend_png_of_an_empty_log_still_draws);
    RUN_TEST(test_trend_png_failure_names_the_file_and_leaves_no_temporary);
    RUN_TEST(test_two_figures_a_minute_apart_give_no_rate);
    RUN_TEST(test_nine_figures_in_four_minutes_give_no_rate);
    RUN_TEST(test_rate_needs_both_the_figures_and_the_span);
    RUN_TEST(test_rate_over_a_week_is_given_with_its_sigma);
    RUN_TEST(test_a_short_trend_is_drawn_at_its_own_scale);
    RUN_TEST(test_radial_change_is_a_second_series);
    RUN_TEST(test_trend_png_reads_without_the_manual);
    RUN_TEST(test_rate_does_not_depend_on_how_many_rows_are_asked_for);
    RUN_TEST(test_trend_text_keeps_the_whole_reason_and_can_be_ascii);
    RUN_TEST(test_a_trend_entry_is_the_records_summary_and_reads_back);
    return UNITY_END();
}
