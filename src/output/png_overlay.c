/* The edges drawn over a plot, the same way in every image: this scan's
 * edges solid white, the baseline's dashed pink, both with a black halo so
 * they stay visible on any colour; a diamond at the centre (filled: this
 * scan, hollow: baseline); the edge heights written at the line ends; and
 * the legend that says which is which. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define DASH_ON 8
#define DASH_OFF 5
#define MARKER_R 5

static const struct uwb_rgb ink = {25, 25, 25};

void uwb_draw_edge_hline(struct uwb_canvas *c, int x0, int x1, int row, enum uwb_edge_kind kind)
{
    int dash_on = kind == UWB_EDGE_BASELINE ? DASH_ON : 0;
    int dash_off = kind == UWB_EDGE_BASELINE ? DASH_OFF : 0;
    struct uwb_rgb core = kind == UWB_EDGE_BASELINE ? UWB_RGB_BASELINE_EDGE : UWB_RGB_CURRENT_EDGE;
    /* Halo first, 3 px wide with the same dash phase, then the 1 px core
     * exactly on the row of the edge's height. */
    uwb_canvas_line(c, x0, row, x1, row, UWB_RGB_HALO, 3, dash_on, dash_off);
    uwb_canvas_line(c, x0, row, x1, row, core, 1, dash_on, dash_off);
}

static void diamond(struct uwb_canvas *c, int cx, int cy, int r_in, int r_out, struct uwb_rgb colour)
{
    for (int dy = -r_out; dy <= r_out; dy++)
        for (int dx = -r_out; dx <= r_out; dx++) {
            int d = abs(dx) + abs(dy);
            if (d >= r_in && d <= r_out)
                uwb_canvas_put(c, cx + dx, cy + dy, colour);
        }
}

void uwb_draw_centre_marker(struct uwb_canvas *c, int cx, int cy, enum uwb_edge_kind kind)
{
    if (kind == UWB_EDGE_BASELINE) {
        diamond(c, cx, cy, MARKER_R - 2, MARKER_R + 1, UWB_RGB_HALO);
        diamond(c, cx, cy, MARKER_R - 1, MARKER_R, UWB_RGB_BASELINE_EDGE);
    } else {
        diamond(c, cx, cy, 0, MARKER_R + 1, UWB_RGB_HALO);
        diamond(c, cx, cy, 0, MARKER_R - 1, UWB_RGB_CURRENT_EDGE);
    }
}

/* A figure in a black box so it reads on any background. */
static void boxed_label(struct uwb_canvas *c, int x, int y_mid, const char *text, int scale,
                        struct uwb_rgb colour, int align_right)
{
    int w = uwb_text_width(text, scale), h = UWB_FONT_CAP_HEIGHT * scale;
    if (align_right)
        x -= w + 4;
    uwb_canvas_fill_rect(c, x, y_mid - h / 2 - 2, w + 4, h + 4, UWB_RGB_HALO);
    uwb_draw_text(c, x + 2, y_mid - h / 2, text, scale, colour);
}

void uwb_draw_edges(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_edges *e,
                    enum uwb_edge_kind kind, double x_from, double x_to, double x_marker, int label_side,
                    int font_scale)
{
    if (!e || !e->found)
        return;
    int c0 = uwb_plot_col(p, x_from), c1 = uwb_plot_col(p, x_to);
    /* Lines stay inside the plot frame. */
    if (c0 < p->x)
        c0 = p->x;
    if (c1 > p->x + p->w - 1)
        c1 = p->x + p->w - 1;
    double heights[2] = {e->lower_m, e->upper_m};
    for (int i = 0; i < 2; i++) {
        int row = uwb_plot_row(p, heights[i]);
        if (row < p->y || row >= p->y + p->h || c1 < c0)
            continue; /* off the plot: the caption still gives the figure */
        uwb_draw_edge_hline(c, c0, c1, row, kind);
        if (label_side) {
            char mm[32];
            snprintf(mm, sizeof mm, "%.1f", heights[i] * 1000.0);
            struct uwb_rgb colour = kind == UWB_EDGE_BASELINE ? UWB_RGB_BASELINE_EDGE : UWB_RGB_CURRENT_EDGE;
            if (label_side > 0)
                boxed_label(c, c1 + 3, row, mm, font_scale, colour, 0);
            else
                boxed_label(c, c0 - 3, row, mm, font_scale, colour, 1);
        }
    }
    if (isnan(x_marker))
        return;
    int mrow = uwb_plot_row(p, e->center_m), mcol = uwb_plot_col(p, x_marker);
    if (mrow >= p->y && mrow < p->y + p->h && mcol >= p->x && mcol < p->x + p->w)
        uwb_draw_centre_marker(c, mcol, mrow, kind);
}

/* One legend entry: a line sample, a marker, the words. Returns its width. */
static int legend_entry(struct uwb_canvas *c, int x, int y, enum uwb_edge_kind kind, const char *words,
                        int scale)
{
    int mid = y + UWB_FONT_CAP_HEIGHT * scale / 2;
    /* The sample sits on a neutral patch, as the lines sit on an image. */
    uwb_canvas_fill_rect(c, x, mid - 8, 64, 17, (struct uwb_rgb){110, 110, 118});
    uwb_draw_edge_hline(c, x + 4, x + 40, mid, kind);
    uwb_draw_centre_marker(c, x + 52, mid, kind);
    int w = uwb_draw_text(c, x + 72, y, words, scale, ink);
    return 72 + w;
}

int uwb_draw_edge_legend(struct uwb_canvas *c, int x, int y, int with_current, int with_baseline,
                         int font_scale)
{
    int at = x;
    if (with_current)
        at += legend_entry(c, at, y, UWB_EDGE_CURRENT, "this scan: edges, centre", font_scale) + 28;
    if (with_baseline)
        at += legend_entry(c, at, y, UWB_EDGE_BASELINE, "baseline: edges, centre", font_scale) + 28;
    return at - x;
}
