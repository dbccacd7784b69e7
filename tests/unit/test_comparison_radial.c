/* Issue 30 item 5: the comparison PNG shows the face's radial change. On
 * the full-wave tank with disks 2-4 bulged 4 mm against the intact tank,
 * the radial panel shades the rows where the verdict found the change past
 * the watch limit (253..320 mm) and no others, and the PNG's text chunks
 * carry the figure; on the pure-shift pair nothing is shaded. */
#include "unity.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fixture_support.h"
#include "output/render_internal.h"
#include "scene_support.h"
#include "uwb/evaluate.h"
#include "uwb/radial.h"
#include "uwbsim/simulate.h"

#define TANK_BASE "tests/fixtures/fdtd2d-tank-d+00.0.uwbscan"
#define PNG_PATH "/tmp/test_comparison_radial.png"

void setUp(void)
{
}
void tearDown(void)
{
    unlink(PNG_PATH);
}

struct rendered {
    struct uwb_verdict v;
    struct uwb_plot panel;
    int w, h;
    unsigned char *px;
    char description[4096], radial[512];
};

static void read_texts(struct rendered *out)
{
    FILE *fp = fopen(PNG_PATH, "rb");
    TEST_ASSERT_NOT_NULL(fp);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    TEST_ASSERT_EQUAL_INT(0, setjmp(png_jmpbuf(png)));
    png_init_io(png, fp);
    png_read_info(png, info);
    png_textp texts;
    int n = 0;
    png_get_text(png, info, &texts, &n);
    for (int i = 0; i < n; i++) {
        if (!strcmp(texts[i].key, "Description"))
            snprintf(out->description, sizeof out->description, "%s", texts[i].text);
        if (!strcmp(texts[i].key, "Radial"))
            snprintf(out->radial, sizeof out->radial, "%s", texts[i].text);
    }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
}

static void render(const char *current, struct rendered *out)
{
    memset(out, 0, sizeof *out);
    struct uwb_scan cur, base;
    fixture_load_scan(current, &cur);
    fixture_load_scan(TANK_BASE, &base);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    char err[256];
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &out->v, &ca, &ba, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(PNG_PATH, &ca, &ba, &out->v, err, sizeof err),
                                  err);
    uwb_render_comparison_radial_layout(&ca, &ba, &out->v, NULL, &out->panel);
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    TEST_ASSERT_TRUE(png_image_begin_read_from_file(&image, PNG_PATH));
    image.format = PNG_FORMAT_RGB;
    out->w = (int)image.width;
    out->h = (int)image.height;
    out->px = malloc(PNG_IMAGE_SIZE(image));
    TEST_ASSERT_NOT_NULL(out->px);
    TEST_ASSERT_TRUE(png_image_finish_read(&image, NULL, out->px, 0, NULL));
    read_texts(out);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
}

/* Pixels of the shade colour in one row of the panel. */
static int shaded_in_row(const struct rendered *r, int row, struct uwb_rgb shade)
{
    int n = 0;
    for (int x = r->panel.x; x < r->panel.x + r->panel.w; x++) {
        const unsigned char *q = r->px + ((size_t)row * (size_t)r->w + (size_t)x) * 3;
        n += q[0] == shade.r && q[1] == shade.g && q[2] == shade.b;
    }
    return n;
}

/* A row's height, from the documented mapping (top row = y_max). */
static double y_of_row(const struct uwb_plot *p, int row)
{
    return p->y_max - (double)(row - p->y) / (p->h - 1) * (p->y_max - p->y_min);
}

static void test_a_bulge_is_shaded_over_its_span_and_labelled(void)
{
    struct rendered r;
    render("tests/fixtures/fdtd2d-tank-radial-r2-4+4-d+00.0.uwbscan", &r);
    const struct uwb_radial_verdict *rv = &r.v.radial;
    TEST_ASSERT_TRUE(rv->measured && rv->has_span);
    TEST_ASSERT_TRUE(r.panel.w > 40 && r.panel.h > 100);
    /* The panel lies beside the others, not over them. */
    TEST_ASSERT_TRUE(r.panel.x + r.panel.w < r.w);
    struct uwb_rgb shade = uwb_radial_shade_colour(rv->status);
    double row_mm = (r.panel.y_max - r.panel.y_min) / (r.panel.h - 1) * 1e3;
    int rows_shaded = 0;
    double lo = INFINITY, hi = -INFINITY;
    for (int row = r.panel.y; row < r.panel.y + r.panel.h; row++) {
        /* A shaded row: most of it in the shade (the curves cross it). */
        if (shaded_in_row(&r, row, shade) < r.panel.w / 2)
            continue;
        double y = y_of_row(&r.panel, row) * 1e3;
        rows_shaded++;
        lo = fmin(lo, y);
        hi = fmax(hi, y);
    }
    printf("shaded %d rows, %.1f..%.1f mm (verdict %.1f..%.1f mm, %.2f mm a row)\n", rows_shaded, lo, hi,
           rv->from_m * 1e3, rv->to_m * 1e3, row_mm);
    TEST_ASSERT_TRUE_MESSAGE(rows_shaded > 0, "no rows shaded");
    TEST_ASSERT_DOUBLE_WITHIN(1.5 * row_mm, rv->from_m * 1e3, lo);
    TEST_ASSERT_DOUBLE_WITHIN(1.5 * row_mm, rv->to_m * 1e3, hi);
    /* Every row in between (none outside, by lo and hi above). */
    TEST_ASSERT_TRUE(rows_shaded >= (int)floor((hi - lo) / row_mm));
    char label[160];
    snprintf(label, sizeof label, "radial %+.1f \u00b1 %.1f mm at %.0f mm (bulge toward the antenna)",
             rv->max_change_m * 1e3, rv->uncertainty_m * 1e3, rv->at_m * 1e3);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.radial, label), r.radial);
    *strstr(label, " (bulge") = '\0';
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.description, label), r.description);
    free(r.px);
}

/* The axial figure the verdict withholds on a deformed face is not in the
 * picture either: no displacement in the caption, the reason instead. */
static void test_a_withheld_axial_figure_is_not_drawn(void)
{
    struct rendered r;
    render("tests/fixtures/fdtd2d-tank-radial-r2-4+4-d+00.0.uwbscan", &r);
    TEST_ASSERT_TRUE(r.v.axial_withheld);
    TEST_ASSERT_NULL_MESSAGE(strstr(r.description, "displacement +"), r.description);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.description, "axial figure withheld"), r.description);
    free(r.px);
}

static void test_a_pure_shift_shades_nothing(void)
{
    struct rendered r;
    render("tests/fixtures/fdtd2d-tank-d+04.0.uwbscan", &r);
    TEST_ASSERT_TRUE(r.v.radial.measured);
    TEST_ASSERT_FALSE(r.v.radial.has_span);
    for (enum uwb_status s = UWB_STATUS_WATCH; s <= UWB_STATUS_ALARM; s++) {
        struct uwb_rgb shade = uwb_radial_shade_colour(s);
        for (int row = r.panel.y; row < r.panel.y + r.panel.h; row++)
            TEST_ASSERT_TRUE(shaded_in_row(&r, row, shade) < r.panel.w / 2);
    }
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.radial, "radial "), r.radial);
    TEST_ASSERT_NULL_MESSAGE(strstr(r.radial, "not measured"), r.radial);
    free(r.px);
}

/* Withheld: the label says so and why. */
static void test_a_withheld_radial_figure_says_why(void)
{
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    v.has_baseline = 1;
    v.radial.status = UWB_STATUS_INCONCLUSIVE;
    snprintf(v.radial.withheld, sizeof v.radial.withheld, "too few rows of the face are bright enough");
    char text[256];
    uwb_describe_radial(&v, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("radial: not measured (too few rows of the face are bright enough)", text);
    v.radial.measured = 1;
    v.radial.status = UWB_STATUS_WATCH;
    v.radial.max_change_m = -0.0031;
    v.radial.uncertainty_m = 0.0004;
    v.radial.at_m = 0.267;
    v.radial.withheld[0] = '\0';
    uwb_describe_radial(&v, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("radial -3.1 \u00b1 0.4 mm at 267 mm (dent, away from the antenna)", text);
}

/* 8 kB of profile: static rather than on the stack. */
static struct uwb_radial profile;

/* A curve's x at y, linear between its points (ascending y); NAN outside. */
static double curve_at(const double *ys, const double *xs, int n, double y)
{
    for (int i = 0; i + 1 < n; i++)
        if (ys[i] <= y && y <= ys[i + 1]) {
            double t = ys[i + 1] > ys[i] ? (y - ys[i]) / (ys[i + 1] - ys[i]) : 0.0;
            return (1.0 - t) * xs[i] + t * xs[i + 1];
        }
    return NAN;
}

/* The panel draws the verdict's own change: at every readable row of the
 * face, what stands off between the two curves is the change the verdict
 * read there (Delta r less the line through the unchanged rows, level and
 * tilt), within a pixel of the panel; at the verdict's at_mm too. */
static void check_panel_draws_the_verdicts_change(const struct uwb_scan *cur, const struct uwb_scan *base,
                                                  const char *what)
{
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    struct uwb_verdict v;
    char err[256];
    struct uwb_baseline_record rec = {.scan = base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(cur, &rec, &opt, &v, &ca, &ba, err, sizeof err), err);
    TEST_ASSERT_TRUE_MESSAGE(v.radial.measured, v.radial.withheld);
    struct uwb_plot panel;
    uwb_render_comparison_radial_layout(&ca, &ba, &v, NULL, &panel);
    double pixel_m = (panel.x_max - panel.x_min) / (panel.w - 1);
    TEST_ASSERT_EQUAL_INT(0, uwb_radial_measure(&ca, &ba, v.radial.shift_m,
                                                opt.compare.radial_thresholds.watch_m, 0.0, &profile));
    TEST_ASSERT_TRUE_MESSAGE(profile.figures.measured, profile.figures.withheld);
    struct uwb_radial_curves k;
    TEST_ASSERT_EQUAL_INT(0, uwb_radial_curves_read(&ca, &ba, &v, &k));
    double worst = 0.0, worst_y = NAN, at_drawn = NAN, at_change = NAN;
    int rows = 0;
    for (int i = 0; i < profile.n; i++) {
        if (profile.change_m[i] == 0.0)
            continue; /* not readable in both scans: the verdict read nothing there */
        double y = profile.y0_m + i * profile.dy_m + v.radial.shift_m;
        double drawn = curve_at(k.yc, k.xc, k.n_cur, y) - curve_at(k.yb, k.xb, k.n_base, y);
        if (!isfinite(drawn))
            continue;
        rows++;
        double off = fabs(drawn - profile.change_m[i]);
        if (off >= worst) {
            worst = off;
            worst_y = y;
        }
        if (fabs(y - v.radial.at_m) < 0.5 * profile.dy_m) {
            at_drawn = drawn;
            at_change = profile.change_m[i];
        }
    }
    uwb_radial_curves_free(&k);
    char msg[320];
    snprintf(msg, sizeof msg,
             "%s: radial %+.2f mm at %.1f mm (there %+.2f mm, drawn %+.2f mm), tilt %+.2f mm; over %d rows "
             "the drawn change is off the verdict's by up to %.2f mm (at %.1f mm), a pixel %.3f mm",
             what, v.radial.max_change_m * 1e3, v.radial.at_m * 1e3, at_change * 1e3, at_drawn * 1e3,
             v.radial.tilt_m * 1e3, rows, worst * 1e3, worst_y * 1e3, pixel_m * 1e3);
    printf("%s\n", msg);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    TEST_ASSERT_TRUE_MESSAGE(rows > 20, msg);
    TEST_ASSERT_TRUE_MESSAGE(isfinite(at_drawn), msg);
    TEST_ASSERT_TRUE_MESSAGE(worst <= pixel_m, msg);
}

static void check_fixture_panel(const char *current)
{
    struct uwb_scan cur, base;
    fixture_load_scan(current, &cur);
    fixture_load_scan(TANK_BASE, &base);
    check_panel_draws_the_verdicts_change(&cur, &base, current);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
}

/* The top three disks bulged 8 mm: the median of the whole face's change
 * is not the verdict's line through the rows that did not change. */
static void test_a_top_bulge_is_drawn_as_the_verdict_reads_it(void)
{
    check_fixture_panel("tests/fixtures/fdtd2d-tank-radial-r5-7+8-d+00.0.uwbscan");
}

static void test_a_bulge_with_a_rise_is_drawn_as_the_verdict_reads_it(void)
{
    check_fixture_panel("tests/fixtures/fdtd2d-tank-radial-r4-5+6-d+10.0.uwbscan");
}

/* The shared tank's winding in the simulator (tools/accuracy/radial-limits.sh:
 * its scene with a direct coupling, for the time zero), intact as the
 * baseline, against the same with one parameter changed. */
static void check_simulated_panel(const char *key, const char *value, const char *what)
{
    struct uwb_scan base, cur;
    scene_tank_winding_pair(key, value, &base, &cur);
    check_panel_draws_the_verdicts_change(&cur, &base, what);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
}

/* The panel's line on what was taken out: the lean read, or with a change
 * at the face's end (its line level, no lean read) the tilt withheld, never
 * "tilt +0.0". */
static void check_level_text(const char *key, const char *value, const char *want)
{
    char err[512], level[128];
    struct uwb_scan base, cur;
    scene_tank_winding_pair(key, value, &base, &cur);
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    struct uwb_verdict v;
    struct uwb_baseline_record rec = {.scan = &base};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, sizeof err), err);
    uwb_radial_level_text(&v, level, sizeof level);
    printf("%s %s: %s\n", key, value, level);
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(level, want), level);
}

static void test_the_panel_gives_a_lean_and_withholds_one_not_read(void)
{
    check_level_text("face_tilt_m", "0.006", ", tilt +6.8 \u00b1 0.6 mm, taken out");
    check_level_text("radial_m", "1:0.004", "taken out; tilt withheld");
}

/* The face's top 6 mm nearer than its bottom and no disk bulged: the
 * verdict reads the lean as the tilt, no change; the panel must not draw
 * it as one either. */
static void test_a_tilted_face_draws_no_lean(void)
{
    check_simulated_panel("face_tilt_m", "0.006", "tank winding, face tilted 6 mm");
}

/* Disks 2-6 of 7 bulged 4 mm: the whole face's median lies in the bulge. */
static void test_a_bulge_over_most_of_the_face_is_drawn_as_the_verdict_reads_it(void)
{
    check_simulated_panel("radial_m", "2-6:0.004", "tank winding, disks 2-6 bulged 4 mm");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_bulge_is_shaded_over_its_span_and_labelled);
    RUN_TEST(test_a_withheld_axial_figure_is_not_drawn);
    RUN_TEST(test_a_pure_shift_shades_nothing);
    RUN_TEST(test_a_withheld_radial_figure_says_why);
    RUN_TEST(test_a_top_bulge_is_drawn_as_the_verdict_reads_it);
    RUN_TEST(test_a_bulge_with_a_rise_is_drawn_as_the_verdict_reads_it);
    RUN_TEST(test_a_tilted_face_draws_no_lean);
    RUN_TEST(test_the_panel_gives_a_lean_and_withholds_one_not_read);
    RUN_TEST(test_a_bulge_over_most_of_the_face_is_drawn_as_the_verdict_reads_it);
    return UNITY_END();
}
