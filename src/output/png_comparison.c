/* Baseline against this scan, side by side so the shift shows at a glance:
 *   [baseline image] [this scan's image] [this - baseline] [radial] [face profiles]
 * The two image panels are cropped to the face, share the height axis and
 * the dB scale (each re its own peak: the scans may differ in gain); this
 * scan's panel also carries the baseline's edges dashed, so the gap between
 * solid and dashed lines IS the displacement. The profile panel overlays
 * both scans' face profiles, each normalised to its peak: the very curves
 * the analysis read the edges from (tapered aperture, side reflector taken
 * out), not a profile of the display image; with the half-peak line the
 * edges are read at, and an arrow from the baseline centre to this
 * scan's centre labelled with the displacement.
 * The difference panel subtracts the baseline's image from this scan's,
 * each re its own peak, on a linear diverging scale (red: stronger now,
 * blue: stronger in the baseline, white: unchanged): a moved winding shows
 * as a red/blue pair at its ends.
 * The radial panel (png_radial.c) draws the face's range along the height
 * in both scans, aligned by the axial shift, with the verdict's radial
 * change shaded and labelled.
 * Without a baseline the left panel says so and only this scan is drawn:
 * the archive keeps the same set of files for every scan. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CROP_HALF_WIDTH_M 0.060 /* face region shown: +/- 60 mm of range */
#define PANEL_GAP 20

static const struct uwb_rgb page = {255, 255, 255};
static const struct uwb_rgb ink = {25, 25, 25};
static const struct uwb_rgb no_data = {128, 128, 128};
static const struct uwb_rgb profile_background = {40, 40, 48};
static const struct uwb_rgb profile_grid = {95, 95, 105};
static const struct uwb_rgb baseline_ink = {150, 20, 110};
const struct uwb_rgb UWB_RGB_NOT_MEASURED = {150, 150, 150};

struct comparison_layout {
    struct uwb_plot base, cur, diff, rad, prof;
    int bar_x, bar_w;
};

static void image_y_range(const struct uwb_image *img, double *lo, double *hi)
{
    double a = img->y0_m, b = img->y0_m + (img->ny - 1) * img->dy_m;
    *lo = fmin(*lo, a);
    *hi = fmax(*hi, b);
}

static void layout(int width, int height, int s, int caption_height, struct comparison_layout *L)
{
    int top = caption_height + 16 + UWB_FONT_LINE_HEIGHT * s; /* room for panel titles */
    int left = 12 + 9 * s + 10 + (5 * UWB_FONT_ADVANCE - 1) * s + 12;
    int right_labels = 12 + (5 * UWB_FONT_ADVANCE - 1) * s; /* profile's y labels */
    L->bar_w = 10 + 6 * s;
    int right = 22 + L->bar_w + 12 + (3 * UWB_FONT_ADVANCE - 1) * s + 10;
    int bottom = 12 + UWB_FONT_CAP_HEIGHT * s + 10 + 9 * s + 14 + UWB_FONT_LINE_HEIGHT * s + 10;
    int avail = width - left - right - right_labels - 4 * PANEL_GAP;
    int panel = avail * 20 / 100, radial = avail * 16 / 100;
    if (panel < 16)
        panel = 16;
    if (radial < 16)
        radial = 16;
    struct uwb_plot p = {0};
    p.y = top;
    p.h = height - top - bottom;
    if (p.h < 16)
        p.h = 16;
    L->base = p;
    L->base.x = left;
    L->base.w = panel;
    L->cur = p;
    L->cur.x = left + panel + PANEL_GAP;
    L->cur.w = panel;
    L->diff = p;
    L->diff.x = L->cur.x + panel + PANEL_GAP;
    L->diff.w = panel;
    L->rad = p;
    L->rad.x = L->diff.x + panel + PANEL_GAP;
    L->rad.w = radial;
    L->prof = p;
    L->prof.x = L->rad.x + radial + PANEL_GAP;
    L->prof.w = avail - 3 * panel - radial > 16 ? avail - 3 * panel - radial : 16;
    L->bar_x = L->prof.x + L->prof.w + right_labels + 22;
}

static void panel_title(struct uwb_canvas *c, const struct uwb_plot *p, const char *title, int s,
                        struct uwb_rgb colour)
{
    int w = uwb_text_width(title, s);
    uwb_draw_text(c, p->x + (p->w - w) / 2, p->y - 10 - UWB_FONT_CAP_HEIGHT * s, title, s, colour);
}

/* Words wrapped to lines no wider than max_w (uwb_wrap_line_length):
 * a panel never cuts a word off at its edge. Returns the line count. */
#define WORD_LINES 8
static int wrap_words(const char *text, int max_w, int s, char lines[WORD_LINES][160])
{
    int n = 0;
    while (*text == ' ')
        text++;
    while (*text && n < WORD_LINES) {
        size_t fit = uwb_wrap_line_length(text, max_w, s);
        snprintf(lines[n++], 160, "%.*s", (int)fit, text);
        text += fit;
        while (*text == ' ')
            text++;
    }
    return n;
}

/* Text centred in an empty panel, wrapped to its width. */
static void panel_words(struct uwb_canvas *c, const struct uwb_plot *p, const char *text, int s,
                        struct uwb_rgb colour)
{
    char lines[WORD_LINES][160];
    int n = wrap_words(text, p->w - 8, s, lines), step = UWB_FONT_LINE_HEIGHT * s;
    int y = p->y + p->h / 2 - n * step / 2;
    for (int i = 0; i < n; i++) {
        int w = uwb_text_width(lines[i], s);
        uwb_draw_text(c, p->x + (p->w - w) / 2, y + i * step, lines[i], s, colour);
    }
}

int uwb_comparison_profile_polyline(const struct uwb_plot *p, const struct uwb_face_profile *profile, int *xs,
                                    int *ys)
{
    if (!profile || !profile->value || profile->n < 2)
        return 0;
    double peak = 0.0;
    for (int i = 0; i < profile->n; i++)
        if (isfinite(profile->value[i]) && profile->value[i] > peak)
            peak = profile->value[i];
    if (!(peak > 0.0))
        return 0;
    int n = 0;
    for (int i = 0; i < profile->n; i++) {
        double y = profile->y0_m + i * profile->dy_m, v = profile->value[i];
        if (y < p->y_min || y > p->y_max)
            continue;
        xs[n] = uwb_plot_col(p, isfinite(v) && v > 0.0 ? v / peak : 0.0);
        ys[n] = uwb_plot_row(p, y);
        n++;
    }
    return n;
}

/* The face profile the edges were read from, as a curve in the profile panel. */
static void draw_profile(struct uwb_canvas *c, const struct uwb_plot *p,
                         const struct uwb_face_profile *profile, enum uwb_edge_kind kind)
{
    if (!profile || profile->n < 2)
        return;
    int *xs = malloc(sizeof *xs * (size_t)profile->n), *ys = malloc(sizeof *ys * (size_t)profile->n);
    int n = xs && ys ? uwb_comparison_profile_polyline(p, profile, xs, ys) : 0;
    if (kind == UWB_EDGE_BASELINE)
        uwb_canvas_polyline(c, xs, ys, n, UWB_RGB_BASELINE_EDGE, 2, 7, 5);
    else
        uwb_canvas_polyline(c, xs, ys, n, UWB_RGB_CURRENT_EDGE, 2, 0, 0);
    free(xs);
    free(ys);
}

/* Arrow from the baseline centre to this scan's centre, with the figure. */
static void draw_shift_arrow(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_verdict *v,
                             int s)
{
    int col = p->x + p->w * 82 / 100;
    int r0 = uwb_plot_row(p, v->baseline.center_m), r1 = uwb_plot_row(p, v->current.center_m);
    if (r0 < p->y || r0 >= p->y + p->h || r1 < p->y || r1 >= p->y + p->h)
        return;
    struct uwb_rgb arrow = UWB_RGB_CURRENT_EDGE;
    if (abs(r1 - r0) >= 8) {
        uwb_canvas_line(c, col, r0, col, r1, arrow, 2, 0, 0);
        int dir = r1 < r0 ? 1 : -1; /* head points toward r1 */
        for (int i = 0; i < 6; i++)
            uwb_canvas_fill_rect(c, col - i, r1 + dir * i, 2 * i + 1, 1, arrow);
    }
    char text[64];
    snprintf(text, sizeof text, "\u0394 %+.1f mm", v->axial_displacement_m * 1000.0);
    int w = uwb_text_width(text, s), h = UWB_FONT_CAP_HEIGHT * s;
    int tx = col - w - 8, ty = (r0 + r1) / 2 - h / 2;
    if (tx < p->x + 2)
        tx = p->x + 2;
    uwb_canvas_fill_rect(c, tx - 2, ty - 2, w + 4, h + 4, UWB_RGB_HALO);
    uwb_draw_text(c, tx, ty, text, s, UWB_RGB_CURRENT_EDGE);
}

/* An image's value re its peak at (y, z), nearest sample; 0 outside. */
static double value_re_peak(const struct uwb_image *img, double peak, double y, double z)
{
    long iy = lround((y - img->y0_m) / img->dy_m), iz = lround((z - img->z0_m) / img->dz_m);
    if (iy < 0 || iz < 0 || iy >= img->ny || iz >= img->nz)
        return 0.0;
    float v = img->pix[iy * img->nz + iz];
    return isfinite(v) && v > 0.0f ? v / peak : 0.0;
}

/* current/its peak - baseline/its peak on the diverging map, full colour
 * at the largest |difference| in the panel (returned; 0: none, all white).
 * The two images may lie on different grids: each is sampled where the
 * pixel is. */
double uwb_paint_difference(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *current,
                            const struct uwb_image *baseline)
{
    double pc = uwb_image_peak(current), pb = uwb_image_peak(baseline);
    if (!(pc > 0.0) || !(pb > 0.0) || p->w < 1 || p->h < 1) {
        uwb_canvas_fill_rect(c, p->x, p->y, p->w, p->h, no_data);
        return 0.0;
    }
    double dz = p->w > 1 ? (p->x_max - p->x_min) / (p->w - 1) : 0.0;
    double dy = p->h > 1 ? (p->y_max - p->y_min) / (p->h - 1) : 0.0;
    float *d = malloc(sizeof *d * (size_t)p->w * (size_t)p->h);
    if (!d) {
        uwb_canvas_fill_rect(c, p->x, p->y, p->w, p->h, no_data);
        return 0.0;
    }
    double largest = 0.0;
    for (int row = 0; row < p->h; row++)
        for (int col = 0; col < p->w; col++) {
            double y = p->y_max - row * dy, z = p->x_min + col * dz;
            double v = value_re_peak(current, pc, y, z) - value_re_peak(baseline, pb, y, z);
            d[(size_t)row * (size_t)p->w + (size_t)col] = (float)v;
            largest = fmax(largest, fabs(v));
        }
    for (int row = 0; row < p->h; row++)
        for (int col = 0; col < p->w; col++) {
            double v = largest > 0.0 ? d[(size_t)row * (size_t)p->w + (size_t)col] / largest : 0.0;
            uwb_canvas_put(c, p->x + col, p->y + row, uwb_colormap_diverging(0.5 + 0.5 * v));
        }
    free(d);
    return largest;
}

/* A verdict that measured no displacement (inconclusive, error) against a
 * baseline: no arrow and no figure, but a grey hatched band between the two
 * centres (where both were found) and a grey box saying "not measured" and
 * why, so nobody reads the gap between the curves as a result. */
static void draw_not_measured(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_verdict *v,
                              int s)
{
    if (v->current.found && v->baseline.found) {
        int r0 = uwb_plot_row(p, v->baseline.center_m), r1 = uwb_plot_row(p, v->current.center_m);
        int top = r0 < r1 ? r0 : r1, bottom = r0 < r1 ? r1 : r0;
        if (top < p->y)
            top = p->y;
        if (bottom > p->y + p->h - 1)
            bottom = p->y + p->h - 1;
        for (int y = top; y <= bottom; y++)
            for (int x = p->x + (y % 6); x < p->x + p->w; x += 6)
                uwb_canvas_put(c, x, y, UWB_RGB_NOT_MEASURED);
    }
    /* "not measured:" and the whole reason, wrapped to the panel (it was
     * cut there: "not measured / radial cha"); at a smaller scale when the
     * panel is narrow. */
    const char *head = "not measured:";
    int ks = s > 1 ? s - 1 : 1;
    char lines[WORD_LINES][160];
    int n = wrap_words(v->reason[0] ? v->reason : uwb_status_name(v->status), p->w - 8 * ks, ks, lines);
    int line = UWB_FONT_LINE_HEIGHT * ks, widest = uwb_text_width(head, ks);
    for (int i = 0; i < n; i++)
        if (uwb_text_width(lines[i], ks) > widest)
            widest = uwb_text_width(lines[i], ks);
    int bw = widest + 6 * ks, bh = (n + 1) * line + 4 * ks;
    int bx = p->x + (p->w - bw) / 2, by = p->y + p->h / 2 - bh / 2;
    uwb_canvas_fill_rect(c, bx, by, bw, bh, UWB_RGB_NOT_MEASURED);
    uwb_draw_text(c, bx + (bw - uwb_text_width(head, ks)) / 2, by + 2 * ks, head, ks, page);
    for (int i = 0; i < n; i++)
        uwb_draw_text(c, bx + (bw - uwb_text_width(lines[i], ks)) / 2, by + 2 * ks + (i + 1) * line, lines[i],
                      ks, page);
}

/* Every panel's place and data ranges for this pair and verdict. */
static void full_layout(const struct uwb_analysis *current_scan, const struct uwb_analysis *baseline_scan,
                        const struct uwb_verdict *v, const struct uwb_render_options *opt,
                        struct comparison_layout *L)
{
    const struct uwb_image *current = &current_scan->intensity;
    const struct uwb_image *baseline = baseline_scan ? &baseline_scan->intensity : NULL;
    struct uwb_render_options o;
    uwb_render_options_sane(opt, &o);
    layout(o.width, o.height, o.font_scale, uwb_caption_height(v, o.provenance, o.width, o.font_scale), L);
    const struct uwb_edges *ec = v && v->current.found ? &v->current : NULL;
    const struct uwb_edges *eb = v && v->has_baseline && v->baseline.found ? &v->baseline : NULL;
    /* Crop centre: the faces found, else the brightest range. */
    double zc;
    if (ec && eb)
        zc = 0.5 * (ec->face_z_m + eb->face_z_m);
    else if (ec)
        zc = ec->face_z_m;
    else if (eb)
        zc = eb->face_z_m;
    else
        zc = uwb_image_peak_z(current);
    double ylo = INFINITY, yhi = -INFINITY;
    image_y_range(current, &ylo, &yhi);
    if (baseline)
        image_y_range(baseline, &ylo, &yhi);
    struct uwb_plot *panels[3] = {&L->base, &L->cur, &L->diff};
    for (int i = 0; i < 3; i++) {
        panels[i]->x_min = zc - CROP_HALF_WIDTH_M;
        panels[i]->x_max = zc + CROP_HALF_WIDTH_M;
        panels[i]->y_min = ylo;
        panels[i]->y_max = yhi;
    }
    L->prof.x_min = 0.0;
    L->prof.x_max = 1.05; /* a little room right of the peak */
    L->prof.y_min = ylo;
    L->prof.y_max = yhi;
    L->rad.y_min = ylo;
    L->rad.y_max = yhi;
    uwb_radial_panel_range(current_scan, baseline_scan, v, &L->rad);
}

void uwb_render_comparison_layout(const struct uwb_analysis *current_scan,
                                  const struct uwb_analysis *baseline_scan, const struct uwb_verdict *v,
                                  const struct uwb_render_options *opt, struct uwb_plot *base_panel,
                                  struct uwb_plot *current_panel, struct uwb_plot *difference_panel,
                                  struct uwb_plot *profile_panel, int *colorbar_x, int *colorbar_w)
{
    struct comparison_layout L;
    full_layout(current_scan, baseline_scan, v, opt, &L);
    *base_panel = L.base;
    *current_panel = L.cur;
    *difference_panel = L.diff;
    *profile_panel = L.prof;
    *colorbar_x = L.bar_x;
    *colorbar_w = L.bar_w;
}

void uwb_render_comparison_radial_layout(const struct uwb_analysis *current,
                                         const struct uwb_analysis *baseline, const struct uwb_verdict *v,
                                         const struct uwb_render_options *opt, struct uwb_plot *radial_panel)
{
    struct comparison_layout L;
    full_layout(current, baseline, v, opt, &L);
    *radial_panel = L.rad;
}

int uwb_render_comparison_png(const char *path, const struct uwb_analysis *current,
                              const struct uwb_analysis *baseline, const struct uwb_verdict *v, char *err,
                              size_t errlen)
{
    return uwb_render_comparison_png_opt(path, current, baseline, v, NULL, err, errlen);
}

int uwb_render_comparison_png_opt(const char *path, const struct uwb_analysis *current_scan,
                                  const struct uwb_analysis *baseline_scan, const struct uwb_verdict *v,
                                  const struct uwb_render_options *opt, char *err, size_t errlen)
{
    if (!current_scan) {
        snprintf(err, errlen, "%s: no analysis to draw", path ? path : "comparison image");
        return -1;
    }
    const struct uwb_image *current = &current_scan->intensity;
    const struct uwb_image *baseline = baseline_scan ? &baseline_scan->intensity : NULL;
    if (!path || !*path) {
        snprintf(err, errlen, "comparison image: no output path");
        return -1;
    }
    if (uwb_image_check(current, path, err, errlen) != 0)
        return -1;
    if (baseline && uwb_image_check(baseline, path, err, errlen) != 0)
        return -1;
    struct uwb_render_options o;
    uwb_render_options_sane(opt, &o);
    int s = o.font_scale;

    struct uwb_canvas c;
    if (uwb_canvas_init(&c, o.width, o.height, page, err, errlen) != 0)
        return -1;
    struct comparison_layout L;
    full_layout(current_scan, baseline_scan, v, &o, &L);
    const struct uwb_edges *ec = v && v->current.found ? &v->current : NULL;
    const struct uwb_edges *eb = v && v->has_baseline && v->baseline.found ? &v->baseline : NULL;

    uwb_draw_caption(&c, "uwbd comparison - baseline vs this scan", v, o.provenance, s);

    /* Without a baseline the empty panels say why: none yet, or this scan
     * is the baseline from now on (commissioning). */
    const char *no_baseline = o.provenance && o.provenance->became_baseline ? "new baseline" : "no baseline";
    /* Baseline panel. */
    if (baseline) {
        uwb_paint_image_db(&c, &L.base, baseline, uwb_image_peak(baseline), o.floor_db);
        uwb_mark_antenna_travel(&c, &L.base, o.provenance, 0);
        if (eb)
            uwb_draw_edges(&c, &L.base, eb, UWB_EDGE_BASELINE, L.base.x_min, L.base.x_max, eb->face_z_m, 0,
                           s);
    } else {
        uwb_canvas_fill_rect(&c, L.base.x, L.base.y, L.base.w, L.base.h, no_data);
        panel_words(&c, &L.base, no_baseline, s, page);
    }
    panel_title(&c, &L.base, "baseline", s, baseline_ink);

    /* This scan's panel: its edges solid, the baseline's dashed under them. */
    uwb_paint_image_db(&c, &L.cur, current, uwb_image_peak(current), o.floor_db);
    uwb_mark_antenna_travel(&c, &L.cur, o.provenance, 0);
    if (eb)
        uwb_draw_edges(&c, &L.cur, eb, UWB_EDGE_BASELINE, L.cur.x_min, L.cur.x_max, eb->face_z_m, 0, s);
    if (ec)
        uwb_draw_edges(&c, &L.cur, ec, UWB_EDGE_CURRENT, L.cur.x_min, L.cur.x_max, ec->face_z_m, 0, s);
    panel_title(&c, &L.cur, "this scan", s, ink);

    /* This scan minus the baseline. */
    if (baseline) {
        double largest = uwb_paint_difference(&c, &L.diff, current, baseline);
        uwb_mark_antenna_travel(&c, &L.diff, o.provenance, 0);
        int ks = s > 1 ? s - 1 : 1;
        char full[48], percent[32];
        snprintf(percent, sizeof percent, "%.0f%% of peak", 100.0 * largest);
        snprintf(full, sizeof full, "full colour: %s", percent);
        const char *key[4] = {"red: stronger now", "blue: weaker now", full, NULL};
        int n_key = 3;
        if (uwb_text_width(full, ks) > L.diff.w - 8) { /* a narrow panel: the last line in two */
            key[2] = "full colour:";
            key[3] = percent;
            n_key = 4;
        }
        for (int i = 0; i < n_key; i++) {
            int w = uwb_text_width(key[i], ks),
                ky = L.diff.y + L.diff.h - (n_key - i) * (UWB_FONT_LINE_HEIGHT * ks + 2) - 4;
            uwb_canvas_fill_rect(&c, L.diff.x + 3, ky - 2, w + 4, UWB_FONT_CAP_HEIGHT * ks + 4, page);
            uwb_draw_text(&c, L.diff.x + 5, ky, key[i], ks, ink);
        }
    } else {
        uwb_canvas_fill_rect(&c, L.diff.x, L.diff.y, L.diff.w, L.diff.h, no_data);
        panel_words(&c, &L.diff, no_baseline, s, page);
    }
    panel_title(&c, &L.diff, "now - base", s, ink);

    uwb_draw_radial_panel(&c, &L.rad, current_scan, baseline_scan, v, s);
    panel_title(&c, &L.rad, "radial", s, ink);

    /* Profiles. */
    uwb_canvas_fill_rect(&c, L.prof.x, L.prof.y, L.prof.w, L.prof.h, profile_background);
    int half_col = uwb_plot_col(&L.prof, 0.5);
    uwb_canvas_line(&c, half_col, L.prof.y, half_col, L.prof.y + L.prof.h - 1, profile_grid, 1, 2, 3);
    if (baseline_scan)
        draw_profile(&c, &L.prof, &baseline_scan->profile, UWB_EDGE_BASELINE);
    draw_profile(&c, &L.prof, &current_scan->profile, UWB_EDGE_CURRENT);
    if (eb)
        uwb_draw_edges(&c, &L.prof, eb, UWB_EDGE_BASELINE, 0.0, L.prof.x_max, NAN, 0, s);
    if (ec)
        uwb_draw_edges(&c, &L.prof, ec, UWB_EDGE_CURRENT, 0.0, L.prof.x_max, NAN, 0, s);
    if (ec && eb && uwb_displacement_measured(v))
        draw_shift_arrow(&c, &L.prof, v, s);
    else if (v && v->has_baseline && !uwb_displacement_measured(v))
        draw_not_measured(&c, &L.prof, v, s);
    panel_title(&c, &L.prof, "face profile", s, ink);

    struct uwb_axis_style img_axes = {.x_label_scale = 1000.0,
                                      .y_label_scale = 1000.0,
                                      .font_scale = s,
                                      .x_ticks = 3,
                                      .y_ticks = 10,
                                      .x_labels = 1,
                                      .y_labels_left = 1,
                                      .x_title = "range z (mm)",
                                      .y_title = "height y (mm)",
                                      /* labels keep clear of the next panel's */
                                      .panel_gap = PANEL_GAP / 2};
    uwb_draw_axes(&c, &L.base, &img_axes);
    img_axes.y_labels_left = 0;
    img_axes.x_title = NULL; /* the baseline's says it: two would run into each other */
    uwb_draw_axes(&c, &L.cur, &img_axes);
    uwb_draw_axes(&c, &L.diff, &img_axes);
    struct uwb_axis_style radial_axes = {.x_label_scale = 1000.0,
                                         .y_label_scale = 1000.0,
                                         .font_scale = s,
                                         .x_ticks = 2,
                                         .y_ticks = 10,
                                         .x_labels = 1,
                                         .panel_gap = PANEL_GAP};
    uwb_draw_axes(&c, &L.rad, &radial_axes);
    struct uwb_axis_style prof_axes = {.x_label_scale = 1.0,
                                       .y_label_scale = 1000.0,
                                       .font_scale = s,
                                       .x_ticks = 2,
                                       .y_ticks = 10,
                                       .x_labels = 1,
                                       .y_labels_right = 1,
                                       .x_title = "brightness / peak",
                                       .panel_gap = PANEL_GAP};
    uwb_draw_axes(&c, &L.prof, &prof_axes);
    uwb_draw_db_colorbar(&c, L.bar_x, L.cur.y, L.bar_w, L.cur.h, o.floor_db, s);
    uwb_draw_edge_legend(&c, L.base.x, uwb_layout_legend_y(&L.cur, s), ec != NULL, eb != NULL, s);

    return uwb_canvas_save_with_verdict(&c, path, "uwbd comparison", v, o.provenance, err, errlen);
}
