/* The watch and alarm thresholds on the images that show a displacement:
 * the displacement is this scan's winding centre minus the baseline's, so
 * the thresholds are heights around the baseline centre; at the images'
 * height scale (800 mm of travel in 500 px) a 5 mm threshold is 3 px, so
 * every caption carries a line naming the thresholds in their zones'
 * colours and a displacement meter on its own scale: zones coloured, the
 * displacement and its 95 % interval marked. The trend, whose axis is the
 * displacement, tints the zones on the plot itself. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

enum uwb_status uwb_threshold_zone(double displacement_m, const struct uwb_thresholds *th)
{
    double d = fabs(displacement_m);
    if (d >= th->alarm_m)
        return UWB_STATUS_ALARM;
    if (d >= th->watch_m)
        return UWB_STATUS_WATCH;
    return UWB_STATUS_OK;
}

int uwb_thresholds_usable(const struct uwb_thresholds *th)
{
    return th && isfinite(th->watch_m) && isfinite(th->alarm_m) && th->watch_m > 0.0 &&
           th->alarm_m >= th->watch_m;
}

static unsigned char mix(unsigned char a, unsigned char b, double alpha)
{
    return (unsigned char)lround(a + (b - a) * alpha);
}

struct uwb_rgb uwb_rgb_blend(struct uwb_rgb under, struct uwb_rgb over, double alpha)
{
    struct uwb_rgb c = {mix(under.r, over.r, alpha), mix(under.g, over.g, alpha),
                        mix(under.b, over.b, alpha)};
    return c;
}

void uwb_tint_threshold_zones(struct uwb_canvas *c, const struct uwb_plot *p, double centre,
                              const struct uwb_thresholds *th, double data_per_m, double alpha)
{
    if (!uwb_thresholds_usable(th) || !isfinite(centre))
        return;
    for (int row = p->y; row < p->y + p->h; row++) {
        double y = p->y_max - (double)(row - p->y) / (p->h > 1 ? p->h - 1 : 1) * (p->y_max - p->y_min);
        enum uwb_status zone = uwb_threshold_zone((y - centre) / data_per_m, th);
        if (zone == UWB_STATUS_OK)
            continue;
        struct uwb_rgb tint = uwb_status_colour(zone);
        for (int x = p->x; x < p->x + p->w; x++)
            uwb_canvas_put(c, x, row, uwb_rgb_blend(uwb_canvas_get(c, x, row), tint, alpha));
    }
}

/* The displacement meter: a bar from -half_range to +half_range of
 * displacement, coloured by zone, with this scan's displacement and its
 * 95 % interval marked. On the images' own height scale the zones are a
 * few pixels (5 mm of 800); the meter gives them room. */
void uwb_meter_layout(const struct uwb_meter_figure *f, const struct uwb_thresholds *th, int x, int y, int w,
                      int h, struct uwb_meter *m)
{
    m->x = x;
    m->y = y;
    m->w = w;
    m->h = h;
    double half = 1.6 * th->alarm_m;
    if (f->measured)
        half = fmax(half, 1.1 * (fabs(f->value_m) + UWB_SIGMAS_95 * f->sigma_m));
    m->half_range_m = half;
}

int uwb_meter_col(const struct uwb_meter *m, double displacement_m)
{
    double t = (displacement_m + m->half_range_m) / (2.0 * m->half_range_m);
    return m->x + (int)lround(t * (m->w - 1));
}

void uwb_draw_meter(struct uwb_canvas *c, const struct uwb_meter *m, const struct uwb_meter_figure *f,
                    const struct uwb_thresholds *th)
{
    for (int col = 0; col < m->w; col++) {
        double d = -m->half_range_m + 2.0 * m->half_range_m * col / (m->w > 1 ? m->w - 1 : 1);
        uwb_canvas_fill_rect(c, m->x + col, m->y, 1, m->h, uwb_status_colour(uwb_threshold_zone(d, th)));
    }
    static const struct uwb_rgb ink = {25, 25, 25};
    uwb_canvas_fill_rect(c, uwb_meter_col(m, 0.0), m->y, 1, m->h, UWB_RGB_HALO); /* zero */
    if (!f->measured)
        return;
    /* The 95 % interval as a bar with caps across the middle, the figure
     * as a tall mark, both on a white halo so they read on any zone. */
    int mid = m->y + m->h / 2;
    int a = uwb_meter_col(m, f->value_m - UWB_SIGMAS_95 * f->sigma_m);
    int b = uwb_meter_col(m, f->value_m + UWB_SIGMAS_95 * f->sigma_m);
    int d = uwb_meter_col(m, f->value_m);
    uwb_canvas_fill_rect(c, a - 1, mid - 2, b - a + 3, 5, UWB_RGB_HALO);
    uwb_canvas_fill_rect(c, d - 2, m->y - 4, 5, m->h + 8, UWB_RGB_HALO);
    uwb_canvas_fill_rect(c, a, mid - 1, b - a + 1, 3, ink);
    uwb_canvas_fill_rect(c, a, mid - 3, 1, 7, ink);
    uwb_canvas_fill_rect(c, b, mid - 3, 1, 7, ink);
    uwb_canvas_fill_rect(c, d - 1, m->y - 3, 3, m->h + 6, ink);
}

int uwb_meter_labels_height(int scale)
{
    return UWB_FONT_CAP_HEIGHT * scale + 6;
}

/* A limit in mm with its sign and without trailing zeros: 2.00 -> "+2",
 * -2.50 -> "-2.5" (unsigned, "5 2 0 2 5" read as one scale of
 * magnitudes, and crowded as "202"). */
static void format_mm(char *buf, size_t len, double metres)
{
    snprintf(buf, len, "%+.2f", metres * 1e3);
    char *dot = strchr(buf, '.');
    if (!dot)
        return;
    char *end = buf + strlen(buf) - 1;
    while (end > dot && *end == '0')
        *end-- = '\0';
    if (end == dot)
        *end = '\0';
}

struct label_row {
    int lo[8], hi[8], n;
};

/* Draw `text` centred on col (kept within the canvas) unless it would
 * come within two glyphs of a label already drawn (closer, "2", "0" and
 * "2" read as "202"): on a narrow meter the figure and the alarm limits
 * matter more than the watch limits, so they are drawn first. */
static void place_label(struct uwb_canvas *c, struct label_row *row, int col, int y, const char *text,
                        int scale, struct uwb_rgb colour)
{
    int w = uwb_text_width(text, scale), x = col - w / 2, gap = 2 * UWB_FONT_ADVANCE * scale;
    if (x + w > c->width - 2)
        x = c->width - 2 - w;
    if (x < 0)
        x = 0;
    for (int i = 0; i < row->n; i++)
        if (x < row->hi[i] + gap && x + w + gap > row->lo[i])
            return;
    if (row->n < 8) {
        row->lo[row->n] = x;
        row->hi[row->n] = x + w;
        row->n++;
    }
    uwb_draw_text(c, x, y, text, scale, colour);
}

void uwb_draw_meter_labels(struct uwb_canvas *c, const struct uwb_meter *m, const struct uwb_meter_figure *f,
                           const struct uwb_thresholds *th, int scale)
{
    static const struct uwb_rgb ink = {25, 25, 25};
    struct label_row row = {{0}, {0}, 0};
    int y = m->y + m->h + 5;
    char text[32];
    if (f->measured) {
        uwb_format_signed(text, sizeof text, f->value_m * 1e3, 2);
        place_label(c, &row, uwb_meter_col(m, f->value_m), y, text, scale, ink);
    }
    /* The zones are of |displacement|: each limit is named with its sign
     * on both sides of zero. */
    const struct {
        double at_m;
        enum uwb_status zone;
    } limit[] = {{th->alarm_m, UWB_STATUS_ALARM}, {th->watch_m, UWB_STATUS_WATCH}};
    for (size_t i = 0; i < sizeof limit / sizeof limit[0]; i++)
        for (int side = 1; side >= -1; side -= 2) {
            format_mm(text, sizeof text, side * limit[i].at_m);
            place_label(c, &row, uwb_meter_col(m, side * limit[i].at_m), y, text, scale,
                        uwb_status_colour(limit[i].zone));
        }
    place_label(c, &row, uwb_meter_col(m, 0.0), y, "0", scale, ink);
}
