/* The PNGs an engineer reads: render synthetic images, read the files back
 * with libpng and check what a person relies on — where the edge lines sit,
 * how they differ, the colour bar, the axis labels, the caption. */
#include "unity.h"
#include "output/render_internal.h"
#include "fixture_support.h"
#include "png_text_support.h"
#include "uwb/evaluate.h"
#include "uwb/version.h"

#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[256];

/* ---------- fixtures ---------- */

/* A face at range FACE_Z between FACE_LO and FACE_HI, flat-topped at 1.0
 * over a -40 dB background. The face sits low in the image on purpose: an
 * image drawn upside down puts it high and fails the tests. */
#define FACE_Z 0.45
#define FACE_LO 0.10
#define FACE_HI 0.25
#define BACKGROUND 0.01

static struct uwb_image make_image(double lo, double hi)
{
    struct uwb_image img = {0};
    img.ny = 301;
    img.nz = 161;
    img.y0_m = 0.0;
    img.dy_m = 0.002; /* 0 .. 600 mm */
    img.z0_m = 0.35;
    img.dz_m = 0.0025; /* 350 .. 750 mm */
    img.pix = calloc((size_t)img.ny * (size_t)img.nz, sizeof *img.pix);
    TEST_ASSERT_NOT_NULL(img.pix);
    for (int iy = 0; iy < img.ny; iy++)
        for (int iz = 0; iz < img.nz; iz++) {
            double y = img.y0_m + iy * img.dy_m, z = img.z0_m + iz * img.dz_m;
            int on_face = y >= lo - 1e-9 && y <= hi + 1e-9 && fabs(z - FACE_Z) <= 0.010 + 1e-9;
            img.pix[iy * img.nz + iz] = on_face ? 1.0f : (float)BACKGROUND;
        }
    return img;
}

/* An analysis as the comparison receives it: the display image with its
 * face at image_lo..image_hi, and the face profile the edges were read
 * from, bright (1.0, else BACKGROUND) over profile_lo..profile_hi on a
 * 1 mm grid. In a real analysis the two agree; tests may part them. */
static struct uwb_analysis make_analysis(double image_lo, double image_hi, double profile_lo,
                                         double profile_hi)
{
    struct uwb_analysis a;
    memset(&a, 0, sizeof a);
    a.intensity = make_image(image_lo, image_hi);
    a.profile.n = 601;
    a.profile.y0_m = 0.0;
    a.profile.dy_m = 0.001;
    a.profile.value = malloc((size_t)a.profile.n * sizeof *a.profile.value);
    TEST_ASSERT_NOT_NULL(a.profile.value);
    for (int i = 0; i < a.profile.n; i++) {
        double y = a.profile.y0_m + i * a.profile.dy_m;
        a.profile.value[i] = y >= profile_lo - 1e-9 && y <= profile_hi + 1e-9 ? 1.0f : (float)BACKGROUND;
    }
    return a;
}

static void set_edges(struct uwb_edges *e, double lo, double hi)
{
    memset(e, 0, sizeof *e);
    e->found = 1;
    e->lower_m = lo;
    e->upper_m = hi;
    e->center_m = 0.5 * (lo + hi);
    e->height_m = hi - lo;
    e->face_z_m = FACE_Z;
    e->sigma_center_m = 0.0003;
}

#define BASE_LO 0.08
#define BASE_HI 0.23

static struct uwb_verdict make_verdict(void)
{
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    v.status = UWB_STATUS_WATCH;
    snprintf(v.scan_id, sizeof v.scan_id, "T1-20240611-0042");
    snprintf(v.created, sizeof v.created, "2024-06-11T10:15:00Z");
    set_edges(&v.current, FACE_LO, FACE_HI);
    v.has_baseline = 1;
    set_edges(&v.baseline, BASE_LO, BASE_HI);
    snprintf(v.baseline_scan_id, sizeof v.baseline_scan_id, "T1-20230302-0001");
    v.axial_displacement_m = v.current.center_m - v.baseline.center_m;
    v.uncertainty_m = 0.0004;
    return v;
}

struct png_rgb {
    int w, h;
    unsigned char *px;
};

static struct png_rgb read_png(const char *path)
{
    struct png_rgb out = {0, 0, NULL};
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    TEST_ASSERT_TRUE_MESSAGE(png_image_begin_read_from_file(&image, path), path);
    image.format = PNG_FORMAT_RGB;
    out.w = (int)image.width;
    out.h = (int)image.height;
    out.px = malloc(PNG_IMAGE_SIZE(image));
    TEST_ASSERT_NOT_NULL(out.px);
    TEST_ASSERT_TRUE(png_image_finish_read(&image, NULL, out.px, 0, NULL));
    return out;
}

static struct uwb_rgb at(const struct png_rgb *p, int x, int y)
{
    TEST_ASSERT_TRUE(x >= 0 && y >= 0 && x < p->w && y < p->h);
    const unsigned char *q = p->px + ((size_t)y * (size_t)p->w + (size_t)x) * 3;
    struct uwb_rgb c = {q[0], q[1], q[2]};
    return c;
}

static int same(struct uwb_rgb a, struct uwb_rgb b)
{
    return a.r == b.r && a.g == b.g && a.b == b.b;
}

/* The row/column of a data value, computed here from the documented
 * mapping (top row = y_max, left column = x_min), not by the code under
 * test. */
static int row_of(const struct uwb_plot *p, double y)
{
    return p->y + (int)lround((p->y_max - y) / (p->y_max - p->y_min) * (p->h - 1));
}

static int col_of(const struct uwb_plot *p, double x)
{
    return p->x + (int)lround((x - p->x_min) / (p->x_max - p->x_min) * (p->w - 1));
}

static double y_of_row(const struct uwb_plot *p, int row)
{
    return p->y_max - (double)(row - p->y) / (p->h - 1) * (p->y_max - p->y_min);
}

static void path_in_dir(char *buf, size_t len, const char *name)
{
    snprintf(buf, len, "%s/%s", dir, name);
}

static int count_dir_entries(const char *d)
{
    DIR *dp = opendir(d);
    TEST_ASSERT_NOT_NULL(dp);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(dp)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            n++;
    closedir(dp);
    return n;
}

static struct png_rgb render_migrated(const char *name, const struct uwb_image *img,
                                      const struct uwb_verdict *v, const struct uwb_render_options *opt)
{
    char path[512], err[512] = "";
    path_in_dir(path, sizeof path, name);
    int rc = uwb_render_migrated_png_opt(path, img, v, opt, err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, err);
    return read_png(path);
}

void setUp(void)
{
    snprintf(dir, sizeof dir, "/tmp/test_render.XXXXXX");
    TEST_ASSERT_NOT_NULL(mkdtemp(dir));
}

void tearDown(void)
{
    DIR *dp = opendir(dir);
    if (dp) {
        struct dirent *e;
        char p[600];
        while ((e = readdir(dp)))
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
                snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
                unlink(p);
            }
        closedir(dp);
    }
    rmdir(dir);
}

/* ---------- building blocks ---------- */

static void test_font_table_is_complete_and_glyphs_are_distinct(void)
{
    TEST_ASSERT_TRUE(uwb_font_table_consistent());
    for (unsigned cp = 32; cp <= 126; cp++)
        TEST_ASSERT_TRUE(uwb_font_has_glyph(cp));
    TEST_ASSERT_TRUE(uwb_font_has_glyph(0x00B1)); /* ± in captions */
    TEST_ASSERT_FALSE(uwb_font_has_glyph(0x4E00));

    /* Every printable glyph leaves ink and no two look the same (a
     * duplicated row set would make "8" and "B" indistinguishable). */
    enum { W = 8, H = 12 };
    static unsigned char seen[95][W * H];
    char err[128];
    for (int i = 0; i < 95; i++) {
        struct uwb_canvas c;
        struct uwb_rgb white = {255, 255, 255}, black = {0, 0, 0};
        TEST_ASSERT_EQUAL_INT(0, uwb_canvas_init(&c, W, H, white, err, sizeof err));
        char s[2] = {(char)(32 + i), 0};
        uwb_draw_text(&c, 0, 0, s, 1, black);
        int ink = 0;
        for (int p = 0; p < W * H; p++) {
            seen[i][p] = c.rgb[p * 3] == 0;
            ink += seen[i][p];
        }
        uwb_canvas_free(&c);
        if (i == 0)
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, ink, "space draws nothing");
        else
            TEST_ASSERT_TRUE_MESSAGE(ink > 0, s);
        for (int j = 1; j < i; j++)
            TEST_ASSERT_FALSE_MESSAGE(memcmp(seen[i], seen[j], sizeof seen[i]) == 0, s);
    }
}

static void test_text_width_matches_drawn_extent_and_scales(void)
{
    char err[128];
    struct uwb_canvas c;
    struct uwb_rgb white = {255, 255, 255}, black = {0, 0, 0};
    TEST_ASSERT_EQUAL_INT(0, uwb_canvas_init(&c, 200, 40, white, err, sizeof err));
    const char *text = "H\xc2\xb1M"; /* UTF-8 ± counts as one glyph */
    int advance = uwb_draw_text(&c, 10, 5, text, 2, black);
    TEST_ASSERT_EQUAL_INT(uwb_text_width(text, 2), advance);
    TEST_ASSERT_EQUAL_INT(2 * uwb_text_width(text, 1), uwb_text_width(text, 2));
    TEST_ASSERT_EQUAL_INT((3 * UWB_FONT_ADVANCE - 1) * 2, advance);
    int min_x = 1000, max_x = -1, min_y = 1000, max_y = -1;
    for (int y = 0; y < c.height; y++)
        for (int x = 0; x < c.width; x++)
            if (uwb_canvas_get(&c, x, y).r == 0) {
                min_x = x < min_x ? x : min_x;
                max_x = x > max_x ? x : max_x;
                min_y = y < min_y ? y : min_y;
                max_y = y > max_y ? y : max_y;
            }
    uwb_canvas_free(&c);
    /* 'H' and 'M' touch the first and last columns and the full cap height. */
    TEST_ASSERT_EQUAL_INT(10, min_x);
    TEST_ASSERT_EQUAL_INT(10 + advance - 1, max_x);
    TEST_ASSERT_EQUAL_INT(5, min_y);
    TEST_ASSERT_EQUAL_INT(5 + UWB_FONT_CAP_HEIGHT * 2 - 1, max_y);
}

static void test_perceptual_map_lightness_rises_monotonically(void)
{
    double prev = uwb_rgb_lightness(uwb_colormap_perceptual(0.0));
    TEST_ASSERT_TRUE(prev < 20.0); /* floor reads dark */
    for (int i = 1; i <= 1000; i++) {
        double l = uwb_rgb_lightness(uwb_colormap_perceptual(i / 1000.0));
        /* Rounding a falling channel to 8 bits can cost ~0.1 L* for a
         * moment; a real reversal of the map is far larger. */
        TEST_ASSERT_TRUE_MESSAGE(l >= prev - 0.25, "lightness must not fall");
        if (l > prev)
            prev = l;
    }
    TEST_ASSERT_TRUE(prev > 85.0); /* peak reads bright */
    /* Over steps of 1/50 (under 1 dB on a 30 dB scale) it strictly rises. */
    for (int i = 0; i < 50; i++)
        TEST_ASSERT_TRUE(uwb_rgb_lightness(uwb_colormap_perceptual((i + 1) / 50.0)) >
                         uwb_rgb_lightness(uwb_colormap_perceptual(i / 50.0)) + 0.5);
    /* Nearly uniform: each eighth of the map adds a similar lightness. */
    for (int i = 0; i < 8; i++) {
        double d = uwb_rgb_lightness(uwb_colormap_perceptual((i + 1) / 8.0)) -
                   uwb_rgb_lightness(uwb_colormap_perceptual(i / 8.0));
        TEST_ASSERT_TRUE(d > 6.0 && d < 13.0);
    }
    TEST_ASSERT_TRUE(same(uwb_colormap_perceptual(-1.0), uwb_colormap_perceptual(0.0)));
    TEST_ASSERT_TRUE(same(uwb_colormap_perceptual(NAN), uwb_colormap_perceptual(0.0)));
    TEST_ASSERT_TRUE(same(uwb_colormap_perceptual(7.0), uwb_colormap_perceptual(1.0)));
}

static void test_diverging_map_is_symmetric_in_lightness(void)
{
    for (int i = 0; i <= 100; i++) {
        double t = i / 200.0;
        double a = uwb_rgb_lightness(uwb_colormap_diverging(t));
        double b = uwb_rgb_lightness(uwb_colormap_diverging(1.0 - t));
        TEST_ASSERT_DOUBLE_WITHIN(3.0, a, b);
    }
    struct uwb_rgb neg = uwb_colormap_diverging(0.0), pos = uwb_colormap_diverging(1.0);
    TEST_ASSERT_TRUE(neg.b > neg.r && pos.r > pos.b);
    TEST_ASSERT_TRUE(uwb_rgb_lightness(uwb_colormap_diverging(0.5)) > 90.0);
}

static void test_nice_ticks_and_labels(void)
{
    double t[64], step;
    int n = uwb_nice_ticks(0.0, 600.0, 10, t, 64, &step);
    TEST_ASSERT_EQUAL_DOUBLE(50.0, step);
    TEST_ASSERT_EQUAL_INT(13, n);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, t[0]);
    TEST_ASSERT_EQUAL_DOUBLE(600.0, t[12]);
    n = uwb_nice_ticks(-30.0, 0.0, 6, t, 64, &step);
    TEST_ASSERT_EQUAL_DOUBLE(5.0, step);
    TEST_ASSERT_EQUAL_DOUBLE(-30.0, t[0]);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, t[n - 1]);
    n = uwb_nice_ticks(-0.71, 7.3, 8, t, 64, &step);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, step);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, t[0]);
    TEST_ASSERT_EQUAL_INT(0, uwb_nice_ticks(1.0, 1.0, 5, t, 64, &step));
    TEST_ASSERT_EQUAL_INT(0, uwb_nice_ticks(0.0, INFINITY, 5, t, 64, &step));

    char b[32];
    uwb_format_tick(b, sizeof b, -1e-13, 0.5);
    TEST_ASSERT_EQUAL_STRING("0", b);
    uwb_format_tick(b, sizeof b, 0.5, 0.5);
    TEST_ASSERT_EQUAL_STRING("0.5", b);
    uwb_format_tick(b, sizeof b, 250.0, 50.0);
    TEST_ASSERT_EQUAL_STRING("250", b);
    uwb_format_tick(b, sizeof b, -2.5, 2.5);
    TEST_ASSERT_EQUAL_STRING("-2.5", b);
}

static void test_dashed_line_has_gaps_and_solid_line_has_none(void)
{
    char err[128];
    struct uwb_canvas c;
    struct uwb_rgb white = {255, 255, 255}, red = {255, 0, 0};
    TEST_ASSERT_EQUAL_INT(0, uwb_canvas_init(&c, 100, 10, white, err, sizeof err));
    uwb_canvas_line(&c, 0, 2, 99, 2, red, 1, 0, 0);
    uwb_canvas_line(&c, 0, 6, 99, 6, red, 1, 8, 5);
    /* off the canvas: clipped, not a crash */
    uwb_canvas_line(&c, -100000, 8, 100000, 8, red, 3, 0, 0);
    int solid = 0, dashed = 0;
    for (int x = 0; x < 100; x++) {
        solid += same(uwb_canvas_get(&c, x, 2), red);
        dashed += same(uwb_canvas_get(&c, x, 6), red);
    }
    TEST_ASSERT_EQUAL_INT(100, solid);
    /* 8 on, 5 off over 100 px: seven full periods and one more dash */
    TEST_ASSERT_EQUAL_INT(7 * 8 + 8, dashed);
    TEST_ASSERT_TRUE(same(uwb_canvas_get(&c, 7, 6), red));
    TEST_ASSERT_FALSE(same(uwb_canvas_get(&c, 8, 6), red));
    TEST_ASSERT_FALSE(same(uwb_canvas_get(&c, 12, 6), red));
    TEST_ASSERT_TRUE(same(uwb_canvas_get(&c, 13, 6), red));
    TEST_ASSERT_TRUE(same(uwb_canvas_get(&c, 50, 8), red));
    uwb_canvas_free(&c);
}

/* A rectangle fills exactly its pixels, clipped to the canvas, whatever
 * part of it lies outside; an empty one draws nothing. */
static void test_filled_rectangle_covers_exactly_its_clipped_pixels(void)
{
    char err[128];
    struct uwb_canvas c;
    struct uwb_rgb white = {255, 255, 255}, blue = {0, 0, 255};
    const struct {
        int x, y, w, h;
    } rects[] = {{3, 2, 5, 4},     {-4, -3, 6, 5}, {17, 9, 10, 10},
                 {-50, 4, 200, 1}, {5, 5, 0, 3},   {5, 5, 3, -2}};
    for (size_t r = 0; r < sizeof rects / sizeof rects[0]; r++) {
        TEST_ASSERT_EQUAL_INT(0, uwb_canvas_init(&c, 20, 12, white, err, sizeof err));
        uwb_canvas_fill_rect(&c, rects[r].x, rects[r].y, rects[r].w, rects[r].h, blue);
        for (int y = 0; y < 12; y++)
            for (int x = 0; x < 20; x++) {
                int inside = x >= rects[r].x && x < rects[r].x + rects[r].w && y >= rects[r].y &&
                             y < rects[r].y + rects[r].h;
                TEST_ASSERT_EQUAL_INT_MESSAGE(inside, same(uwb_canvas_get(&c, x, y), blue), "pixel");
            }
        uwb_canvas_free(&c);
    }
}

/* ---------- migrated image ---------- */

static void test_migrated_png_edges_sit_on_their_heights(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    struct png_rgb png = render_migrated("m.png", &img, &v, NULL);
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    TEST_ASSERT_EQUAL_INT(o.width, png.w);
    TEST_ASSERT_EQUAL_INT(o.height, png.h);

    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_migrated_layout(&img, &v, &o, &p, &bar_x, &bar_w);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0, p.y_min);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.6, p.y_max);

    /* Solid white core exactly on the row of each current edge, black halo
     * right above and below, across the face. */
    int face_col = col_of(&p, FACE_Z);
    double heights[2] = {FACE_LO, FACE_HI};
    for (int i = 0; i < 2; i++) {
        int row = row_of(&p, heights[i]);
        for (int dx = -30; dx <= 30; dx++)
            TEST_ASSERT_TRUE_MESSAGE(same(at(&png, face_col + dx, row), UWB_RGB_CURRENT_EDGE),
                                     "current edge core");
        TEST_ASSERT_TRUE(same(at(&png, face_col + 20, row - 1), UWB_RGB_HALO));
        TEST_ASSERT_TRUE(same(at(&png, face_col + 20, row + 1), UWB_RGB_HALO));
    }
    /* Baseline edges: on their rows, in their own colour, dashed. */
    double base_heights[2] = {BASE_LO, BASE_HI};
    for (int i = 0; i < 2; i++) {
        int row = row_of(&p, base_heights[i]);
        int pink = 0, other = 0;
        for (int dx = -30; dx <= 30; dx++) {
            if (same(at(&png, face_col + dx, row), UWB_RGB_BASELINE_EDGE))
                pink++;
            else
                other++;
        }
        TEST_ASSERT_TRUE_MESSAGE(pink >= 25, "baseline edge drawn on its row");
        TEST_ASSERT_TRUE_MESSAGE(other >= 10, "baseline edge has gaps (dashed)");
        TEST_ASSERT_FALSE(same(UWB_RGB_BASELINE_EDGE, UWB_RGB_CURRENT_EDGE));
        /* and the current edges are not on those rows */
        TEST_ASSERT_FALSE(same(at(&png, face_col, row), UWB_RGB_CURRENT_EDGE));
    }
    /* Centre marker (filled white diamond) at the centre height. */
    TEST_ASSERT_TRUE(same(at(&png, face_col, row_of(&p, v.current.center_m)), UWB_RGB_CURRENT_EDGE));
    free(png.px);
    uwb_image_free(&img);
}

static void test_migrated_png_puts_the_face_where_the_axis_says(void)
{
    /* No verdict: nothing drawn over the image. */
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct png_rgb png = render_migrated("face.png", &img, NULL, NULL);
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_migrated_layout(&img, NULL, NULL, &p, &bar_x, &bar_w);
    int face_col = col_of(&p, FACE_Z);
    struct uwb_rgb peak = uwb_colormap_perceptual(1.0), floor_colour = uwb_colormap_perceptual(0.0);
    int top = -1, bottom = -1;
    for (int row = p.y; row < p.y + p.h; row++)
        if (same(at(&png, face_col, row), peak)) {
            if (top < 0)
                top = row;
            bottom = row;
        }
    TEST_ASSERT_TRUE_MESSAGE(top >= 0, "face drawn at the peak colour");
    /* Up the page is larger y: the top of the bright run is the face's
     * upper end (within a grid step). */
    TEST_ASSERT_DOUBLE_WITHIN(0.004, FACE_HI, y_of_row(&p, top));
    TEST_ASSERT_DOUBLE_WITHIN(0.004, FACE_LO, y_of_row(&p, bottom));
    /* The -40 dB background is below the -30 dB floor: floor colour. */
    TEST_ASSERT_TRUE(same(at(&png, face_col, row_of(&p, 0.45)), floor_colour));
    TEST_ASSERT_TRUE(same(at(&png, col_of(&p, 0.65), row_of(&p, 0.18)), floor_colour));
    /* Without a verdict there are no edge lines. */
    TEST_ASSERT_FALSE(same(at(&png, face_col + 20, row_of(&p, FACE_LO)), UWB_RGB_CURRENT_EDGE));
    free(png.px);
    uwb_image_free(&img);
}

static void test_migrated_colorbar_runs_from_peak_colour_to_floor_colour(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    struct png_rgb png = render_migrated("bar.png", &img, &v, NULL);
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_migrated_layout(&img, &v, NULL, &p, &bar_x, &bar_w);
    TEST_ASSERT_TRUE(bar_x > p.x + p.w);
    struct uwb_rgb top = at(&png, bar_x + bar_w / 2, p.y),
                   bottom = at(&png, bar_x + bar_w / 2, p.y + p.h - 1);
    TEST_ASSERT_TRUE(same(top, uwb_colormap_perceptual(1.0)));
    TEST_ASSERT_TRUE(same(bottom, uwb_colormap_perceptual(0.0)));
    /* and lightness falls steadily down the bar */
    double prev = 200;
    for (int row = p.y; row < p.y + p.h; row += 10) {
        double l = uwb_rgb_lightness(at(&png, bar_x + bar_w / 2, row));
        TEST_ASSERT_TRUE(l <= prev + 0.05);
        prev = l;
    }
    /* dB tick labels beside the bar: ink right of it at the 0 dB row */
    int ink = 0;
    for (int x = bar_x + bar_w + 8; x < bar_x + bar_w + 60 && x < png.w; x++)
        for (int y = p.y - 6; y <= p.y + 6; y++)
            ink += at(&png, x, y).r < 100;
    TEST_ASSERT_TRUE_MESSAGE(ink > 10, "0 dB label");
    free(png.px);
    uwb_image_free(&img);
}

static int ink_in(const struct png_rgb *png, int x0, int x1, int y0, int y1)
{
    int n = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            struct uwb_rgb c = at(png, x, y);
            n += c.r < 128 && c.g < 128 && c.b < 128;
        }
    return n;
}

static void test_migrated_axes_have_tick_labels_on_both_axes(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct png_rgb png = render_migrated("axes.png", &img, NULL, NULL);
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_migrated_layout(&img, NULL, NULL, &p, &bar_x, &bar_w);
    int half_cap = UWB_FONT_CAP_HEIGHT; /* font scale 2 by default */
    /* y labels every 50 mm over 0..600: ink left of the axis at the 200 mm
     * tick, none half-way between two labels. */
    int r200 = row_of(&p, 0.200), r225 = row_of(&p, 0.225);
    TEST_ASSERT_TRUE_MESSAGE(ink_in(&png, p.x - 50, p.x - 12, r200 - half_cap, r200 + half_cap) > 15,
                             "y label 200");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, ink_in(&png, p.x - 50, p.x - 12, r225 - 3, r225 + 3),
                                  "no label between ticks");
    /* x labels under the axis at 450 mm */
    int c450 = col_of(&p, 0.450);
    TEST_ASSERT_TRUE_MESSAGE(ink_in(&png, c450 - 20, c450 + 20, p.y + p.h + 6, p.y + p.h + 30) > 15,
                             "x label 450");
    free(png.px);
    uwb_image_free(&img);
}

static void test_caption_text_names_the_scan(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    struct png_rgb a = render_migrated("a.png", &img, &v, NULL);
    snprintf(v.scan_id, sizeof v.scan_id, "T1-20240611-0043");
    struct png_rgb b = render_migrated("b.png", &img, &v, NULL);
    int caption_h = uwb_caption_height(&v, NULL, a.w, 2);
    int ink = ink_in(&a, 0, a.w - 1, 0, caption_h - 6), differ_caption = 0, differ_rest = 0;
    for (int y = 0; y < a.h; y++)
        for (int x = 0; x < a.w; x++) {
            int d = !same(at(&a, x, y), at(&b, x, y));
            if (y < caption_h)
                differ_caption += d;
            else
                differ_rest += d;
        }
    TEST_ASSERT_TRUE_MESSAGE(ink > 2000, "caption has text");
    TEST_ASSERT_TRUE_MESSAGE(differ_caption > 0, "a different scan id changes the caption");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, differ_rest, "and nothing else");
    free(a.px);
    free(b.px);
    uwb_image_free(&img);
}

static void test_long_reason_wraps_and_pushes_the_plot_down(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    int short_h = uwb_caption_height(&v, NULL, 960, 2);
    v.status = UWB_STATUS_INCONCLUSIVE;
    snprintf(v.reason, sizeof v.reason,
             "the baseline's upper edge lies beyond the last antenna position, so its centre "
             "and with it the displacement cannot be established from these scans");
    int long_h = uwb_caption_height(&v, NULL, 960, 2);
    int line = UWB_FONT_LINE_HEIGHT * 2 + 3;
    TEST_ASSERT_EQUAL_INT(short_h + 2 * line, long_h); /* the reason takes three lines */
    /* a longer reason takes more lines: nothing in a caption is cut */
    char three_lines[sizeof v.reason];
    snprintf(three_lines, sizeof three_lines, "%s", v.reason);
    memset(v.reason, 'x', sizeof v.reason - 1);
    for (size_t i = 10; i < sizeof v.reason - 1; i += 11)
        v.reason[i] = ' ';
    v.reason[sizeof v.reason - 1] = '\0';
    TEST_ASSERT_TRUE(uwb_caption_height(&v, NULL, 960, 2) > short_h + 2 * line);
    snprintf(v.reason, sizeof v.reason, "%s", three_lines);
    struct uwb_plot p_short, p_long;
    int bx, bw;
    struct uwb_verdict plain = make_verdict();
    uwb_render_migrated_layout(&img, &plain, NULL, &p_short, &bx, &bw);
    uwb_render_migrated_layout(&img, &v, NULL, &p_long, &bx, &bw);
    TEST_ASSERT_EQUAL_INT(p_short.y + 2 * line, p_long.y);
    struct png_rgb png = render_migrated("long.png", &img, &v, NULL);
    /* The plot really starts lower: its frame is right above p_long.y. */
    TEST_ASSERT_FALSE(same(at(&png, p_long.x + 5, p_long.y - 1), (struct uwb_rgb){255, 255, 255}));
    TEST_ASSERT_TRUE(same(at(&png, p_long.x + 5, p_long.y - 5), (struct uwb_rgb){255, 255, 255}));
    free(png.px);
    uwb_image_free(&img);
}

static void test_png_description_carries_the_verdict(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    char path[512], err[256];
    path_in_dir(path, sizeof path, "text.png");
    TEST_ASSERT_EQUAL_INT(0, uwb_render_migrated_png(path, &img, &v, err, sizeof err));
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL(fp);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    TEST_ASSERT_EQUAL_INT(0, setjmp(png_jmpbuf(png)));
    png_init_io(png, fp);
    png_read_info(png, info);
    png_textp texts;
    int n = 0;
    png_get_text(png, info, &texts, &n);
    const char *description = NULL;
    for (int i = 0; i < n; i++)
        if (!strcmp(texts[i].key, "Description"))
            description = texts[i].text;
    TEST_ASSERT_NOT_NULL(description);
    TEST_ASSERT_NOT_NULL(strstr(description, "T1-20240611-0042"));
    TEST_ASSERT_NOT_NULL(strstr(description, "watch"));
    TEST_ASSERT_NOT_NULL(strstr(description, "+20.00")); /* displacement in mm */
    TEST_ASSERT_NOT_NULL(strstr(description, "T1-20230302-0001"));
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    uwb_image_free(&img);
}

static void test_floor_option_changes_the_scale(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    o.floor_db = -60.0;
    struct png_rgb png = render_migrated("floor.png", &img, NULL, &o);
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_migrated_layout(&img, NULL, &o, &p, &bar_x, &bar_w);
    /* -40 dB background on a 0..-60 dB scale sits a third of the way up. */
    struct uwb_rgb bg = at(&png, col_of(&p, 0.65), row_of(&p, 0.45));
    struct uwb_rgb want = uwb_colormap_perceptual(1.0 / 3.0);
    TEST_ASSERT_INT_WITHIN(2, want.r, bg.r);
    TEST_ASSERT_INT_WITHIN(2, want.g, bg.g);
    TEST_ASSERT_INT_WITHIN(2, want.b, bg.b);
    free(png.px);
    uwb_image_free(&img);
}

static void test_same_input_gives_identical_bytes(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    char p1[512], p2[512], err[256];
    path_in_dir(p1, sizeof p1, "1.png");
    path_in_dir(p2, sizeof p2, "2.png");
    TEST_ASSERT_EQUAL_INT(0, uwb_render_migrated_png(p1, &img, &v, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwb_render_migrated_png(p2, &img, &v, err, sizeof err));
    FILE *a = fopen(p1, "rb"), *b = fopen(p2, "rb");
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    int ca, cb;
    long n = 0;
    do {
        ca = fgetc(a);
        cb = fgetc(b);
        TEST_ASSERT_EQUAL_INT(ca, cb);
        n++;
    } while (ca != EOF);
    TEST_ASSERT_TRUE(n > 1000);
    fclose(a);
    fclose(b);
    uwb_image_free(&img);
}

/* ---------- B-scan ---------- */

static void test_bscan_traces_are_at_their_antenna_heights(void)
{
    struct uwb_scan scan;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&scan, 21, 400, err, sizeof err));
    scan.sample_interval_s = 20e-12;
    scan.t0_s = -0.5e-9;
    scan.tx_m[0] = -0.02;
    scan.rx_m[0] = 0.02;
    for (int k = 0; k < 21; k++) {
        scan.antenna_y_m[k] = 0.03 * k;
        /* a positive arrival on every trace, a negative one on traces 5..10
         * only (heights 150..300 mm: low in the plot, so a flip shows) */
        for (int s = 95; s <= 105; s++)
            scan.data[k * 400 + s] = 100.0f;
        if (k >= 5 && k <= 10)
            for (int s = 245; s <= 255; s++)
                scan.data[k * 400 + s] = -50.0f;
    }
    struct uwb_verdict v = make_verdict();
    char path[512];
    path_in_dir(path, sizeof path, "bscan.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_bscan_png(path, &scan, &v, err, sizeof err), err);
    struct png_rgb png = read_png(path);
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_bscan_layout(&scan, &v, NULL, &p, &bar_x, &bar_w);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, -0.015, p.y_min);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.615, p.y_max);
    double t_pos = scan.t0_s + 100 * scan.sample_interval_s, t_neg = scan.t0_s + 250 * scan.sample_interval_s;
    struct uwb_rgb c;
    c = at(&png, col_of(&p, t_pos), row_of(&p, 0.51));
    TEST_ASSERT_TRUE_MESSAGE(c.r > c.b + 60, "positive arrival is red");
    c = at(&png, col_of(&p, t_neg), row_of(&p, 0.21));
    TEST_ASSERT_TRUE_MESSAGE(c.b > c.r + 60, "negative arrival is blue, at its trace's height");
    c = at(&png, col_of(&p, t_neg), row_of(&p, 0.45));
    TEST_ASSERT_TRUE_MESSAGE(same(c, uwb_colormap_diverging(0.5)), "no arrival there: zero colour");
    /* -50 is 6 dB under the peak 100: on a 40 dB scale, 85 % toward blue. */
    c = at(&png, col_of(&p, t_neg), row_of(&p, 0.15));
    struct uwb_rgb want = uwb_colormap_diverging(uwb_signed_db_to_t(-50.0, 100.0, -40.0));
    TEST_ASSERT_INT_WITHIN(2, want.b, c.b);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.5 - 0.5 * (40 - 20 * log10(2.0)) / 40,
                              uwb_signed_db_to_t(-50.0, 100.0, -40.0));
    /* The current lower edge crosses the face's echo time on its row. */
    double t_face = uwb_face_echo_time(&scan, FACE_Z);
    TEST_ASSERT_DOUBLE_WITHIN(1e-13, sqrt(0.9 * 0.9 + 0.04 * 0.04) / 299792458.0, t_face);
    TEST_ASSERT_TRUE(same(at(&png, col_of(&p, t_face) + 10, row_of(&p, FACE_LO)), UWB_RGB_CURRENT_EDGE));
    free(png.px);
    uwb_scan_free(&scan);
}

/* ---------- comparison ---------- */

static void test_comparison_shows_both_scans_and_the_shift(void)
{
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_analysis base = make_analysis(BASE_LO, BASE_HI, BASE_LO, BASE_HI);
    struct uwb_verdict v = make_verdict();
    char path[512], err[256];
    path_in_dir(path, sizeof path, "cmp.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, &base, &v, err, sizeof err), err);
    struct png_rgb png = read_png(path);
    struct uwb_plot pb, pc, pd, pp;
    int bar_x, bar_w;
    uwb_render_comparison_layout(&cur, &base, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    TEST_ASSERT_TRUE(pb.x + pb.w < pc.x && pc.x + pc.w < pp.x); /* baseline left, current right */
    struct uwb_rgb peak = uwb_colormap_perceptual(1.0);
    int fc_b = col_of(&pb, FACE_Z), fc_c = col_of(&pc, FACE_Z);
    /* Each panel shows its own image: the face bright at the heights only
     * one of them has (80..100 mm baseline only, 230..250 current only). */
    TEST_ASSERT_TRUE(same(at(&png, fc_b, row_of(&pb, 0.090)), peak));
    TEST_ASSERT_FALSE(same(at(&png, fc_c, row_of(&pc, 0.090)), peak));
    TEST_ASSERT_TRUE(same(at(&png, fc_c, row_of(&pc, 0.240)), peak));
    TEST_ASSERT_FALSE(same(at(&png, fc_b, row_of(&pb, 0.240)), peak));
    /* This scan's panel: its edges solid, the baseline's dashed beside them. */
    int row_cur = row_of(&pc, FACE_LO), row_base = row_of(&pc, BASE_LO);
    TEST_ASSERT_TRUE(row_base > row_cur + 5); /* moved up = drawn higher */
    int solid = 0, pink = 0;
    for (int x = pc.x + 2; x < pc.x + pc.w - 2; x++) {
        solid += same(at(&png, x, row_cur), UWB_RGB_CURRENT_EDGE);
        pink += same(at(&png, x, row_base), UWB_RGB_BASELINE_EDGE);
    }
    TEST_ASSERT_TRUE_MESSAGE(solid >= pc.w - 6, "current edge solid across the panel");
    TEST_ASSERT_TRUE_MESSAGE(pink > pc.w / 3 && pink < pc.w - 20, "baseline edge dashed across the panel");
    /* Profile panel: both curves present; at mid-face of this scan (175 mm)
     * the white curve reaches the right part of the panel. */
    int white_right = 0, pink_curve = 0;
    int r175 = row_of(&pp, 0.175), r120 = row_of(&pp, 0.090);
    for (int x = col_of(&pp, 0.9); x < pp.x + pp.w; x++) {
        white_right += same(at(&png, x, r175), UWB_RGB_CURRENT_EDGE);
        pink_curve += same(at(&png, x, r120), UWB_RGB_BASELINE_EDGE);
    }
    TEST_ASSERT_TRUE_MESSAGE(white_right > 0, "current profile at full intensity mid-face");
    TEST_ASSERT_TRUE_MESSAGE(pink_curve > 0, "baseline profile at full intensity where only it is bright");
    free(png.px);
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
}

/* The profile panel draws the profile the analysis read its edges from, not
 * one taken again from the display image: here the two are made to differ
 * (the profile bright at 350..450 mm, the image's face at 100..250 mm), and
 * the curve follows the profile. */
static void test_comparison_draws_the_analysis_profile_not_the_image(void)
{
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, 0.35, 0.45);
    struct uwb_verdict v = make_verdict();
    v.has_baseline = 0;
    v.status = UWB_STATUS_EDGES;
    char path[512], err[256];
    path_in_dir(path, sizeof path, "cmp-profile.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, NULL, &v, err, sizeof err), err);
    struct png_rgb png = read_png(path);
    struct uwb_plot pb, pc, pd, pp;
    int bar_x, bar_w;
    uwb_render_comparison_layout(&cur, NULL, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    int at_profile = 0, at_image = 0;
    int r_profile = row_of(&pp, 0.40), r_image = row_of(&pp, 0.20);
    for (int x = col_of(&pp, 0.9); x < pp.x + pp.w; x++) {
        at_profile += same(at(&png, x, r_profile), UWB_RGB_CURRENT_EDGE);
        at_image += same(at(&png, x, r_image), UWB_RGB_CURRENT_EDGE);
    }
    TEST_ASSERT_TRUE_MESSAGE(at_profile > 0, "curve at full intensity where the analysis' profile is");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, at_image, "no curve at full intensity where only the image is bright");
    /* The drawing's own points: value / peak on the x axis, one per sample. */
    int xs[601], ys[601];
    int n = uwb_comparison_profile_polyline(&pp, &cur.profile, xs, ys);
    TEST_ASSERT_TRUE(n > 300);
    for (int i = 0; i < n; i++) {
        double y = pp.y_max - (ys[i] - pp.y) * (pp.y_max - pp.y_min) / (pp.h - 1);
        int bright = y >= 0.35 + 0.002 && y <= 0.45 - 0.002, dark = y < 0.35 - 0.002 || y > 0.45 + 0.002;
        if (bright)
            TEST_ASSERT_INT_WITHIN(1, col_of(&pp, 1.0), xs[i]);
        if (dark)
            TEST_ASSERT_INT_WITHIN(1, col_of(&pp, BACKGROUND), xs[i]);
    }
    free(png.px);
    uwb_analysis_free(&cur);
}

static void test_comparison_without_baseline_draws_this_scan_only(void)
{
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    v.has_baseline = 0;
    v.status = UWB_STATUS_EDGES;
    char path[512], err[256];
    path_in_dir(path, sizeof path, "cmp1.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, NULL, &v, err, sizeof err), err);
    struct png_rgb png = read_png(path);
    struct uwb_plot pb, pc, pd, pp;
    int bar_x, bar_w;
    uwb_render_comparison_layout(&cur, NULL, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    int pink = 0;
    for (int y = pb.y; y < pb.y + pb.h; y++)
        for (int x = pb.x; x < pp.x + pp.w; x++)
            pink += same(at(&png, x, y), UWB_RGB_BASELINE_EDGE);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, pink, "nothing drawn as baseline");
    TEST_ASSERT_TRUE(same(at(&png, col_of(&pc, FACE_Z) + 15, row_of(&pc, FACE_LO)), UWB_RGB_CURRENT_EDGE));
    /* The baseline panel carries no image (no colour-map colours). */
    struct uwb_rgb c = at(&png, pb.x + 5, pb.y + 5);
    TEST_ASSERT_TRUE(c.r == c.g && c.g == c.b);
    free(png.px);
    uwb_analysis_free(&cur);
}

/* ---------- failures ---------- */

static void test_unwritable_path_fails_naming_it_and_leaves_nothing(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    char path[512], err[512] = "";
    snprintf(path, sizeof path, "%s/no-such-dir/m.png", dir);
    TEST_ASSERT_EQUAL_INT(-1, uwb_render_migrated_png(path, &img, &v, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, path), err);
    TEST_ASSERT_EQUAL_INT(0, count_dir_entries(dir));
    uwb_image_free(&img);
}

static void test_libpng_failure_keeps_the_old_file_and_no_temporary(void)
{
    char path[512], err[512] = "";
    path_in_dir(path, sizeof path, "old.png");
    FILE *fp = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(fp);
    fputs("old", fp);
    fclose(fp);
    /* A width libpng refuses (over its 1,000,000 px limit) makes it fail
     * inside png_set_IHDR, through the longjmp path. */
    unsigned char row[3] = {0, 0, 0};
    struct uwb_canvas c = {2000000, 1, row};
    TEST_ASSERT_EQUAL_INT(-1, uwb_canvas_write_png(&c, path, NULL, 0, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, path), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "PNG"), err);
    TEST_ASSERT_EQUAL_INT(1, count_dir_entries(dir));
    char buf[16] = "";
    fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL(fp);
    TEST_ASSERT_NOT_NULL(fgets(buf, sizeof buf, fp));
    fclose(fp);
    TEST_ASSERT_EQUAL_STRING("old", buf);
}

static void test_bad_inputs_are_refused_with_the_path(void)
{
    char path[512], err[512] = "";
    path_in_dir(path, sizeof path, "bad.png");
    struct uwb_image empty = {0};
    TEST_ASSERT_EQUAL_INT(-1, uwb_render_migrated_png(path, &empty, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, path));
    struct uwb_analysis bad = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    bad.intensity.dy_m = 0.0;
    TEST_ASSERT_EQUAL_INT(-1, uwb_render_comparison_png(path, &bad, NULL, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "spacing"));
    uwb_analysis_free(&bad);
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_scan scan;
    memset(&scan, 0, sizeof scan);
    TEST_ASSERT_EQUAL_INT(-1, uwb_render_bscan_png(path, &scan, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, path));
    TEST_ASSERT_EQUAL_INT(0, count_dir_entries(dir));
    uwb_image_free(&img);
}

/* ---------- provenance, text chunks, what is not measured ---------- */

#define MAX_TEXTS 16
struct png_texts {
    int n;
    char key[MAX_TEXTS][80];
    char text[MAX_TEXTS][2048];
    int compression[MAX_TEXTS]; /* PNG_TEXT_COMPRESSION_NONE: tEXt; PNG_ITXT_COMPRESSION_NONE: iTXt */
};

static void read_texts(const char *path, struct png_texts *out)
{
    memset(out, 0, sizeof *out);
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, path);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    TEST_ASSERT_EQUAL_INT(0, setjmp(png_jmpbuf(png)));
    png_init_io(png, fp);
    png_read_info(png, info);
    png_textp texts;
    int n = 0;
    png_get_text(png, info, &texts, &n);
    for (int i = 0; i < n && i < MAX_TEXTS; i++) {
        snprintf(out->key[i], sizeof out->key[i], "%s", texts[i].key);
        snprintf(out->text[i], sizeof out->text[i], "%s", texts[i].text);
        out->compression[i] = texts[i].compression;
    }
    out->n = n < MAX_TEXTS ? n : MAX_TEXTS;
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
}

/* The chunk's text, or NULL; *compression gets its kind. */
static const char *text_of(const struct png_texts *t, const char *key, int *compression)
{
    for (int i = 0; i < t->n; i++)
        if (!strcmp(t->key[i], key)) {
            if (compression)
                *compression = t->compression[i];
            return t->text[i];
        }
    return NULL;
}

static int is_ascii_text(const char *s)
{
    for (; *s; s++)
        if ((unsigned char)*s >= 0x80)
            return 0;
    return 1;
}

/* A replayed file without a scan id: every image names the scan by the
 * file's stem (not "(unknown)") and carries the asset, the software
 * version, the stack, eps_r and the SNR; UTF-8 text sits in iTXt chunks,
 * ASCII in tEXt. */
static void test_replayed_images_carry_the_file_stem_and_provenance(void)
{
    struct uwb_scan cur, base;
    fixture_load_scan("tests/fixtures/fdtd2d-paper-up20mm.uwbscan", &cur);
    fixture_load_scan("tests/fixtures/fdtd2d-paper-intact.uwbscan", &base);
    free(cur.scan_id);
    cur.scan_id = NULL;
    if (cur.stack <= 0)
        cur.stack = 64; /* the fixture may not record it; the images must show what the scan says */
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_baseline_record rec = {.scan = &base};
    struct uwb_verdict v;
    struct uwb_analysis cur_a, base_a;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &cur_a, &base_a, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_STRING("", v.scan_id);
    const char *asset = "Umspannwerk S\u00fcd, phase B";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0,
                                  uwb_write_images(dir, "site-recording-7",
                                                   &(struct uwb_provenance){.asset = asset}, &cur, &cur_a,
                                                   &base_a, &v, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_INT(3, v.n_images);
    /* The B-scan shows the conditioned traces the migration ran on, not
     * the raw ones (whose direct coupling and clutter were taken out). */
    struct png_texts bt;
    read_texts(v.images[1], &bt);
    TEST_ASSERT_EQUAL_STRING("uwbd conditioned B-scan", text_of(&bt, "Title", NULL));
    char raw_path[512];
    path_in_dir(raw_path, sizeof raw_path, "raw-bscan.png");
    struct uwb_provenance prov = {
        .scan_name = "site-recording-7", .asset = asset, .stack = cur.stack, .eps_r = cur.eps_r};
    struct uwb_render_options ro;
    uwb_render_options_default(&ro);
    ro.provenance = &prov;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_bscan_png_opt(raw_path, &cur, &v, &ro, err, sizeof err), err);
    struct png_rgb conditioned_png = read_png(v.images[1]), raw_png = read_png(raw_path);
    struct uwb_plot bp;
    int bbx, bbw;
    uwb_render_bscan_layout(&cur_a.conditioned, &v, &ro, &bp, &bbx, &bbw);
    int differ = 0;
    for (int y = bp.y; y < bp.y + bp.h; y++)
        for (int x = bp.x; x < bp.x + bp.w; x++)
            differ += !same(at(&conditioned_png, x, y), at(&raw_png, x, y));
    TEST_ASSERT_TRUE_MESSAGE(differ > bp.w * bp.h / 20, "conditioned traces drawn, not the raw ones");
    free(conditioned_png.px);
    free(raw_png.px);
    unlink(raw_path);
    char stack[32], eps[32];
    snprintf(stack, sizeof stack, "%d", cur.stack);
    snprintf(eps, sizeof eps, "%.3g", cur.eps_r);
    for (int i = 0; i < v.n_images; i++) {
        struct png_texts t;
        read_texts(v.images[i], &t);
        int kind = 0;
        TEST_ASSERT_EQUAL_STRING_MESSAGE("site-recording-7", text_of(&t, "Scan", NULL), v.images[i]);
        const char *d = text_of(&t, "Description", &kind);
        TEST_ASSERT_NOT_NULL(d);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "scan site-recording-7 "), d);
        TEST_ASSERT_NULL_MESSAGE(strstr(d, "scan (unknown)"), d);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "asset Umspannwerk S\u00fcd, phase B"), d);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "uwbd " UWBD_VERSION), d);
        TEST_ASSERT_EQUAL_INT_MESSAGE(PNG_ITXT_COMPRESSION_NONE, kind,
                                      "the description (with a \u00b1) is UTF-8 iTXt");
        TEST_ASSERT_EQUAL_STRING(asset, text_of(&t, "Asset", &kind));
        TEST_ASSERT_EQUAL_INT(PNG_ITXT_COMPRESSION_NONE, kind);
        TEST_ASSERT_EQUAL_STRING("uwbd " UWBD_VERSION, text_of(&t, "Software", &kind));
        TEST_ASSERT_EQUAL_INT_MESSAGE(PNG_TEXT_COMPRESSION_NONE, kind, "ASCII stays in tEXt");
        TEST_ASSERT_EQUAL_STRING(stack, text_of(&t, "Stack", NULL));
        TEST_ASSERT_EQUAL_STRING(eps, text_of(&t, "eps_r", NULL));
        const char *snr = text_of(&t, "SNR dB", NULL);
        TEST_ASSERT_NOT_NULL(snr);
        TEST_ASSERT_DOUBLE_WITHIN(0.051, v.current.snr_db, strtod(snr, NULL));
        /* No chunk says it is Latin-1 while holding UTF-8. */
        for (int k = 0; k < t.n; k++) {
            if (t.compression[k] == PNG_TEXT_COMPRESSION_NONE) {
                TEST_ASSERT_TRUE_MESSAGE(is_ascii_text(t.text[k]), t.key[k]);
            }
        }
        unlink(v.images[i]);
    }
    uwb_analysis_free(&cur_a);
    uwb_analysis_free(&base_a);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
}

/* The caption names an id-less scan by the name it was given, and shows
 * the source line; with neither it says "(unknown)". */
static void test_caption_names_an_id_less_scan_by_its_given_name(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    v.scan_id[0] = '\0';
    struct uwb_provenance prov = {.scan_name = "recording-7", .asset = "phase B", .stack = 64, .eps_r = 3.2};
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    struct png_rgb a = render_migrated("anon.png", &img, &v, &o);
    o.provenance = &prov;
    struct png_rgb b = render_migrated("named.png", &img, &v, &o);
    /* One caption line more: the source line holds the asset etc., too
     * long for one line at 960 px, so it wraps rather than being cut. */
    TEST_ASSERT_EQUAL_INT(uwb_caption_height(&v, NULL, 960, 2) + UWB_FONT_LINE_HEIGHT * 2 + 3,
                          uwb_caption_height(&v, &prov, 960, 2));
    int caption_h = uwb_caption_height(&v, &prov, a.w, 2), differ = 0;
    for (int y = 0; y < caption_h; y++)
        for (int x = 0; x < a.w; x++)
            differ += !same(at(&a, x, y), at(&b, x, y));
    TEST_ASSERT_TRUE_MESSAGE(differ > 200, "the name and the source line are drawn");
    char line[512];
    uwb_describe_provenance(&v, &prov, line, sizeof line);
    TEST_ASSERT_EQUAL_STRING(
        "asset phase B   stack 64 pulses/position   eps_r 3.20   SNR 0.0 dB   uwbd " UWBD_VERSION, line);
    uwb_describe_provenance(NULL, NULL, line, sizeof line);
    TEST_ASSERT_EQUAL_STRING("asset (not set)   uwbd " UWBD_VERSION, line);
    char summary[2048];
    uwb_verdict_summary(&v, NULL, summary, sizeof summary);
    TEST_ASSERT_NOT_NULL(strstr(summary, "scan (unknown) "));
    uwb_verdict_summary(&v, &prov, summary, sizeof summary);
    TEST_ASSERT_NOT_NULL(strstr(summary, "scan recording-7 "));
    free(a.px);
    free(b.px);
    uwb_image_free(&img);
}

/* Pixels of `colour` in the profile panel between the two centres' rows,
 * in the column the displacement arrow is drawn in. */
static int arrow_pixels(const struct png_rgb *png, const struct uwb_plot *pp, const struct uwb_verdict *v,
                        struct uwb_rgb colour)
{
    int col = pp->x + pp->w * 82 / 100, n = 0;
    int r0 = row_of(pp, v->baseline.center_m), r1 = row_of(pp, v->current.center_m);
    for (int y = (r0 < r1 ? r0 : r1) + 2; y <= (r0 < r1 ? r1 : r0) - 2; y++)
        for (int x = col - 1; x <= col + 1; x++)
            n += same(at(png, x, y), colour);
    return n;
}

static int colour_in_panel(const struct png_rgb *png, const struct uwb_plot *p, struct uwb_rgb colour)
{
    int n = 0;
    for (int y = p->y; y < p->y + p->h; y++)
        for (int x = p->x; x < p->x + p->w; x++)
            n += same(at(png, x, y), colour);
    return n;
}

/* An inconclusive or error verdict against a baseline draws no arrow even
 * when both scans' edges were found: the gap is hatched grey and marked
 * "not measured" with the reason; a watch verdict draws the arrow and no
 * grey. */
static void test_comparison_without_a_measured_displacement_draws_no_arrow(void)
{
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_analysis base = make_analysis(BASE_LO, BASE_HI, BASE_LO, BASE_HI);
    const enum uwb_status statuses[] = {UWB_STATUS_WATCH, UWB_STATUS_INCONCLUSIVE, UWB_STATUS_ERROR};
    for (int i = 0; i < 3; i++) {
        struct uwb_verdict v = make_verdict();
        v.status = statuses[i];
        if (i > 0)
            snprintf(v.reason, sizeof v.reason, "uncertainty 3.1 mm exceeds the 1.0 mm allowed");
        char path[512], err[256];
        path_in_dir(path, sizeof path, "cmp-status.png");
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, &base, &v, err, sizeof err),
                                      err);
        struct png_rgb png = read_png(path);
        struct uwb_plot pb, pc, pd, pp;
        int bar_x, bar_w;
        uwb_render_comparison_layout(&cur, &base, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
        int arrow = arrow_pixels(&png, &pp, &v, UWB_RGB_CURRENT_EDGE);
        int grey = colour_in_panel(&png, &pp, UWB_RGB_NOT_MEASURED);
        if (statuses[i] == UWB_STATUS_WATCH) {
            TEST_ASSERT_TRUE_MESSAGE(arrow > 10, "a measured displacement has its arrow");
            TEST_ASSERT_EQUAL_INT(0, grey);
        } else {
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, arrow, uwb_status_name(statuses[i]));
            TEST_ASSERT_TRUE_MESSAGE(arrow_pixels(&png, &pp, &v, UWB_RGB_NOT_MEASURED) > 0,
                                     "gap hatched grey");
            TEST_ASSERT_TRUE_MESSAGE(grey > 2000, "a grey 'not measured' box");
        }
        free(png.px);
        unlink(path);
    }
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
}

/* Issue 48, finding 7: no word on the comparison is cut at a panel's
 * edge. A commissioning scan's empty panels say "new baseline" whole
 * (they read "ew baselin"), a displacement not measured keeps its whole
 * reason in the profile panel ("not measured radial cha"), and the
 * profile's axis is in plain words, not "intensity re peak". */
static void test_comparison_words_are_whole(void)
{
    const struct uwb_rgb page = {255, 255, 255};
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_analysis base = make_analysis(BASE_LO, BASE_HI, BASE_LO, BASE_HI);
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    struct uwb_provenance prov = {.scan_name = "x", .became_baseline = 1};
    o.provenance = &prov;
    struct uwb_verdict v = make_verdict();
    v.has_baseline = 0;
    v.status = UWB_STATUS_EDGES;
    char path[512], err[256];
    path_in_dir(path, sizeof path, "cmp-words.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png_opt(path, &cur, NULL, &v, &o, err, sizeof err),
                                  err);
    struct png_rgb png = read_png(path);
    struct uwb_plot pb, pc, pd, pp;
    int bar_x, bar_w;
    uwb_render_comparison_layout(&cur, NULL, &v, &o, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    const unsigned char *panels = png.px + (size_t)pb.y * (size_t)png.w * 3;
    int s = o.font_scale;
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, png_text_find(panels, png.w, pb.h, "baseline", s, page, NULL, NULL),
                                  "\"baseline\" whole in the baseline and difference panels");
    TEST_ASSERT_EQUAL_INT(2, png_text_find(panels, png.w, pb.h, "new", s, page, NULL, NULL));
    free(png.px);

    prov.became_baseline = 0;
    v = make_verdict();
    v.status = UWB_STATUS_INCONCLUSIVE;
    snprintf(v.reason, sizeof v.reason, "radial change could not be read: too few rows of the face ENDWORD");
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwb_render_comparison_png_opt(path, &cur, &base, &v, &o, err, sizeof err), err);
    png = read_png(path);
    TEST_ASSERT_TRUE_MESSAGE(png_text_present(png.px, png.w, png.h, "ENDWORD"), "the reason's last word");
    TEST_ASSERT_TRUE_MESSAGE(png_text_present(png.px, png.w, png.h, "radial change could"),
                             "the reason's first words");
    TEST_ASSERT_FALSE(png_text_present(png.px, png.w, png.h, "intensity re peak"));
    TEST_ASSERT_TRUE_MESSAGE(png_text_present(png.px, png.w, png.h, "brightness / peak"),
                             "the profile's axis");
    free(png.px);
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
}

/* Issue 48, finding 7: the radial panel names a change "dent" or
 * "bulge" only beyond its noise (the 95 % interval holds zero: it is no
 * shape), and never prints "-0.0"; read from the pixels and the Radial
 * text chunk. A change well beyond its noise is still named. */
static void test_radial_words_stay_within_the_noise(void)
{
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_analysis base = make_analysis(BASE_LO, BASE_HI, BASE_LO, BASE_HI);
    const struct {
        double change_m, sigma_m;
        const char *named;
    } cases[] = {
        {-0.00004, 0.0003, NULL},
        {0.0002, 0.0003, NULL},
        {0.0031, 0.0004, "bulge"},
        {-0.0031, 0.0004, "dent"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        struct uwb_verdict v = make_verdict();
        v.status = UWB_STATUS_OK;
        v.radial.measured = 1;
        v.radial.status = UWB_STATUS_OK;
        v.radial.max_change_m = cases[i].change_m;
        v.radial.uncertainty_m = cases[i].sigma_m;
        v.radial.at_m = 0.2;
        snprintf(v.radial.tilt_withheld, sizeof v.radial.tilt_withheld, "no lean");
        char path[512], err[256];
        path_in_dir(path, sizeof path, "cmp-radial-words.png");
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, &base, &v, err, sizeof err),
                                      err);
        struct png_rgb png = read_png(path);
        struct png_texts t;
        read_texts(path, &t);
        const char *radial = text_of(&t, "Radial", NULL);
        TEST_ASSERT_NOT_NULL(radial);
        TEST_ASSERT_NULL_MESSAGE(strstr(radial, "-0.0"), radial);
        TEST_ASSERT_FALSE_MESSAGE(png_text_present(png.px, png.w, png.h, "-0.0"), radial);
        if (cases[i].named) {
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(radial, cases[i].named), radial);
            TEST_ASSERT_TRUE_MESSAGE(png_text_present(png.px, png.w, png.h, cases[i].named), radial);
        } else {
            TEST_ASSERT_NULL_MESSAGE(strstr(radial, "dent"), radial);
            TEST_ASSERT_NULL_MESSAGE(strstr(radial, "bulge"), radial);
            TEST_ASSERT_FALSE_MESSAGE(png_text_present(png.px, png.w, png.h, "dent"), radial);
            TEST_ASSERT_FALSE_MESSAGE(png_text_present(png.px, png.w, png.h, "bulge"), radial);
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(radial, "within its noise"), radial);
        }
        free(png.px);
        unlink(path);
    }
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
}

/* The migrated image has as many mm per pixel across as up: a circle in
 * the tank is a circle on the page. */
static void test_migrated_image_has_equal_scales(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_migrated_layout(&img, &v, NULL, &p, &bar_x, &bar_w);
    double across = (p.x_max - p.x_min) / (p.w - 1), up = (p.y_max - p.y_min) / (p.h - 1);
    TEST_ASSERT_DOUBLE_WITHIN(0.01 * up, up, across);
    TEST_ASSERT_EQUAL_INT(p.x + p.w + 22, bar_x);
    /* And on the page: the face (20 mm wide, 150 mm tall) spans that many
     * mm in pixels each way. */
    uwb_render_migrated_layout(&img, NULL, NULL, &p, &bar_x, &bar_w); /* no overlays on the face */
    up = (p.y_max - p.y_min) / (p.h - 1);
    struct png_rgb png = render_migrated("aspect.png", &img, NULL, NULL);
    struct uwb_rgb peak = uwb_colormap_perceptual(1.0);
    int cols = 0, rows = 0, mid_row = row_of(&p, 0.5 * (FACE_LO + FACE_HI)), fc = col_of(&p, FACE_Z);
    for (int x = p.x; x < p.x + p.w; x++)
        cols += same(at(&png, x, mid_row), peak);
    for (int y = p.y; y < p.y + p.h; y++)
        rows += same(at(&png, fc, y), peak);
    char msg[96];
    snprintf(msg, sizeof msg, "%d columns, %d rows at %.3f mm/px", cols, rows, 1000.0 * up);
    TEST_ASSERT_INT_WITHIN_MESSAGE(3, (int)lround(0.020 / up), cols, msg);
    TEST_ASSERT_INT_WITHIN_MESSAGE(3, (int)lround(0.150 / up), rows, msg);
    free(png.px);
    uwb_image_free(&img);
}

/* The difference panel: red where only this scan is bright (its face moved
 * up to 230..250 mm), blue where only the baseline is (80..100 mm), white
 * where both are; full colour at the largest difference. Without a
 * baseline it is grey and says so. */
static void test_comparison_difference_panel_shows_the_move(void)
{
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_analysis base = make_analysis(BASE_LO, BASE_HI, BASE_LO, BASE_HI);
    struct uwb_verdict v = make_verdict();
    char path[512], err[256];
    path_in_dir(path, sizeof path, "cmp-diff.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, &base, &v, err, sizeof err), err);
    struct png_rgb png = read_png(path);
    struct uwb_plot pb, pc, pd, pp;
    int bar_x, bar_w;
    uwb_render_comparison_layout(&cur, &base, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    TEST_ASSERT_TRUE(pc.x + pc.w < pd.x && pd.x + pd.w < pp.x); /* between this scan and the profiles */
    int fc = col_of(&pd, FACE_Z);
    TEST_ASSERT_TRUE(same(at(&png, fc, row_of(&pd, 0.240)), uwb_colormap_diverging(1.0)));
    TEST_ASSERT_TRUE(same(at(&png, fc, row_of(&pd, 0.090)), uwb_colormap_diverging(0.0)));
    TEST_ASSERT_TRUE(same(at(&png, fc, row_of(&pd, 0.175)), uwb_colormap_diverging(0.5)));
    TEST_ASSERT_TRUE(
        same(at(&png, col_of(&pd, FACE_Z + 0.040), row_of(&pd, 0.240)), uwb_colormap_diverging(0.5)));
    free(png.px);
    unlink(path);

    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_comparison_png(path, &cur, NULL, &v, err, sizeof err), err);
    png = read_png(path);
    uwb_render_comparison_layout(&cur, NULL, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    struct uwb_rgb grey = {128, 128, 128};
    TEST_ASSERT_TRUE(same(at(&png, fc, row_of(&pd, 0.240)), grey));
    int lettering = 0; /* "no baseline" in white across the middle */
    for (int y = pd.y + pd.h / 2 - 2; y <= pd.y + pd.h / 2 + 16; y++)
        for (int x = pd.x + 2; x < pd.x + pd.w - 2; x++)
            lettering += same(at(&png, x, y), (struct uwb_rgb){255, 255, 255});
    TEST_ASSERT_TRUE(lettering > 20);
    free(png.px);
    unlink(path);
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
}

/* A page with the limits meter: the +20 mm verdict (sigma 0.4 mm), watch
 * 2 mm, alarm 5 mm, and where its meter sits. */
struct meter_page {
    struct uwb_verdict v;
    struct uwb_thresholds th;
    struct uwb_provenance prov;
    struct uwb_render_options o;
    struct uwb_meter m;
};

static void meter_page_init(struct meter_page *p)
{
    p->v = make_verdict();
    p->th = (struct uwb_thresholds){.watch_m = 0.002, .alarm_m = 0.005};
    p->prov = (struct uwb_provenance){.scan_name = "x", .thresholds = &p->th};
    uwb_render_options_default(&p->o);
    p->o.provenance = &p->prov;
    TEST_ASSERT_TRUE(uwb_caption_meter(&p->v, &p->prov, p->o.width, p->o.font_scale, &p->m));
}

/* The watch and alarm thresholds: a caption line names them in their
 * zones' colours and a meter on the displacement's own scale (on the
 * height axis 5 mm is a few pixels) shows the zones with this scan's
 * displacement and its 95 % interval; the Description says them too. No
 * thresholds given: no line, no meter. */
static void test_images_show_the_watch_and_alarm_zones(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_analysis cur = make_analysis(FACE_LO, FACE_HI, FACE_LO, FACE_HI);
    struct uwb_analysis base = make_analysis(BASE_LO, BASE_HI, BASE_LO, BASE_HI);
    struct meter_page page;
    meter_page_init(&page);
    TEST_ASSERT_TRUE(page.m.w > 100);
    TEST_ASSERT_TRUE(page.m.half_range_m >= page.v.axial_displacement_m + 2 * page.v.uncertainty_m);
    TEST_ASSERT_TRUE(uwb_caption_height(&page.v, &page.prov, page.o.width, 2) >
                     uwb_caption_height(&page.v, NULL, page.o.width, 2));
    char path[512], err[256];
    path_in_dir(path, sizeof path, "cmp-zones.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwb_render_comparison_png_opt(path, &cur, &base, &page.v, &page.o, err, sizeof err), err);
    struct png_rgb images[2] = {render_migrated("mig-zones.png", &img, &page.v, &page.o), read_png(path)};
    const struct uwb_rgb ink = {25, 25, 25};
    for (int i = 0; i < 2; i++) {
        const struct png_rgb *png = &images[i];
        int top = page.m.y + 1; /* a row of the bar clear of the interval bar in the middle */
        TEST_ASSERT_TRUE(same(at(png, uwb_meter_col(&page.m, 0.001), top), uwb_status_colour(UWB_STATUS_OK)));
        TEST_ASSERT_TRUE(
            same(at(png, uwb_meter_col(&page.m, -0.0035), top), uwb_status_colour(UWB_STATUS_WATCH)));
        TEST_ASSERT_TRUE(
            same(at(png, uwb_meter_col(&page.m, 0.0035), top), uwb_status_colour(UWB_STATUS_WATCH)));
        TEST_ASSERT_TRUE(
            same(at(png, uwb_meter_col(&page.m, -0.007), top), uwb_status_colour(UWB_STATUS_ALARM)));
        /* The displacement's mark, and its 95 % interval's ends (+/-2 sigma). */
        int mid = page.m.y + page.m.h / 2;
        TEST_ASSERT_TRUE(same(at(png, uwb_meter_col(&page.m, page.v.axial_displacement_m), top), ink));
        TEST_ASSERT_TRUE(same(
            at(png, uwb_meter_col(&page.m, page.v.axial_displacement_m + 2 * page.v.uncertainty_m), mid - 3),
            ink));
        TEST_ASSERT_TRUE(same(
            at(png, uwb_meter_col(&page.m, page.v.axial_displacement_m - 2 * page.v.uncertainty_m), mid - 3),
            ink));
        free(images[i].px);
    }
    struct png_texts t;
    read_texts(path, &t);
    const char *d = text_of(&t, "Description", NULL);
    TEST_ASSERT_NOT_NULL(d);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "thresholds watch 2.00 mm, alarm 5.00 mm"), d);
    /* Without thresholds: no meter. */
    page.prov.thresholds = NULL;
    TEST_ASSERT_FALSE(uwb_caption_meter(&page.v, &page.prov, page.o.width, page.o.font_scale, &page.m));
    uwb_image_free(&img);
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
}

/* The ± is named: one sigma, and the 95 % interval (UWB_SIGMAS_95 sigma
 * either side) is given in figures, in the caption (a line beside the
 * meter) and in the Description, as `ctl --text` gives them. */
static void test_the_plus_minus_says_what_it_is(void)
{
    struct uwb_verdict v = make_verdict(); /* +20.00 mm, sigma 0.40 mm */
    char line[512], summary[2048];
    TEST_ASSERT_TRUE(uwb_font_has_glyph(0x03C3));
    uwb_describe_displacement(&v, line, sizeof line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "+20.00 \u00b1 0.40 mm (1\u03c3)"), line);
    uwb_describe_edges(&v.current, line, sizeof line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "\u00b1 0.3 mm (1\u03c3)"), line);
    uwb_verdict_summary(&v, NULL, summary, sizeof summary);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(summary, "95 % interval +19.20..+20.80 mm"), summary);
    struct uwb_thresholds th = {.watch_m = 0.002, .alarm_m = 0.005};
    struct uwb_provenance prov = {.thresholds = &th};
    int line_h = UWB_FONT_LINE_HEIGHT * 2 + 3, numbers = uwb_meter_labels_height(2);
    /* limits, the meter on a line of its own with its numbers under it,
     * and the 95 % line when measured; no 95 % line when not */
    TEST_ASSERT_EQUAL_INT(uwb_caption_height(&v, NULL, 960, 2) + 3 * line_h + numbers,
                          uwb_caption_height(&v, &prov, 960, 2));
    v.status = UWB_STATUS_INCONCLUSIVE;
    uwb_verdict_summary(&v, NULL, summary, sizeof summary);
    TEST_ASSERT_NULL_MESSAGE(strstr(summary, "95 %"), summary);
    TEST_ASSERT_EQUAL_INT(uwb_caption_height(&v, NULL, 960, 2) + 2 * line_h + numbers,
                          uwb_caption_height(&v, &prov, 960, 2));
}

/* A height change the verdict withheld is no number in any caption: the
 * comparison image once said "height change -0.42 mm" where the verdict
 * had withheld it (issue 44). */
static void test_a_withheld_height_change_shows_no_number(void)
{
    struct uwb_verdict v = make_verdict(); /* +20.00 mm, sigma 0.40 mm */
    v.height_change_m = -0.00042;
    snprintf(v.height_change_withheld, sizeof v.height_change_withheld,
             "height change uncertainty over its limit");
    char line[512], summary[2048];
    uwb_describe_displacement(&v, line, sizeof line);
    TEST_ASSERT_NULL_MESSAGE(strstr(line, "0.42"), line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "height change withheld"), line);
    uwb_verdict_summary(&v, NULL, summary, sizeof summary);
    TEST_ASSERT_NULL_MESSAGE(strstr(summary, "0.42"), summary);
}

/* Nothing in a caption is cut: a source line wider than the image wraps
 * onto a second line, so its end (the SNR, the version) is drawn; a
 * different SNR at the end of a long line changes the caption. */
static void test_a_long_source_line_wraps_rather_than_being_cut(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct uwb_verdict v = make_verdict();
    v.current.snr_db = 48.9;
    struct uwb_provenance prov = {.asset = "substation North T1 phase B", .stack = 64, .eps_r = 3.2};
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    o.provenance = &prov;
    int line = UWB_FONT_LINE_HEIGHT * o.font_scale + 3;
    TEST_ASSERT_EQUAL_INT_MESSAGE(uwb_caption_height(&v, NULL, o.width, o.font_scale) + line,
                                  uwb_caption_height(&v, &prov, o.width, o.font_scale),
                                  "the long source line takes two caption lines");
    struct png_rgb a = render_migrated("snr-a.png", &img, &v, &o);
    v.current.snr_db = 12.3;
    struct png_rgb b = render_migrated("snr-b.png", &img, &v, &o);
    int caption_h = uwb_caption_height(&v, &prov, o.width, o.font_scale), differ = 0;
    for (int y = 0; y < caption_h; y++)
        for (int x = 0; x < a.w; x++)
            differ += !same(at(&a, x, y), at(&b, x, y));
    TEST_ASSERT_TRUE_MESSAGE(differ > 20, "the SNR at the end of the source line is drawn");
    free(a.px);
    free(b.px);
    uwb_image_free(&img);
}

/* The meter has its numbers: under it, the watch and alarm limits (mm, in
 * their zones' colours) at their places on its scale, and the measured
 * displacement under its mark. */
static void test_the_meter_labels_its_limits_and_the_figure(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct meter_page page;
    meter_page_init(&page);
    struct png_rgb png = render_migrated("meter-labels.png", &img, &page.v, &page.o);
    int top = page.m.y + page.m.h + 4, bottom = top + UWB_FONT_CAP_HEIGHT * page.o.font_scale + 2;
    const struct uwb_rgb ink = {25, 25, 25};
    struct {
        double at_m;
        struct uwb_rgb colour;
        const char *what;
    } want[] = {
        {page.th.alarm_m, uwb_status_colour(UWB_STATUS_ALARM), "+alarm limit labelled"},
        {-page.th.alarm_m, uwb_status_colour(UWB_STATUS_ALARM), "-alarm limit labelled"},
        {page.v.axial_displacement_m, ink, "the figure labelled"},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        int col = uwb_meter_col(&page.m, want[i].at_m), n = 0;
        for (int y = top; y <= bottom; y++)
            for (int x = col - 40; x <= col + 40; x++)
                if (x >= page.m.x - 20 && x < png.w)
                    n += same(at(&png, x, y), want[i].colour);
        TEST_ASSERT_TRUE_MESSAGE(n > 10, want[i].what);
    }
    free(png.px);
    uwb_image_free(&img);
}

/* Issue 48, finding 7: the limits meter's numbers carry their signs
 * ("-5 -2 0 +2 +5", not "5 2 0 2 5") and stand two glyphs apart at the
 * least (crowded, "2", "0" and "2" read "202"); on a radial alarm (axial
 * figure withheld) the caption shows the radial limits and a meter of
 * the radial change as well, and the Description names them. */
static int meter_label_crowding(const struct png_rgb *png, const struct uwb_meter *m, int scale)
{
    const struct uwb_rgb white = {255, 255, 255};
    int top = m->y + m->h + 5, crowded = 0, last_ink = -1;
    for (int x = 0; x < png->w; x++) {
        int ink = 0;
        for (int y = top; y < top + UWB_FONT_CAP_HEIGHT * scale; y++)
            ink |= !same(at(png, x, y), white);
        if (!ink)
            continue;
        int gap = x - last_ink - 1;
        if (last_ink >= 0 && gap > 3 * scale && gap < 2 * UWB_FONT_ADVANCE * scale)
            crowded++;
        last_ink = x;
    }
    return crowded;
}

static void test_the_meter_signs_its_limits_and_shows_the_radial_ones(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI);
    struct meter_page page;
    meter_page_init(&page);
    int s = page.o.font_scale;
    page.v.axial_displacement_m = 0.0005;
    TEST_ASSERT_TRUE(uwb_caption_meter(&page.v, &page.prov, page.o.width, s, &page.m));
    struct png_rgb png = render_migrated("meter-signs.png", &img, &page.v, &page.o);
    const unsigned char *row = png.px + (size_t)(page.m.y + page.m.h) * (size_t)png.w * 3;
    int rows = uwb_meter_labels_height(s) + 4;
    const struct uwb_rgb alarm = uwb_status_colour(UWB_STATUS_ALARM),
                         watch = uwb_status_colour(UWB_STATUS_WATCH);
    TEST_ASSERT_EQUAL_INT(1, png_text_find(row, png.w, rows, "-5", s, alarm, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(1, png_text_find(row, png.w, rows, "+5", s, alarm, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(1, png_text_find(row, png.w, rows, "-2", s, watch, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(1, png_text_find(row, png.w, rows, "+2", s, watch, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(0, meter_label_crowding(&png, &page.m, s));
    free(png.px);

    /* A narrow page: labels are left out rather than crowded. */
    page.o.width = 640;
    TEST_ASSERT_TRUE(uwb_caption_meter(&page.v, &page.prov, page.o.width, s, &page.m));
    png = render_migrated("meter-narrow.png", &img, &page.v, &page.o);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, meter_label_crowding(&png, &page.m, s), "labels closer than two glyphs");
    free(png.px);

    /* A radial alarm, the axial figure withheld. */
    uwb_render_options_default(&page.o);
    page.o.provenance = &page.prov;
    struct uwb_thresholds radial_th = {.watch_m = 0.0015, .alarm_m = 0.004};
    page.prov.radial_thresholds = &radial_th;
    page.v.status = UWB_STATUS_ALARM;
    page.v.axial_withheld = 1;
    snprintf(page.v.reason, sizeof page.v.reason, "axial figure withheld: the face changed shape");
    page.v.radial.measured = 1;
    page.v.radial.status = UWB_STATUS_ALARM;
    page.v.radial.max_change_m = 0.0062;
    page.v.radial.uncertainty_m = 0.0004;
    page.v.radial.at_m = 0.2;
    char path[512];
    path_in_dir(path, sizeof path, "meter-radial.png");
    png = render_migrated("meter-radial.png", &img, &page.v, &page.o);
    TEST_ASSERT_TRUE_MESSAGE(png_text_find(png.px, png.w, png.h, "-4", s, alarm, NULL, NULL) == 1,
                             "the radial alarm limit, below zero");
    TEST_ASSERT_TRUE_MESSAGE(png_text_find(png.px, png.w, png.h, "+4", s, alarm, NULL, NULL) == 1,
                             "the radial alarm limit, above zero");
    TEST_ASSERT_TRUE_MESSAGE(
        png_text_find(png.px, png.w, png.h, "+6.20", s, (struct uwb_rgb){25, 25, 25}, NULL, NULL) == 1,
        "the radial change on its meter");
    struct png_texts t;
    read_texts(path, &t);
    const char *d = text_of(&t, "Description", NULL);
    TEST_ASSERT_NOT_NULL(d);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "radial thresholds watch 1.50 mm, alarm 4.00 mm"), d);
    free(png.px);
    uwb_image_free(&img);
}

/* The B-scan's time axis fits the echoes: a 20 ns record whose echoes
 * all lie at 4-7 ns is drawn over about those times, not with 80 % of the
 * plot empty; the ranges the analysis searched are marked at their echo
 * times (a render with the window differs there from one without). */
static void test_bscan_axis_fits_the_echoes_and_marks_the_window(void)
{
    struct uwb_scan scan;
    char err[256];
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&scan, 21, 1000, err, sizeof err));
    scan.sample_interval_s = 20e-12; /* 0 .. 20 ns */
    scan.t0_s = 0.0;
    scan.tx_m[0] = -0.02;
    scan.rx_m[0] = 0.02;
    for (int k = 0; k < 21; k++) {
        scan.antenna_y_m[k] = 0.03 * k;
        int first = 200 + 7 * k; /* 4.0 .. 6.8 ns */
        for (int s = first; s <= first + 10; s++)
            scan.data[k * 1000 + s] = 100.0f;
    }
    struct uwb_verdict v = make_verdict();
    v.current.face_z_m = v.baseline.face_z_m = 0.75; /* echo at 5 ns */
    struct uwb_provenance prov = {.has_search_window = 1, .search_z_lo_m = 0.62, .search_z_hi_m = 0.95};
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    o.provenance = &prov;
    char path[512], bare_path[512];
    path_in_dir(path, sizeof path, "bscan-fit.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_bscan_png_opt(path, &scan, &v, &o, err, sizeof err), err);
    struct uwb_provenance bare = prov;
    bare.has_search_window = 0;
    o.provenance = &bare;
    path_in_dir(bare_path, sizeof bare_path, "bscan-bare.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_bscan_png_opt(bare_path, &scan, &v, &o, err, sizeof err),
                                  err);
    o.provenance = &prov;
    struct png_rgb png = read_png(path), plain = read_png(bare_path);
    struct uwb_plot p;
    int bar_x, bar_w;
    uwb_render_bscan_layout(&scan, &v, &o, &p, &bar_x, &bar_w);
    int echo_cols = 0;
    for (int x = p.x; x < p.x + p.w; x++) {
        int red = 0;
        for (int y = p.y; y < p.y + p.h && !red; y++) {
            struct uwb_rgb c = at(&png, x, y);
            red = c.r > c.b + 60;
        }
        echo_cols += red;
    }
    char msg[96];
    snprintf(msg, sizeof msg, "echoes fill %d of %d columns", echo_cols, p.w);
    TEST_ASSERT_TRUE_MESSAGE(echo_cols * 2 > p.w, msg);
    /* The window's ends, at the echo times of its ranges: drawn there. */
    for (int end = 0; end < 2; end++) {
        double t = uwb_face_echo_time(&scan, end ? prov.search_z_hi_m : prov.search_z_lo_m);
        int col = col_of(&p, t), differ = 0;
        TEST_ASSERT_TRUE_MESSAGE(col >= p.x && col < p.x + p.w, "the window lies on the plot");
        for (int y = p.y; y < p.y + p.h; y++)
            differ += !same(at(&png, col, y), at(&plain, col, y));
        TEST_ASSERT_TRUE_MESSAGE(differ > p.h / 4,
                                 end ? "the window's far end is marked" : "its near end is marked");
    }
    free(png.px);
    free(plain.px);
    uwb_scan_free(&scan);
}

/* A return as strong as the winding's face but away from it (a clamping
 * plate above the winding) is labelled as not the winding; a weak one is
 * not. The label is white on the image, where the colour map has none. */
static int white_near(const struct png_rgb *png, const struct uwb_plot *p, int row)
{
    int n = 0;
    for (int y = row - 30; y <= row + 30; y++)
        for (int x = p->x; x < p->x + p->w; x++)
            if (y >= p->y && y < p->y + p->h)
                n += same(at(png, x, y), (struct uwb_rgb){255, 255, 255});
    return n;
}

static void test_a_strong_return_off_the_winding_is_labelled_not_the_winding(void)
{
    struct uwb_verdict v = make_verdict();
    struct uwb_plot p;
    int bx, bw;
    float strength[2] = {1.5f, 0.1f}; /* brighter than the face; 20 dB under it */
    for (int i = 0; i < 2; i++) {
        struct uwb_image img = make_image(FACE_LO, FACE_HI);
        for (int iy = 0; iy < img.ny; iy++)
            for (int iz = 0; iz < img.nz; iz++) {
                double y = img.y0_m + iy * img.dy_m, z = img.z0_m + iz * img.dz_m;
                if (hypot(y - 0.45, z - 0.52) <= 0.008)
                    img.pix[iy * img.nz + iz] = strength[i];
            }
        uwb_render_migrated_layout(&img, &v, NULL, &p, &bx, &bw);
        struct png_rgb png = render_migrated(i ? "weak-return.png" : "strong-return.png", &img, &v, NULL);
        int n = white_near(&png, &p, row_of(&p, 0.45));
        if (i == 0) {
            TEST_ASSERT_TRUE_MESSAGE(n > 30, "the strong return is labelled");
        } else {
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, n, "a weak one is not");
        }
        free(png.px);
        uwb_image_free(&img);
    }
}

/* Issue 48, finding 7: the migrated image's brightest feature that is
 * not the winding, a band across the whole height (in the demo's tank
 * the core leg's front face at 520 mm), is labelled with its range and
 * as not the winding; a point return or a clean image gets no such
 * label. */
static void test_a_full_height_reflector_is_labelled(void)
{
    struct uwb_verdict v = make_verdict();
    for (int band = 1; band >= 0; band--) {
        struct uwb_image img = make_image(FACE_LO, FACE_HI);
        for (int iy = 0; iy < img.ny; iy++)
            for (int iz = 0; iz < img.nz; iz++) {
                double z = img.z0_m + iz * img.dz_m;
                if (band && fabs(z - 0.52) <= 0.006)
                    img.pix[iy * img.nz + iz] = 0.5f; /* 6 dB under the face, at every height */
            }
        double z;
        TEST_ASSERT_EQUAL_INT(band, uwb_find_reflector_band(&img, &v.current, &z));
        if (band)
            TEST_ASSERT_DOUBLE_WITHIN(0.007, 0.52, z);
        struct png_rgb png = render_migrated("band.png", &img, &v, NULL);
        TEST_ASSERT_EQUAL_INT_MESSAGE(band, png_text_present(png.px, png.w, png.h, "reflector at 520 mm"),
                                      "the band's label");
        TEST_ASSERT_EQUAL_INT(band, png_text_present(png.px, png.w, png.h, "not the winding"));
        free(png.px);
        uwb_image_free(&img);
    }
}

/* The migrated image's height axis reaches past the antenna's travel:
 * rows beyond it are hatched (and say so), rows within are untouched. */
static void test_migrated_image_marks_what_lies_beyond_the_antenna_travel(void)
{
    struct uwb_image img = make_image(FACE_LO, FACE_HI); /* 0 .. 600 mm */
    struct uwb_verdict v = make_verdict();
    struct uwb_provenance prov = {
        .scan_name = "t", .has_travel = 1, .travel_lo_m = 0.05, .travel_hi_m = 0.50};
    struct uwb_render_options o;
    uwb_render_options_default(&o);
    o.provenance = &prov;
    struct png_rgb with = render_migrated("travel.png", &img, &v, &o);
    prov.has_travel = 0;
    struct png_rgb without = render_migrated("no-travel.png", &img, &v, &o);
    struct uwb_plot p;
    int bx, bw;
    uwb_render_migrated_layout(&img, &v, &o, &p, &bx, &bw);
    const struct uwb_rgb hatch = {215, 215, 215};
    int beyond = 0, within_changed = 0, hatch_without = 0;
    for (int row = row_of(&p, 0.59); row <= row_of(&p, 0.52); row++)
        for (int x = p.x; x < p.x + p.w; x++) {
            beyond += same(at(&with, x, row), hatch);
            hatch_without += same(at(&without, x, row), hatch);
        }
    for (int row = row_of(&p, 0.45); row <= row_of(&p, 0.30); row++)
        for (int x = p.x; x < p.x + p.w; x++)
            within_changed += !same(at(&with, x, row), at(&without, x, row));
    TEST_ASSERT_TRUE_MESSAGE(beyond > (row_of(&p, 0.52) - row_of(&p, 0.59)) * p.w / 10, "hatched beyond");
    TEST_ASSERT_EQUAL_INT(0, hatch_without);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, within_changed, "nothing drawn within the travel");
    int below = 0; /* and below the lowest position (0 .. 50 mm) */
    for (int x = p.x; x < p.x + p.w; x++)
        below += same(at(&with, x, row_of(&p, 0.02)), hatch);
    TEST_ASSERT_TRUE(below > p.w / 10);
    free(with.px);
    free(without.px);
    uwb_image_free(&img);
}

/* The B-scan has a range axis along the top: a face at range z echoes at
 * uwb_face_echo_time(z), and its tick sits in that time's column. */
static void test_bscan_has_a_range_axis(void)
{
    struct uwb_scan scan;
    fixture_load_scan("tests/fixtures/fdtd2d-paper-intact.uwbscan", &scan);
    for (double z = 0.2; z < 1.0; z += 0.1)
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, z, uwb_face_range_at_time(&scan, uwb_face_echo_time(&scan, z)));
    TEST_ASSERT_TRUE(isnan(uwb_face_range_at_time(&scan, -1e-9)));
    char path[512], err[256];
    path_in_dir(path, sizeof path, "bscan-range.png");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_render_bscan_png(path, &scan, NULL, err, sizeof err), err);
    struct png_rgb png = read_png(path);
    struct uwb_plot p;
    int bx, bw;
    uwb_render_bscan_layout(&scan, NULL, NULL, &p, &bx, &bw);
    const struct uwb_rgb tick = {120, 120, 120}, white = {255, 255, 255};
    int col = col_of(&p, uwb_face_echo_time(&scan, 0.400));
    TEST_ASSERT_TRUE_MESSAGE(same(at(&png, col, p.y - 4), tick), "a tick at 400 mm of range above the plot");
    TEST_ASSERT_TRUE(same(at(&png, col + 3, p.y - 4), white));
    int lettering = 0; /* its label above it */
    for (int y = p.y - 30; y < p.y - 8; y++)
        for (int x = col - 20; x <= col + 20; x++)
            lettering += !same(at(&png, x, y), white);
    TEST_ASSERT_TRUE(lettering > 20);
    free(png.px);
    uwb_scan_free(&scan);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_font_table_is_complete_and_glyphs_are_distinct);
    RUN_TEST(test_text_width_matches_drawn_extent_and_scales);
    RUN_TEST(test_perceptual_map_lightness_rises_monotonically);
    RUN_TEST(test_diverging_map_is_symmetric_in_lightness);
    RUN_TEST(test_nice_ticks_and_labels);
    RUN_TEST(test_dashed_line_has_gaps_and_solid_line_has_none);
    RUN_TEST(test_filled_rectangle_covers_exactly_its_clipped_pixels);
    RUN_TEST(test_migrated_png_edges_sit_on_their_heights);
    RUN_TEST(test_migrated_png_puts_the_face_where_the_axis_says);
    RUN_TEST(test_migrated_colorbar_runs_from_peak_colour_to_floor_colour);
    RUN_TEST(test_migrated_axes_have_tick_labels_on_both_axes);
    RUN_TEST(test_caption_text_names_the_scan);
    RUN_TEST(test_long_reason_wraps_and_pushes_the_plot_down);
    RUN_TEST(test_png_description_carries_the_verdict);
    RUN_TEST(test_floor_option_changes_the_scale);
    RUN_TEST(test_same_input_gives_identical_bytes);
    RUN_TEST(test_bscan_traces_are_at_their_antenna_heights);
    RUN_TEST(test_comparison_shows_both_scans_and_the_shift);
    RUN_TEST(test_comparison_without_baseline_draws_this_scan_only);
    RUN_TEST(test_comparison_draws_the_analysis_profile_not_the_image);
    RUN_TEST(test_unwritable_path_fails_naming_it_and_leaves_nothing);
    RUN_TEST(test_libpng_failure_keeps_the_old_file_and_no_temporary);
    RUN_TEST(test_bad_inputs_are_refused_with_the_path);
    RUN_TEST(test_replayed_images_carry_the_file_stem_and_provenance);
    RUN_TEST(test_caption_names_an_id_less_scan_by_its_given_name);
    RUN_TEST(test_comparison_without_a_measured_displacement_draws_no_arrow);
    RUN_TEST(test_comparison_words_are_whole);
    RUN_TEST(test_radial_words_stay_within_the_noise);
    RUN_TEST(test_the_meter_signs_its_limits_and_shows_the_radial_ones);
    RUN_TEST(test_migrated_image_has_equal_scales);
    RUN_TEST(test_comparison_difference_panel_shows_the_move);
    RUN_TEST(test_images_show_the_watch_and_alarm_zones);
    RUN_TEST(test_the_plus_minus_says_what_it_is);
    RUN_TEST(test_a_withheld_height_change_shows_no_number);
    RUN_TEST(test_migrated_image_marks_what_lies_beyond_the_antenna_travel);
    RUN_TEST(test_bscan_has_a_range_axis);
    RUN_TEST(test_a_long_source_line_wraps_rather_than_being_cut);
    RUN_TEST(test_the_meter_labels_its_limits_and_the_figure);
    RUN_TEST(test_bscan_axis_fits_the_echoes_and_marks_the_window);
    RUN_TEST(test_a_strong_return_off_the_winding_is_labelled_not_the_winding);
    RUN_TEST(test_a_full_height_reflector_is_labelled);
    return UNITY_END();
}
