/* The B-scan: every trace as a band at its antenna height, time across;
 * the raw traces, or the conditioned ones the migration ran on (direct
 * coupling and clutter taken out: what the image is made of).
 * Signed amplitude on a signed dB scale (red positive, blue negative, white
 * below the floor) because the direct coupling is several times stronger
 * than the winding's echo: on a linear scale the echo, the thing to look
 * at, would be a faint smudge. The face's expected arrival and the edges
 * are overlaid like in the migrated image, the search window the
 * analysis used as two dashed lines; the time axis spans the echoes. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SPEED_OF_LIGHT 299792458.0
#define FACE_REGION_FRACTION 0.12
#define UWB_RANGE_TICK 6

static const struct uwb_rgb page = {255, 255, 255};
static const struct uwb_rgb ink = {25, 25, 25};
/* Green: a colour the diverging map of the traces never takes. */
const struct uwb_rgb UWB_RGB_SEARCH_WINDOW = {0, 130, 60};

static int check_scan(const struct uwb_scan *scan, const char *path, char *err, size_t errlen)
{
    if (!scan || !scan->data || !scan->antenna_y_m) {
        snprintf(err, errlen, "%s: no scan data", path);
        return -1;
    }
    if (scan->positions < 1 || scan->samples < 2) {
        snprintf(err, errlen, "%s: scan of %d positions x %d samples is too small to draw", path,
                 scan->positions, scan->samples);
        return -1;
    }
    if (!(scan->sample_interval_s > 0) || !isfinite(scan->sample_interval_s) || !isfinite(scan->t0_s)) {
        snprintf(err, errlen, "%s: sample interval must be finite and positive (%g s)", path,
                 scan->sample_interval_s);
        return -1;
    }
    for (int k = 0; k < scan->positions; k++)
        if (!isfinite(scan->antenna_y_m[k])) {
            snprintf(err, errlen, "%s: antenna position %d is not a number", path, k);
            return -1;
        }
    return 0;
}

static double sample_value(const struct uwb_scan *scan, int k, int s)
{
    double v = scan->data[(size_t)k * (size_t)scan->samples + (size_t)s];
    return isfinite(v) ? v : 0.0;
}

/* Colour-map position of a signed amplitude: 0.5 is zero (or below the
 * floor), 1 the positive peak, 0 the negative peak. */
double uwb_signed_db_to_t(double value, double peak, double floor_db)
{
    if (!(peak > 0) || value == 0.0 || !isfinite(value))
        return 0.5;
    double m = fabs(value) / peak;
    double u = (20.0 * log10(m) - floor_db) / (0.0 - floor_db);
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    return value > 0 ? 0.5 + 0.5 * u : 0.5 - 0.5 * u;
}

/* Two-way time of the specular echo from a plane face at range face_z:
 * mirror the receiver in the plane (image method), so it holds for the
 * bistatic pair at any height. */
double uwb_face_echo_time(const struct uwb_scan *scan, double face_z_m)
{
    double eps = scan->eps_r > 0 ? scan->eps_r : 1.0;
    double v = SPEED_OF_LIGHT / sqrt(eps);
    double dz = 2.0 * face_z_m - scan->tx_m[1] - scan->rx_m[1];
    double dy = scan->rx_m[0] - scan->tx_m[0];
    return sqrt(dz * dz + dy * dy) / v;
}

/* The range of a plane face whose specular echo arrives at time t (the
 * inverse of uwb_face_echo_time); NAN before the earliest such echo. */
double uwb_face_range_at_time(const struct uwb_scan *scan, double t_s)
{
    double eps = scan->eps_r > 0 ? scan->eps_r : 1.0;
    double path = t_s * SPEED_OF_LIGHT / sqrt(eps);
    double dy = scan->rx_m[0] - scan->tx_m[0];
    if (!(path >= fabs(dy)))
        return NAN;
    return 0.5 * (sqrt(path * path - dy * dy) + scan->tx_m[1] + scan->rx_m[1]);
}

/* A second axis along the top: the range a face would be at for its echo
 * to arrive at that time (this scan's antenna pair and eps_r), so the
 * winding's face can be read off the traces in millimetres. */
static void draw_range_axis(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_scan *scan,
                            int s)
{
    double z_lo = uwb_face_range_at_time(scan, p->x_min), z_hi = uwb_face_range_at_time(scan, p->x_max);
    if (!isfinite(z_lo))
        z_lo = uwb_face_range_at_time(scan, fabs(scan->rx_m[0] - scan->tx_m[0]) *
                                                sqrt(scan->eps_r > 0 ? scan->eps_r : 1.0) / SPEED_OF_LIGHT);
    if (!isfinite(z_lo) || !isfinite(z_hi) || !(z_hi > z_lo))
        return;
    double ticks[64], step;
    int n = uwb_nice_ticks(z_lo * 1000.0, z_hi * 1000.0, 8, ticks, 64, &step);
    static const struct uwb_rgb grey = {120, 120, 120};
    char label[32];
    int text_h = UWB_FONT_CAP_HEIGHT * s, last_right = -1000;
    for (int i = 0; i < n; i++) {
        int col = uwb_plot_col(p, uwb_face_echo_time(scan, ticks[i] / 1000.0));
        if (col < p->x || col >= p->x + p->w)
            continue;
        uwb_canvas_fill_rect(c, col, p->y - 1 - UWB_RANGE_TICK, 1, UWB_RANGE_TICK, grey);
        uwb_format_tick(label, sizeof label, ticks[i], step);
        int w = uwb_text_width(label, s);
        if (col - w / 2 < last_right + 6 * s) /* the ticks bunch up near the direct path */
            continue;
        uwb_draw_text(c, col - w / 2, p->y - 1 - UWB_RANGE_TICK - 4 - text_h, label, s, ink);
        last_right = col - w / 2 + w;
    }
    const char *title = "range z of a face echo (mm)";
    uwb_draw_text(c, p->x + (p->w - uwb_text_width(title, s)) / 2,
                  p->y - 1 - UWB_RANGE_TICK - 4 - text_h - 6 - text_h, title, s, ink);
}

/* The trace whose antenna height is nearest y. */
static int nearest_trace(const struct uwb_scan *scan, double y)
{
    int best = 0;
    for (int k = 1; k < scan->positions; k++)
        if (fabs(scan->antenna_y_m[k] - y) < fabs(scan->antenna_y_m[best] - y))
            best = k;
    return best;
}

/* One trace's colours across the plot. */
static void trace_colours(const struct uwb_plot *p, const struct uwb_scan *scan, int k, double peak,
                          double floor_db, struct uwb_rgb *colours)
{
    double dt = scan->sample_interval_s;
    for (int col = 0; col < p->w; col++) {
        /* The column spans [ta, tb); with many samples per column take
         * the strongest, so a short echo cannot fall between pixels. */
        double ta = p->x_min + (p->x_max - p->x_min) * (col - 0.5) / (p->w - 1);
        double tb = p->x_min + (p->x_max - p->x_min) * (col + 0.5) / (p->w - 1);
        double fa = (ta - scan->t0_s) / dt, fb = (tb - scan->t0_s) / dt;
        int sa = (int)ceil(fa), sb = (int)floor(fb);
        double value;
        if (sb - sa >= 1) {
            sa = sa < 0 ? 0 : sa;
            sb = sb > scan->samples - 1 ? scan->samples - 1 : sb;
            value = 0;
            for (int s = sa; s <= sb; s++) {
                double v = sample_value(scan, k, s);
                if (fabs(v) > fabs(value))
                    value = v;
            }
        } else {
            double f = 0.5 * (fa + fb);
            f = f < 0 ? 0 : f > scan->samples - 1 ? scan->samples - 1 : f;
            int s = (int)f;
            if (s > scan->samples - 2)
                s = scan->samples - 2;
            double a = f - s;
            value = (1 - a) * sample_value(scan, k, s) + a * sample_value(scan, k, s + 1);
        }
        colours[col] = uwb_colormap_diverging(uwb_signed_db_to_t(value, peak, floor_db));
    }
}

/* Each plot row shows the trace nearest its height: a trace's colours are
 * worked out once and copied to every row it covers (tens of rows each). */
static void paint_traces(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_scan *scan,
                         double peak, double floor_db)
{
    struct uwb_rgb *colours = malloc(sizeof *colours * (size_t)p->w);
    if (!colours)
        return;
    int painted = -1;
    for (int row = 0; row < p->h; row++) {
        double y = p->y_max - (p->y_max - p->y_min) * row / (p->h > 1 ? p->h - 1 : 1);
        int k = nearest_trace(scan, y);
        if (k != painted) {
            trace_colours(p, scan, k, peak, floor_db, colours);
            painted = k;
        }
        for (int col = 0; col < p->w; col++)
            uwb_canvas_put(c, p->x + col, p->y + row, colours[col]);
    }
    free(colours);
}

static void draw_signed_colorbar(struct uwb_canvas *c, int x, int y, int w, int h, double floor_db, int s)
{
    double ticks[32], step, pos[64];
    char text[64][16];
    const char *labels[64];
    int n = uwb_nice_ticks(floor_db, 0.0, 4, ticks, 32, &step), m = 0;
    /* The same dB figures on both halves; the floor, where they meet, once. */
    for (int i = 0; i < n; i++) {
        double u = (ticks[i] - floor_db) / (0.0 - floor_db);
        uwb_format_tick(text[m], sizeof text[m], ticks[i], step);
        labels[m] = text[m];
        pos[m++] = 0.5 + 0.5 * u;
        if (u > 1e-9) {
            uwb_format_tick(text[m], sizeof text[m], ticks[i], step);
            labels[m] = text[m];
            pos[m++] = 0.5 - 0.5 * u;
        }
    }
    uwb_draw_colorbar(c, x, y, w, h, uwb_colormap_diverging, pos, labels, m, "+ dB", s);
    int tw = uwb_text_width("- dB", s);
    uwb_draw_text(c, x + w / 2 - tw / 2, y + h + 8, "- dB", s, ink);
}

/* The times the analysis's search window spans: the echo times of its
 * nearest and farthest ranges. 0 when there is no window. */
static int search_window_times(const struct uwb_scan *scan, const struct uwb_provenance *prov, double *t_lo,
                               double *t_hi)
{
    if (!prov || !prov->has_search_window || !(prov->search_z_hi_m > prov->search_z_lo_m))
        return 0;
    *t_lo = uwb_face_echo_time(scan, prov->search_z_lo_m);
    *t_hi = uwb_face_echo_time(scan, prov->search_z_hi_m);
    return isfinite(*t_lo) && isfinite(*t_hi) && *t_hi > *t_lo;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The time axis fits the echoes: the times whose energy summed over the
 * traces stands ECHO_OVER_NOISE_DB over the median time's (the noise)
 * and is no more than ECHO_RANGE_DB under the strongest, and the faces'
 * echo times, with a margin, within the record. Against the noise, not the
 * strongest alone: on raw traces the direct coupling outshines the
 * winding's echo. A long record whose echoes fill a fifth of it would
 * otherwise leave most of the plot empty. The search window may reach past
 * it: its ends are marked where they fall on the plot. */
#define ECHO_OVER_NOISE_DB 15.0
#define ECHO_RANGE_DB 60.0
static void fit_time_axis(const struct uwb_scan *scan, const struct uwb_verdict *v, double *x_min,
                          double *x_max)
{
    double dt = scan->sample_interval_s, rec_lo = scan->t0_s, rec_hi = rec_lo + (scan->samples - 1) * dt;
    *x_min = rec_lo;
    *x_max = rec_hi;
    size_t n = (size_t)scan->samples;
    double *energy = calloc(n, sizeof *energy), *sorted = malloc(n * sizeof *sorted);
    if (!energy || !sorted) {
        free(energy);
        free(sorted);
        return;
    }
    for (int k = 0; k < scan->positions; k++)
        for (int s = 0; s < scan->samples; s++) {
            double a = sample_value(scan, k, s);
            energy[s] += a * a;
        }
    memcpy(sorted, energy, n * sizeof *sorted);
    qsort(sorted, n, sizeof *sorted, by_value);
    double least = fmax(sorted[n / 2] * pow(10.0, ECHO_OVER_NOISE_DB / 10.0),
                        sorted[n - 1] * pow(10.0, -ECHO_RANGE_DB / 10.0));
    free(sorted);
    int first = scan->samples, last = -1;
    for (int s = 0; s < scan->samples; s++)
        if (energy[s] > least) {
            first = s < first ? s : first;
            last = s;
        }
    free(energy);
    if (last < 0)
        return;
    double lo = rec_lo + first * dt, hi = rec_lo + last * dt;
    const struct uwb_edges *faces[2] = {v ? &v->current : NULL, v && v->has_baseline ? &v->baseline : NULL};
    for (int i = 0; i < 2; i++)
        if (faces[i] && faces[i]->found) {
            double t = uwb_face_echo_time(scan, faces[i]->face_z_m);
            lo = fmin(lo, t);
            hi = fmax(hi, t);
        }
    double margin = 0.25 * (hi - lo) + 4 * dt;
    lo = fmax(rec_lo, lo - margin);
    hi = fmin(rec_hi, hi + margin);
    if (hi > lo) {
        *x_min = lo;
        *x_max = hi;
    }
}

/* The search window: its ends as dashed lines where they fall on the
 * plot, named with its ranges (an end off the plot is still named). */
static void mark_search_window(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_scan *scan,
                               const struct uwb_provenance *prov)
{
    double t[2];
    if (!search_window_times(scan, prov, &t[0], &t[1]))
        return;
    int cols[2];
    for (int i = 0; i < 2; i++) {
        cols[i] = uwb_plot_col(p, t[i]);
        if (cols[i] >= p->x && cols[i] < p->x + p->w)
            uwb_canvas_line(c, cols[i], p->y, cols[i], p->y + p->h - 1, UWB_RGB_SEARCH_WINDOW, 2, 8, 5);
    }
    char label[80];
    snprintf(label, sizeof label, "search window %.0f-%.0f mm", prov->search_z_lo_m * 1e3,
             prov->search_z_hi_m * 1e3);
    int w = uwb_text_width(label, 1), h = UWB_FONT_CAP_HEIGHT;
    int x = cols[0] >= p->x ? cols[0] + 5 : p->x + 4;
    if (x + w + 4 >= p->x + p->w)
        x = p->x + p->w - w - 4;
    if (x >= p->x) {
        uwb_canvas_fill_rect(c, x - 2, p->y + 3, w + 4, h + 4, page);
        uwb_draw_text(c, x, p->y + 5, label, 1, UWB_RGB_SEARCH_WINDOW);
    }
}

void uwb_render_bscan_layout(const struct uwb_scan *scan, const struct uwb_verdict *v,
                             const struct uwb_render_options *opt, struct uwb_plot *plot, int *colorbar_x,
                             int *colorbar_w)
{
    struct uwb_render_options o;
    uwb_render_options_sane(opt, &o);
    uwb_layout_single_plot(o.width, o.height, o.font_scale,
                           uwb_caption_height(v, o.provenance, o.width, o.font_scale), plot, colorbar_x,
                           colorbar_w);
    fit_time_axis(scan, v, &plot->x_min, &plot->x_max);
    /* Each trace owns the band half-way to its neighbours, so the outer
     * traces get a half (mean) step beyond their heights too. */
    double lo = scan->antenna_y_m[0], hi = lo;
    for (int k = 1; k < scan->positions; k++) {
        lo = fmin(lo, scan->antenna_y_m[k]);
        hi = fmax(hi, scan->antenna_y_m[k]);
    }
    double margin = scan->positions > 1 ? 0.5 * (hi - lo) / (scan->positions - 1) : 0.015;
    if (!(margin > 0))
        margin = 0.015;
    plot->y_min = lo - margin;
    plot->y_max = hi + margin;
    /* Room above the plot for the range axis: ticks, labels, title. */
    int room = UWB_RANGE_TICK + 4 + 2 * UWB_FONT_CAP_HEIGHT * o.font_scale + 6 + 4;
    plot->y += room;
    plot->h -= room;
    if (plot->h < 16)
        plot->h = 16;
}

int uwb_render_bscan_png(const char *path, const struct uwb_scan *scan, const struct uwb_verdict *v,
                         char *err, size_t errlen)
{
    return uwb_render_bscan_png_opt(path, scan, v, NULL, err, errlen);
}

int uwb_render_bscan_png_opt(const char *path, const struct uwb_scan *scan, const struct uwb_verdict *v,
                             const struct uwb_render_options *opt, char *err, size_t errlen)
{
    if (!path || !*path) {
        snprintf(err, errlen, "B-scan image: no output path");
        return -1;
    }
    if (check_scan(scan, path, err, errlen) != 0)
        return -1;
    struct uwb_render_options o;
    uwb_render_options_sane(opt, &o);
    int s = o.font_scale;

    struct uwb_canvas c;
    if (uwb_canvas_init(&c, o.width, o.height, page, err, errlen) != 0)
        return -1;
    struct uwb_plot plot;
    int bar_x, bar_w;
    uwb_render_bscan_layout(scan, v, &o, &plot, &bar_x, &bar_w);

    const char *kind = o.bscan_conditioned ? "conditioned" : "raw";
    char title[96], short_title[48];
    snprintf(title, sizeof title, "uwbd %s B-scan - signed, dB re |peak|", kind);
    snprintf(short_title, sizeof short_title, "uwbd %s B-scan", kind);
    uwb_draw_caption(&c, title, v, o.provenance, s);

    double peak = 0;
    for (int k = 0; k < scan->positions; k++)
        for (int i = 0; i < scan->samples; i++)
            peak = fmax(peak, fabs(sample_value(scan, k, i)));
    paint_traces(&c, &plot, scan, peak, o.bscan_floor_db);
    if (!(peak > 0))
        uwb_draw_text(&c, plot.x + 10, plot.y + 10, "scan is empty (all zero)", s, ink);

    mark_search_window(&c, &plot, scan, o.provenance);
    if (v) {
        const struct uwb_edges *b = v->has_baseline ? &v->baseline : NULL, *e = &v->current;
        if (b && b->found) {
            double t = uwb_face_echo_time(scan, b->face_z_m),
                   half = FACE_REGION_FRACTION * (plot.x_max - plot.x_min);
            uwb_draw_edges(&c, &plot, b, UWB_EDGE_BASELINE, t - half, t + half, t, -1, s);
        }
        if (e->found) {
            double t = uwb_face_echo_time(scan, e->face_z_m),
                   half = FACE_REGION_FRACTION * (plot.x_max - plot.x_min);
            uwb_draw_edges(&c, &plot, e, UWB_EDGE_CURRENT, t - half, t + half, t, 1, s);
        }
    }

    struct uwb_axis_style axes = {.x_label_scale = 1e9,
                                  .y_label_scale = 1000.0,
                                  .font_scale = s,
                                  .x_ticks = 8,
                                  .y_ticks = 10,
                                  .x_labels = 1,
                                  .y_labels_left = 1,
                                  .x_title = "time after the pulse leaves Tx (ns)",
                                  .y_title = "antenna height y (mm)"};
    uwb_draw_axes(&c, &plot, &axes);
    draw_range_axis(&c, &plot, scan, s);
    draw_signed_colorbar(&c, bar_x, plot.y, bar_w, plot.h, o.bscan_floor_db, s);
    uwb_draw_edge_legend(&c, plot.x, uwb_layout_legend_y(&plot, s), v && v->current.found,
                         v && v->has_baseline && v->baseline.found, s);

    return uwb_canvas_save_with_verdict(&c, path, short_title, v, o.provenance, err, errlen);
}
