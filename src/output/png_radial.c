/* The comparison's radial panel: the face's range along the height in
 * both scans (the analyses' face_range, the brightest pixel's range on
 * each row), the baseline's moved up by the axial shift the verdict
 * compared the faces at, so that what stands off between the curves is
 * the face's radial change. x is millimetres toward the antenna re the
 * baseline's median range (a bulge leans right); this scan's curve has the
 * verdict's line through the unchanged rows taken out (the whole face's
 * move and its tilt, uwb_radial_line), so the curves stand apart by the
 * very change the verdict reads. Only the rows between
 * the baseline's edges are drawn: elsewhere there is no face to read.
 * The rows where the verdict found the change past the watch limit are
 * shaded in the radial status's colour, and the verdict's figure is
 * written in the panel. Nothing here is measured again: the verdict
 * holds the figure, the analyses the curves. */
#include "output/render_internal.h"
#include "uwb/radial.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SHADE_ALPHA 0.45
#define MIN_HALF_SPAN_M 0.003 /* the x axis shows at least +/- 3 mm */
#define PAD_M 0.001

static const struct uwb_rgb panel_background = {40, 40, 48};
static const struct uwb_rgb panel_grid = {95, 95, 105};
static const struct uwb_rgb no_data = {128, 128, 128};
static const struct uwb_rgb page = {255, 255, 255};
static const struct uwb_rgb ink = {25, 25, 25};

struct uwb_rgb uwb_radial_shade_colour(enum uwb_status status)
{
    return uwb_rgb_blend(panel_background, uwb_status_colour(status), SHADE_ALPHA);
}

/* The shift the faces were compared at: the radial's own, else the axial
 * displacement where measured, else none. */
static double compare_shift(const struct uwb_verdict *v)
{
    if (v->radial.measured)
        return v->radial.shift_m;
    return uwb_displacement_measured(v) ? v->axial_displacement_m : 0.0;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of the finite values (sorted in place); NAN if none. */
static double median(double *x, int n)
{
    int m = 0;
    for (int i = 0; i < n; i++)
        if (isfinite(x[i]))
            x[m++] = x[i];
    if (m == 0)
        return NAN;
    qsort(x, (size_t)m, sizeof *x, compare_doubles);
    return x[m / 2];
}

void uwb_radial_curves_free(struct uwb_radial_curves *k)
{
    free(k->yb);
    free(k->xb);
    free(k->yc);
    free(k->xc);
    memset(k, 0, sizeof *k);
}

int uwb_radial_curves_read(const struct uwb_analysis *cur, const struct uwb_analysis *base,
                           const struct uwb_verdict *v, struct uwb_radial_curves *k)
{
    memset(k, 0, sizeof *k);
    if (!cur || !base || !v || !v->has_baseline || !v->baseline.found || !base->face_range.value ||
        !cur->face_range.value || base->face_range.n < 2 || cur->face_range.n < 2)
        return -1;
    const struct uwb_face_profile *rb = &base->face_range, *rc = &cur->face_range;
    double lo = v->baseline.lower_m, hi = v->baseline.upper_m, shift = compare_shift(v);
    size_t nb = (size_t)rb->n, nc = (size_t)rc->n;
    k->yb = malloc(sizeof *k->yb * nb);
    k->xb = malloc(sizeof *k->xb * nb);
    k->yc = malloc(sizeof *k->yc * nc);
    k->xc = malloc(sizeof *k->xc * nc);
    double *scratch = malloc(sizeof *scratch * nb);
    if (!k->yb || !k->xb || !k->yc || !k->xc || !scratch) {
        free(scratch);
        uwb_radial_curves_free(k);
        return -1;
    }
    /* The baseline as the verdict compared it: its ripple that stays in
     * the image as the winding moves (the line's frame share) read where
     * this scan's row is. */
    double share = v->radial.measured ? v->radial.line.frame_share : 0.0;
    for (int i = 0; i < rb->n; i++) {
        double y = rb->y0_m + i * rb->dy_m;
        if (y < lo || y > hi)
            continue;
        k->yb[k->n_base] = y + shift;
        k->xb[k->n_base++] = rb->value[i] - share * uwb_radial_frame_ripple(rb, y, shift);
    }
    memcpy(scratch, k->xb, sizeof *scratch * (size_t)k->n_base);
    double z_ref = median(scratch, k->n_base);
    free(scratch);
    if (!isfinite(z_ref)) {
        uwb_radial_curves_free(k);
        return -1;
    }
    /* Not measured, no line: the ranges as read. */
    const struct uwb_radial_line none = {0};
    const struct uwb_radial_line *line = v->radial.measured ? &v->radial.line : &none;
    for (int i = 0; i < rc->n; i++) {
        double y = rc->y0_m + i * rc->dy_m;
        if (y < lo + shift || y > hi + shift)
            continue;
        k->yc[k->n_cur] = y;
        k->xc[k->n_cur++] = z_ref - rc->value[i] - uwb_radial_line_at(line, y - shift);
    }
    for (int i = 0; i < k->n_base; i++)
        k->xb[i] = z_ref - k->xb[i];
    return 0;
}

void uwb_radial_panel_range(const struct uwb_analysis *cur, const struct uwb_analysis *base,
                            const struct uwb_verdict *v, struct uwb_plot *p)
{
    double lo = -MIN_HALF_SPAN_M, hi = MIN_HALF_SPAN_M;
    struct uwb_radial_curves k;
    if (uwb_radial_curves_read(cur, base, v, &k) == 0) {
        for (int i = 0; i < k.n_base; i++)
            if (isfinite(k.xb[i])) {
                lo = fmin(lo, k.xb[i] - PAD_M);
                hi = fmax(hi, k.xb[i] + PAD_M);
            }
        for (int i = 0; i < k.n_cur; i++)
            if (isfinite(k.xc[i])) {
                lo = fmin(lo, k.xc[i] - PAD_M);
                hi = fmax(hi, k.xc[i] + PAD_M);
            }
        uwb_radial_curves_free(&k);
    }
    /* Symmetric about no change, at a half-span whose ticks fall on round
     * figures (-2 0 2, -5 0 5, -10 0 10 mm): the panel is narrow. */
    static const double half_spans_m[] = {0.003, 0.006, 0.012, 0.025, 0.06, 0.12};
    double half = fmax(-lo, hi);
    for (size_t i = 0; i < sizeof half_spans_m / sizeof half_spans_m[0]; i++)
        if (half_spans_m[i] >= half) {
            half = half_spans_m[i];
            break;
        }
    p->x_min = -half;
    p->x_max = half;
}

/* A curve as polylines broken where a row has no range. */
static void draw_curve(struct uwb_canvas *c, const struct uwb_plot *p, const double *ys, const double *xs,
                       int n, enum uwb_edge_kind kind)
{
    int *px = malloc(sizeof *px * (size_t)(n > 0 ? n : 1)),
        *py = malloc(sizeof *py * (size_t)(n > 0 ? n : 1));
    if (!px || !py) {
        free(px);
        free(py);
        return;
    }
    int m = 0;
    for (int i = 0; i <= n; i++) {
        int ok = i < n && isfinite(xs[i]) && ys[i] >= p->y_min && ys[i] <= p->y_max;
        if (ok) {
            px[m] = uwb_plot_col(p, xs[i]);
            py[m++] = uwb_plot_row(p, ys[i]);
            continue;
        }
        if (kind == UWB_EDGE_BASELINE)
            uwb_canvas_polyline(c, px, py, m, UWB_RGB_BASELINE_EDGE, 2, 7, 5);
        else
            uwb_canvas_polyline(c, px, py, m, UWB_RGB_CURRENT_EDGE, 2, 0, 0);
        m = 0;
    }
    free(px);
    free(py);
}

/* The rows past the watch limit, across the panel, in the status colour. */
static void shade_span(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_radial_verdict *r)
{
    int top = uwb_plot_row(p, fmax(r->from_m, r->to_m)), bottom = uwb_plot_row(p, fmin(r->from_m, r->to_m));
    if (top < p->y)
        top = p->y;
    if (bottom > p->y + p->h - 1)
        bottom = p->y + p->h - 1;
    if (bottom >= top)
        uwb_canvas_fill_rect(c, p->x, top, p->w, bottom - top + 1, uwb_radial_shade_colour(r->status));
}

/* Text lines in a page-coloured box at the panel's bottom, or its top
 * when the face reaches down there. */
static void draw_key(struct uwb_canvas *c, const struct uwb_plot *p, const char *const *lines, int n_lines,
                     int scale, double face_lo_m, struct uwb_rgb colour)
{
    char wrapped[12][96];
    int n = 0, max_w = p->w - 6;
    for (int i = 0; i < n_lines; i++) {
        const char *t = lines[i];
        while (*t && n < 12) {
            size_t len = uwb_wrap_line_length(t, max_w, scale);
            if (len >= sizeof wrapped[n])
                len = sizeof wrapped[n] - 1;
            memcpy(wrapped[n], t, len);
            wrapped[n++][len] = '\0';
            t += len;
            while (*t == ' ')
                t++;
        }
    }
    int line = UWB_FONT_LINE_HEIGHT * scale, bh = n * line + 4;
    int by = p->y + p->h - bh - 2;
    if (isfinite(face_lo_m) && uwb_plot_row(p, face_lo_m) > by)
        by = p->y + 2;
    uwb_canvas_fill_rect(c, p->x + 2, by, p->w - 4, bh, page);
    for (int i = 0; i < n; i++)
        uwb_draw_text(c, p->x + 4, by + 3 + i * line, wrapped[i], scale, colour);
}

void uwb_radial_level_text(const struct uwb_verdict *v, char *buf, size_t len)
{
    const struct uwb_radial_verdict *r = &v->radial;
    double whole_m = uwb_radial_line_at(&r->line, 0.5 * (v->baseline.lower_m + v->baseline.upper_m));
    if (len == 0)
        return;
    char whole[32], tilt[32];
    uwb_format_signed(whole, sizeof whole, whole_m * 1e3, 1);
    uwb_format_signed(tilt, sizeof tilt, r->tilt_m * 1e3, 1);
    if (!r->measured)
        buf[0] = '\0';
    else if (!r->tilt_withheld[0])
        snprintf(buf, len, "face as a whole %s mm, tilt %s \u00b1 %.1f mm, taken out", whole, tilt,
                 r->tilt_uncertainty_m * 1e3);
    else /* the line is level: no lean was read, so none is said */
        snprintf(buf, len, "face as a whole %s mm taken out; tilt withheld", whole);
}

void uwb_draw_radial_panel(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_analysis *cur,
                           const struct uwb_analysis *base, const struct uwb_verdict *v, int font_scale)
{
    int ks = font_scale > 1 ? font_scale - 1 : 1;
    if (!base || !v || !v->has_baseline) {
        uwb_canvas_fill_rect(c, p->x, p->y, p->w, p->h, no_data);
        const char *text = "no baseline";
        int w = uwb_text_width(text, ks);
        uwb_draw_text(c, p->x + (p->w - w) / 2, p->y + p->h / 2, text, ks, page);
        return;
    }
    uwb_canvas_fill_rect(c, p->x, p->y, p->w, p->h, panel_background);
    const struct uwb_radial_verdict *r = &v->radial;
    if (r->measured && r->has_span)
        shade_span(c, p, r);
    int zero = uwb_plot_col(p, 0.0);
    uwb_canvas_line(c, zero, p->y, zero, p->y + p->h - 1, panel_grid, 1, 2, 3);
    struct uwb_radial_curves k;
    char level[96] = "";
    if (uwb_radial_curves_read(cur, base, v, &k) == 0) {
        draw_curve(c, p, k.yb, k.xb, k.n_base, UWB_EDGE_BASELINE);
        draw_curve(c, p, k.yc, k.xc, k.n_cur, UWB_EDGE_CURRENT);
        uwb_radial_curves_free(&k);
        uwb_radial_level_text(v, level, sizeof level);
    }
    char figure[256];
    uwb_describe_radial(v, figure, sizeof figure);
    const char *lines[3] = {"x: mm nearer the antenna", figure, level};
    draw_key(c, p, lines, level[0] ? 3 : 2, ks,
             v->baseline.found ? v->baseline.lower_m + compare_shift(v) : NAN,
             r->measured && r->status != UWB_STATUS_OK ? uwb_status_colour(r->status) : ink);
}
