/* Data-to-pixel mapping, "nice" tick values, framed axes with labelled
 * ticks on both axes, and vertical colour bars. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const struct uwb_rgb ink = {25, 25, 25};
static const struct uwb_rgb frame_grey = {60, 60, 60};

double uwb_plot_px_x(const struct uwb_plot *p, double x)
{
    double span = p->x_max - p->x_min;
    if (!(span != 0.0))
        return p->x;
    return p->x + (x - p->x_min) / span * (p->w - 1);
}

double uwb_plot_px_y(const struct uwb_plot *p, double y)
{
    double span = p->y_max - p->y_min;
    if (!(span != 0.0))
        return p->y;
    return p->y + (p->y_max - y) / span * (p->h - 1);
}

/* Rounded, and kept within int range for wild inputs (clipping happens
 * later, in the drawing). */
static int to_pixel(double v)
{
    if (!(v > -1e6))
        return -1000000;
    if (v > 1e6)
        return 1000000;
    return (int)lround(v);
}

int uwb_plot_col(const struct uwb_plot *p, double x)
{
    return to_pixel(uwb_plot_px_x(p, x));
}

int uwb_plot_row(const struct uwb_plot *p, double y)
{
    return to_pixel(uwb_plot_px_y(p, y));
}

int uwb_nice_ticks(double lo, double hi, int target, double *ticks, int max_ticks, double *step_out)
{
    if (!(hi > lo) || !isfinite(lo) || !isfinite(hi) || max_ticks < 1 || target < 1)
        return 0;
    double raw = (hi - lo) / target;
    double mag = pow(10.0, floor(log10(raw)));
    double frac = raw / mag;
    double step = frac < 1.5 ? mag : frac < 3.5 ? 2 * mag : frac < 7.5 ? 5 * mag : 10 * mag;
    double first = ceil(lo / step - 1e-9) * step;
    int n = 0;
    for (; n < max_ticks; n++) {
        double v = first + n * step;
        if (v > hi + step * 1e-9)
            break;
        ticks[n] = fabs(v) < step * 1e-9 ? 0.0 : v;
    }
    if (step_out)
        *step_out = step;
    return n;
}

void uwb_format_tick(char *buf, size_t len, double value, double step)
{
    /* As many decimals as the step has (2.5 needs one, 0.25 two). */
    int decimals = 0;
    double scaled = fabs(step);
    while (decimals < 6 && fabs(scaled - round(scaled)) > 1e-6 * fmax(1.0, scaled)) {
        scaled *= 10.0;
        decimals++;
    }
    if (fabs(value) < step * 1e-6)
        value = 0.0; /* never print "-0" */
    snprintf(buf, len, "%.*f", decimals, value);
    /* "0.5 1" rather than "0.5 1.0": shorter labels, same figure. */
    if (decimals > 0) {
        char *end = buf + strlen(buf) - 1;
        while (end > buf && *end == '0')
            *end-- = '\0';
        if (end > buf && *end == '.')
            *end = '\0';
    }
}

#define TICK_LEN 6
#define MINOR_LEN 3
#define LABEL_GAP 4

void uwb_draw_axes(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_axis_style *s)
{
    double ticks[64], step;
    char label[32];
    int scale = s->font_scale > 0 ? s->font_scale : 1;
    int text_h = UWB_FONT_CAP_HEIGHT * scale;
    uwb_canvas_frame_rect(c, p->x - 1, p->y - 1, p->w + 2, p->h + 2, frame_grey);

    /* x axis: ticks below the frame, labels centred under them. */
    double xs = s->x_label_scale > 0 ? s->x_label_scale : 1.0;
    int n = uwb_nice_ticks(p->x_min * xs, p->x_max * xs, s->x_ticks > 0 ? s->x_ticks : 6, ticks, 64, &step);
    int label_bottom = p->y + p->h + TICK_LEN + LABEL_GAP;
    for (int i = 0; i < n; i++) {
        int col = uwb_plot_col(p, ticks[i] / xs);
        uwb_canvas_fill_rect(c, col, p->y + p->h, 1, TICK_LEN, frame_grey);
        if (!s->x_labels)
            continue;
        uwb_format_tick(label, sizeof label, ticks[i], step);
        int w = uwb_text_width(label, scale);
        /* A label that would reach into a neighbouring panel is left out. */
        int overhang = s->panel_gap > 0 ? s->panel_gap / 2 - 1 : w;
        if (col - w / 2 < p->x - overhang || col - w / 2 + w > p->x + p->w + overhang)
            continue;
        uwb_draw_text(c, col - w / 2, p->y + p->h + TICK_LEN + LABEL_GAP, label, scale, ink);
        label_bottom = p->y + p->h + TICK_LEN + LABEL_GAP + text_h;
    }
    if (s->x_title) {
        int w = uwb_text_width(s->x_title, scale);
        uwb_draw_text(c, p->x + (p->w - w) / 2, label_bottom + 8, s->x_title, scale, ink);
    }

    /* y axis: ticks left (and right), labels beside them, vertically centred. */
    double ys = s->y_label_scale > 0 ? s->y_label_scale : 1.0;
    n = uwb_nice_ticks(p->y_min * ys, p->y_max * ys, s->y_ticks > 0 ? s->y_ticks : 8, ticks, 64, &step);
    /* Unlabelled minor ticks (a fifth of the step, a quarter for steps of
     * 2 x 10^n) so heights read to a few mm without a ruler. */
    double lead = step / pow(10.0, floor(log10(step) + 1e-9));
    double minor = lead > 1.5 && lead < 3.5 ? step / 4 : step / 5;
    double first_minor = ceil(p->y_min * ys / minor - 1e-9);
    for (int i = 0;; i++) {
        double m = (first_minor + i) * minor;     /* counted, not accumulated */
        if (!(m <= p->y_max * ys + minor * 1e-9)) /* NaN limits too: no ticks */
            break;
        int row = uwb_plot_row(p, m / ys);
        if (s->y_labels_left)
            uwb_canvas_fill_rect(c, p->x - 1 - MINOR_LEN, row, MINOR_LEN, 1, frame_grey);
        if (s->y_labels_right)
            uwb_canvas_fill_rect(c, p->x + p->w + 1, row, MINOR_LEN, 1, frame_grey);
    }
    int widest = 0;
    for (int i = 0; i < n; i++) {
        int row = uwb_plot_row(p, ticks[i] / ys);
        uwb_format_tick(label, sizeof label, ticks[i], step);
        int w = uwb_text_width(label, scale);
        if (w > widest)
            widest = w;
        if (s->y_labels_left) {
            uwb_canvas_fill_rect(c, p->x - 1 - TICK_LEN, row, TICK_LEN, 1, frame_grey);
            uwb_draw_text(c, p->x - 1 - TICK_LEN - LABEL_GAP - w, row - text_h / 2, label, scale, ink);
        }
        if (s->y_labels_right) {
            uwb_canvas_fill_rect(c, p->x + p->w + 1, row, TICK_LEN, 1, frame_grey);
            uwb_draw_text(c, p->x + p->w + 1 + TICK_LEN + LABEL_GAP, row - text_h / 2, label, scale, ink);
        }
    }
    if (s->y_title && s->y_labels_left) {
        int w = uwb_text_width(s->y_title, scale);
        int x = p->x - 1 - TICK_LEN - LABEL_GAP - widest - 8 - (UWB_FONT_LINE_HEIGHT - 2) * scale;
        uwb_draw_text_up(c, x, p->y + (p->h + w) / 2, s->y_title, scale, ink);
    }
    if (s->y_title_right && s->y_labels_right) {
        int w = uwb_text_width(s->y_title_right, scale);
        int x = p->x + p->w + 1 + TICK_LEN + LABEL_GAP + widest + 8;
        uwb_draw_text_up(c, x, p->y + (p->h + w) / 2, s->y_title_right, scale, ink);
    }
}

void uwb_draw_colorbar(struct uwb_canvas *c, int x, int y, int w, int h, struct uwb_rgb (*map)(double),
                       const double *tick_t, const char *const *labels, int n_ticks, const char *title,
                       int font_scale)
{
    if (h < 2 || w < 1)
        return;
    int scale = font_scale > 0 ? font_scale : 1;
    /* Top row is t = 1 (the map's maximum colour), bottom row t = 0. */
    for (int r = 0; r < h; r++) {
        double t = 1.0 - (double)r / (h - 1);
        uwb_canvas_fill_rect(c, x, y + r, w, 1, map(t));
    }
    uwb_canvas_frame_rect(c, x - 1, y - 1, w + 2, h + 2, frame_grey);
    for (int i = 0; i < n_ticks; i++) {
        int row = y + (int)lround((1.0 - tick_t[i]) * (h - 1));
        uwb_canvas_fill_rect(c, x + w + 1, row, TICK_LEN, 1, frame_grey);
        if (labels && labels[i])
            uwb_draw_text(c, x + w + 1 + TICK_LEN + LABEL_GAP, row - UWB_FONT_CAP_HEIGHT * scale / 2,
                          labels[i], scale, ink);
    }
    if (title) {
        int tw = uwb_text_width(title, scale);
        int tx = x + w / 2 - tw / 2;
        if (tx < 0)
            tx = 0;
        uwb_draw_text(c, tx, y - 8 - UWB_FONT_LINE_HEIGHT * scale, title, scale, ink);
    }
}

void uwb_draw_db_colorbar(struct uwb_canvas *c, int x, int y, int w, int h, double floor_db, int font_scale)
{
    double ticks[32], step, pos[32];
    char text[32][16];
    const char *labels[32];
    int n = uwb_nice_ticks(floor_db, 0.0, 6, ticks, 32, &step);
    for (int i = 0; i < n; i++) {
        pos[i] = (ticks[i] - floor_db) / (0.0 - floor_db);
        uwb_format_tick(text[i], sizeof text[i], ticks[i], step);
        labels[i] = text[i];
    }
    uwb_draw_colorbar(c, x, y, w, h, uwb_colormap_perceptual, pos, labels, n, "dB", font_scale);
}
