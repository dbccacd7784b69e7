/* The trend PNG (see output/render_trend.h): displacement over time with
 * 2-sigma bars, the radial change as a second series, the thresholds,
 * baseline changes, and the verdicts that have no figure shown as marks
 * of their own. */
#include "output/render_trend.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "uwb/version.h"

#define FONT_SCALE 2
#define MARGIN_LEFT 110
#define MARGIN_RIGHT 30
#define MARGIN_BOTTOM 80
#define STRIP_H 22
#define MARKER 4 /* half-size of a figure's square, px */
#define CAP 5    /* half-width of a bar's cap, px */
#define X_TICKS 6
#define ZONE_TINT 0.12 /* the zones' colour over the white page */

static const struct uwb_rgb white = {255, 255, 255};
static const struct uwb_rgb ink = {25, 25, 25};
static const struct uwb_rgb muted = {90, 90, 90};
static const struct uwb_rgb rule = {170, 170, 170};
static const struct uwb_rgb zero_grey = {200, 200, 200};
static const struct uwb_rgb series_grey = {150, 150, 150};
static const struct uwb_rgb strip_fill = {242, 242, 242};
static const struct uwb_rgb baseline_ink = {150, 20, 110};
static const struct uwb_rgb radial_line = {130, 195, 205};
const struct uwb_rgb UWB_TREND_RADIAL_INK = {0, 120, 140};

static double mm_per_year(double mm_per_day)
{
    return mm_per_day * 365.25;
}

static int line_step(int scale)
{
    return UWB_FONT_LINE_HEIGHT * scale + 3;
}

/* An ok, watch or alarm verdict without an axial figure: its status is
 * the radial change's (the axial figure was withheld), not an
 * inconclusive one. */
static int axial_withheld(const struct uwb_trend_entry *p)
{
    return !p->summary.has_displacement &&
           (p->summary.status == UWB_STATUS_OK || p->summary.status == UWB_STATUS_WATCH ||
            p->summary.status == UWB_STATUS_ALARM);
}

static void count_kinds(const struct uwb_trend *t, int *figures, int *inconclusive, int *errors, int *edges,
                        int *withheld, int *undated)
{
    *figures = *inconclusive = *errors = *edges = *withheld = *undated = 0;
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *p = &t->entries[i];
        *undated += !p->has_time;
        if (p->summary.has_displacement)
            ++*figures;
        else if (p->summary.status == UWB_STATUS_ERROR)
            ++*errors;
        else if (p->summary.status == UWB_STATUS_EDGES)
            ++*edges;
        else if (axial_withheld(p))
            ++*withheld;
        else
            ++*inconclusive;
    }
}

static const struct uwb_trend_entry *latest(const struct uwb_trend *t)
{
    return t->count > 0 ? &t->entries[t->count - 1] : NULL;
}

/* The latest verdict in words, ASCII (sep is "+/-" or the font's "±"). */
static void describe_point(const struct uwb_trend_entry *p, const char *sep, char *buf, size_t len)
{
    if (!p)
        snprintf(buf, len, "no verdict yet");
    else if (p->summary.has_displacement)
        snprintf(buf, len, "%s %+.2f %s %.2f mm (1 sigma)", uwb_status_name(p->summary.status),
                 p->summary.axial_displacement_mm, sep, p->summary.uncertainty_mm);
    else if (p->summary.status == UWB_STATUS_EDGES)
        snprintf(buf, len, "edges only (%s)", p->became_baseline ? "became the baseline" : "no baseline");
    else
        snprintf(buf, len, "%s, no figure%s%s", uwb_status_name(p->summary.status),
                 p->summary.reason[0] ? ": " : "", p->summary.reason);
}

static void describe_rate(const struct uwb_trend *t, const char *sep, char *buf, size_t len)
{
    if (t->rate.known)
        snprintf(buf, len, "%+.2f %s %.2f mm/year (1 sigma), %d figures over %.1f days since the baseline",
                 mm_per_year(t->rate.mm_per_day), sep, mm_per_year(t->rate.sigma_mm_per_day), t->rate.points,
                 t->rate.days);
    else
        snprintf(buf, len, "not known yet: %s", t->rate.withheld);
}

/* The radial series: how many figures, and the latest (NULL: none). */
static const struct uwb_trend_entry *latest_radial(const struct uwb_trend *t, int *figures)
{
    const struct uwb_trend_entry *last = NULL;
    *figures = 0;
    for (int i = 0; i < t->count; i++)
        if (t->entries[i].summary.radial_measured) {
            last = &t->entries[i];
            ++*figures;
        }
    return last;
}

static void describe_radial(const struct uwb_trend *t, const char *sep, char *buf, size_t len)
{
    int figures;
    const struct uwb_trend_entry *q = latest_radial(t, &figures);
    buf[0] = '\0';
    if (q)
        snprintf(buf, len, "%d radial figure%s, latest %+.2f %s %.2f mm (%s)", figures,
                 figures == 1 ? "" : "s", q->summary.radial_max_change_mm, sep,
                 q->summary.radial_uncertainty_mm, uwb_status_name(q->summary.radial_status));
}

void uwb_trend_summary(const struct uwb_trend *t, const struct uwb_thresholds *th, char *buf, size_t len)
{
    int figures, inconclusive, errors, edges, withheld, undated;
    count_kinds(t, &figures, &inconclusive, &errors, &edges, &withheld, &undated);
    char last[400], rate[200];
    describe_point(latest(t), "+/-", last, sizeof last);
    describe_rate(t, "+/-", rate, sizeof rate);
    char radial[160];
    describe_radial(t, "+/-", radial, sizeof radial);
    const struct uwb_trend_entry *p = latest(t);
    snprintf(buf, len,
             "%d verdicts: %d with a figure, %d inconclusive, %d error, %d edges only, %d with the axial "
             "figure withheld; latest %s: %s; "
             "rate %s; %s%sthresholds watch %.2f mm, alarm %.2f mm; bars +/-%.0f sigma (95 %%)",
             t->count, figures, inconclusive, errors, edges, withheld,
             p && p->summary.created[0] ? p->summary.created : "(none)", last, rate, radial,
             radial[0] ? "; " : "", th->watch_m * 1e3, th->alarm_m * 1e3, UWB_TREND_BAR_SIGMAS);
}

static int first_last_time(const struct uwb_trend *t, time_t *first, time_t *last)
{
    int any = 0;
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *p = &t->entries[i];
        if (!p->has_time)
            continue;
        if (!any || p->t < *first)
            *first = p->t;
        if (!any || p->t > *last)
            *last = p->t;
        any = 1;
    }
    return any;
}

/* text from (x, y), wrapped as the images' captions are
 * (uwb_wrap_line_length), so nothing runs off the page. Drawn when c is
 * set; returns the height it takes. */
static int wrapped_text(struct uwb_canvas *c, int x, int y, const char *text, int scale,
                        struct uwb_rgb colour, int max_w)
{
    int height = 0;
    while (*text) {
        size_t fit = uwb_wrap_line_length(text, max_w, scale);
        char line[512];
        snprintf(line, sizeof line, "%.*s", (int)fit, text);
        if (c)
            uwb_draw_text(c, x, y + height, line, scale, colour);
        height += line_step(scale);
        text += fit;
        while (*text == ' ')
            text++;
    }
    return height > 0 ? height : line_step(scale);
}

/* The marks of the verdicts without an axial figure, in the strip and in
 * the caption's key (the manual's words for them). */
static const struct {
    const char *mark, *words;
    enum uwb_status colour;
} marks[] = {
    {"?", "inconclusive", UWB_STATUS_INCONCLUSIVE},
    {"X", "error", UWB_STATUS_ERROR},
    {"B", "became the baseline", UWB_STATUS_EDGES},
    {"E", "edges only", UWB_STATUS_EDGES},
    {"R", "axial figure withheld (radial only)", UWB_STATUS_ALARM},
};

static const char *mark_of(const struct uwb_trend_entry *q)
{
    return q->summary.status == UWB_STATUS_ERROR   ? "X"
           : q->became_baseline                    ? "B"
           : q->summary.status == UWB_STATUS_EDGES ? "E"
           : axial_withheld(q)                     ? "R"
                                                   : "?";
}

/* "no axial figure:  ? inconclusive   X error ...", each mark in its
 * colour, wrapped onto a second line where the page is too narrow. */
static int marks_key(struct uwb_canvas *c, int x, int y, int scale)
{
    const char *head = "strip above the plot, no axial figure:";
    int right = UWB_TREND_PNG_WIDTH - 12, lx = x, gap = 3 * UWB_FONT_ADVANCE * scale;
    if (c)
        uwb_draw_text(c, lx, y, head, scale, muted);
    lx += uwb_text_width(head, scale) + gap;
    int height = line_step(scale);
    for (size_t i = 0; i < sizeof marks / sizeof marks[0]; i++) {
        int w = uwb_text_width(marks[i].mark, scale) + UWB_FONT_ADVANCE * scale +
                uwb_text_width(marks[i].words, scale);
        if (lx + w > right) {
            lx = x + uwb_text_width("latest  ", scale);
            y += line_step(scale);
            height += line_step(scale);
        }
        if (c) {
            uwb_draw_text(c, lx, y, marks[i].mark, scale, uwb_status_colour(marks[i].colour));
            uwb_draw_text(c, lx + uwb_text_width(marks[i].mark, scale) + UWB_FONT_ADVANCE * scale, y,
                          marks[i].words, scale, ink);
        }
        lx += w + gap;
    }
    return height;
}

/* Caption lines: title, site, latest, rate, legend. Drawn when c is set;
 * returns the height either way so layout and drawing agree. */
static int caption(struct uwb_canvas *c, const struct uwb_trend *t, const struct uwb_thresholds *th,
                   const char *site)
{
    int scale = FONT_SCALE, x = 12, y = 10;
    char a[700], b[600];
    if (c)
        uwb_draw_text(c, x, y, "uwbd trend: axial displacement and radial change", scale + 1, ink);
    y += UWB_FONT_LINE_HEIGHT * (scale + 1) + 6;
    int label_w = uwb_text_width("latest  ", scale);
    int text_w = UWB_TREND_PNG_WIDTH - x - label_w - x;
    if (site && site[0]) {
        if (c) {
            uwb_draw_text(c, x, y, "asset", scale, muted);
            uwb_draw_text(c, x + label_w, y, site, scale, ink);
        }
        y += line_step(scale);
    }
    const struct uwb_trend_entry *p = latest(t);
    if (c)
        uwb_draw_text(c, x, y, "latest", scale, muted);
    describe_point(p, "\u00b1", b, sizeof b);
    snprintf(a, sizeof a, "%s  %s", p && p->summary.created[0] ? p->summary.created : "", b);
    y += wrapped_text(c, x + label_w, y, a, scale, p ? uwb_status_colour(p->summary.status) : ink, text_w);
    if (c)
        uwb_draw_text(c, x, y, "rate", scale, muted);
    describe_rate(t, "\u00b1", a, sizeof a);
    y += wrapped_text(c, x + label_w, y, a, scale, ink, text_w);
    describe_radial(t, "\u00b1", b, sizeof b);
    if (b[0]) {
        if (c)
            uwb_draw_text(c, x, y, "radial", scale, UWB_TREND_RADIAL_INK);
        snprintf(a, sizeof a, "%s; diamonds, + toward the antenna", b);
        y += wrapped_text(c, x + label_w, y, a, scale, UWB_TREND_RADIAL_INK, text_w);
    }
    if (c) {
        /* Legend: a sample of each line next to what it means. */
        int lx = x, mid = y + UWB_FONT_CAP_HEIGHT * scale / 2;
        uwb_canvas_fill_rect(c, lx + 6, y - 2, 1, UWB_FONT_CAP_HEIGHT * scale + 4, ink);
        uwb_canvas_fill_rect(c, lx + 6 - CAP, y - 2, 2 * CAP + 1, 1, ink);
        uwb_canvas_fill_rect(c, lx + 6 - CAP, y + UWB_FONT_CAP_HEIGHT * scale + 1, 2 * CAP + 1, 1, ink);
        lx += 18;
        snprintf(a, sizeof a, "\u00b1%.0f sigma (95 %%)", UWB_TREND_BAR_SIGMAS);
        lx += uwb_draw_text(c, lx, y, a, scale, ink) + 24;
        uwb_canvas_line(c, lx, mid, lx + 28, mid, uwb_status_colour(UWB_STATUS_WATCH), 2, 6, 4);
        lx += 34;
        snprintf(a, sizeof a, "watch \u00b1%.2g mm", th->watch_m * 1e3);
        lx += uwb_draw_text(c, lx, y, a, scale, ink) + 24;
        uwb_canvas_line(c, lx, mid, lx + 28, mid, uwb_status_colour(UWB_STATUS_ALARM), 2, 0, 0);
        lx += 34;
        snprintf(a, sizeof a, "alarm \u00b1%.2g mm", th->alarm_m * 1e3);
        lx += uwb_draw_text(c, lx, y, a, scale, ink) + 24;
        uwb_canvas_line(c, lx + 4, y - 2, lx + 4, y + UWB_FONT_CAP_HEIGHT * scale + 2, baseline_ink, 1, 3, 3);
        lx += 12;
        uwb_draw_text(c, lx, y, "new baseline", scale, ink);
    }
    y += line_step(scale);
    y += marks_key(c, x, y, scale) + 4;
    if (c)
        uwb_canvas_fill_rect(c, 0, y - 4, c->width, 1, rule);
    return y;
}

void uwb_render_trend_layout(const struct uwb_trend *t, const struct uwb_thresholds *th, const char *site,
                             struct uwb_trend_layout *out)
{
    memset(out, 0, sizeof *out);
    out->caption_h = caption(NULL, t, th, site);
    out->strip_y = out->caption_h + 6;
    out->strip_h = STRIP_H;
    struct uwb_plot *p = &out->plot;
    p->x = MARGIN_LEFT;
    p->y = out->strip_y + out->strip_h + 8;
    p->w = UWB_TREND_PNG_WIDTH - MARGIN_LEFT - MARGIN_RIGHT;
    p->h = UWB_TREND_PNG_HEIGHT - p->y - MARGIN_BOTTOM;

    time_t first = 0, last = 0;
    out->unit_s = 86400.0;
    if (first_last_time(t, &first, &last)) {
        out->t_ref = first - first % 86400;
        /* A short trend at its own scale: hours under two days, minutes
         * under two hours, and a margin of a few percent (a quarter of a
         * unit when the figures are all at one time). */
        if (last - first < (time_t)2 * 86400)
            out->unit_s = 3600.0;
        if (last - first < (time_t)2 * 3600)
            out->unit_s = 60.0;
        double span = (double)(last - first) / out->unit_s;
        double pad = fmax(0.04 * span, 0.25);
        p->x_min = (double)(first - out->t_ref) / out->unit_s - pad;
        p->x_max = (double)(last - out->t_ref) / out->unit_s + pad;
    } else {
        p->x_min = 0;
        p->x_max = 1;
    }
    /* Symmetric about zero, so "up" and "down" look alike, and always
     * wide enough for the alarm lines. */
    double lim = fmax(th->alarm_m * 1e3 * 1.25, 1.0);
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *q = &t->entries[i];
        if (q->summary.has_displacement)
            lim = fmax(lim, 1.1 * (fabs(q->summary.axial_displacement_mm) +
                                   UWB_TREND_BAR_SIGMAS * q->summary.uncertainty_mm));
        if (q->summary.radial_measured)
            lim = fmax(lim, 1.1 * (fabs(q->summary.radial_max_change_mm) +
                                   UWB_TREND_BAR_SIGMAS * q->summary.radial_uncertainty_mm));
    }
    p->y_min = -lim;
    p->y_max = lim;
}

int uwb_trend_col(const struct uwb_trend_layout *l, time_t when)
{
    return uwb_plot_col(&l->plot, (double)(when - l->t_ref) / l->unit_s);
}

static void hline(struct uwb_canvas *c, const struct uwb_plot *p, double y, struct uwb_rgb colour,
                  int dash_on, int dash_off)
{
    int row = uwb_plot_row(p, y);
    uwb_canvas_line(c, p->x, row, p->x + p->w - 1, row, colour, 1, dash_on, dash_off);
}

static void thresholds(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_thresholds *th)
{
    hline(c, p, 0.0, zero_grey, 0, 0);
    for (int sign = -1; sign <= 1; sign += 2) {
        hline(c, p, sign * th->watch_m * 1e3, uwb_status_colour(UWB_STATUS_WATCH), 6, 4);
        hline(c, p, sign * th->alarm_m * 1e3, uwb_status_colour(UWB_STATUS_ALARM), 0, 0);
    }
    int right = p->x + p->w - 4;
    int w = uwb_text_width("watch", 1);
    uwb_draw_text(c, right - w, uwb_plot_row(p, th->watch_m * 1e3) - UWB_FONT_CAP_HEIGHT - 3, "watch", 1,
                  uwb_status_colour(UWB_STATUS_WATCH));
    w = uwb_text_width("alarm", 1);
    uwb_draw_text(c, right - w, uwb_plot_row(p, th->alarm_m * 1e3) - UWB_FONT_CAP_HEIGHT - 3, "alarm", 1,
                  uwb_status_colour(UWB_STATUS_ALARM));
}

/* A verdict without a figure: its letter in the strip, in its colour. */
static void no_figure_mark(struct uwb_canvas *c, const struct uwb_trend_layout *l,
                           const struct uwb_trend_entry *q)
{
    /* ? inconclusive, X error, B became the baseline, E edges only, R
     * the axial figure withheld (the status is the radial change's). */
    const char *mark = mark_of(q);
    int col = uwb_trend_col(l, q->t);
    int w = uwb_text_width(mark, FONT_SCALE);
    uwb_draw_text(c, col - w / 2, l->strip_y + (l->strip_h - UWB_FONT_CAP_HEIGHT * FONT_SCALE) / 2, mark,
                  FONT_SCALE, uwb_status_colour(q->summary.status));
}

static void figure(struct uwb_canvas *c, const struct uwb_plot *p, int col, const struct uwb_trend_entry *q)
{
    double bar = UWB_TREND_BAR_SIGMAS * q->summary.uncertainty_mm;
    int top = uwb_plot_row(p, q->summary.axial_displacement_mm + bar),
        bottom = uwb_plot_row(p, q->summary.axial_displacement_mm - bar);
    int row = uwb_plot_row(p, q->summary.axial_displacement_mm);
    uwb_canvas_line(c, col, top, col, bottom, ink, 1, 0, 0);
    uwb_canvas_line(c, col - CAP, top, col + CAP, top, ink, 1, 0, 0);
    uwb_canvas_line(c, col - CAP, bottom, col + CAP, bottom, ink, 1, 0, 0);
    uwb_canvas_fill_rect(c, col - MARKER, row - MARKER, 2 * MARKER + 1, 2 * MARKER + 1,
                         uwb_status_colour(q->summary.status));
    uwb_canvas_frame_rect(c, col - MARKER, row - MARKER, 2 * MARKER + 1, 2 * MARKER + 1, ink);
}

/* A radial figure: its bar in the radial ink, a diamond in its status colour. */
static void radial_figure(struct uwb_canvas *c, const struct uwb_plot *p, int col,
                          const struct uwb_trend_entry *q)
{
    double bar = UWB_TREND_BAR_SIGMAS * q->summary.radial_uncertainty_mm;
    int top = uwb_plot_row(p, q->summary.radial_max_change_mm + bar),
        bottom = uwb_plot_row(p, q->summary.radial_max_change_mm - bar);
    int row = uwb_plot_row(p, q->summary.radial_max_change_mm);
    uwb_canvas_line(c, col, top, col, bottom, UWB_TREND_RADIAL_INK, 1, 0, 0);
    uwb_canvas_line(c, col - CAP, top, col + CAP, top, UWB_TREND_RADIAL_INK, 1, 0, 0);
    uwb_canvas_line(c, col - CAP, bottom, col + CAP, bottom, UWB_TREND_RADIAL_INK, 1, 0, 0);
    int r = MARKER + 1;
    for (int dy = -r; dy <= r; dy++) {
        int half = r - (dy < 0 ? -dy : dy);
        uwb_canvas_fill_rect(c, col - half, row + dy, 2 * half + 1, 1, UWB_TREND_RADIAL_INK);
        if (half > 0)
            uwb_canvas_fill_rect(c, col - half + 1, row + dy, 2 * half - 1, 1,
                                 uwb_status_colour(q->summary.radial_status));
    }
}

static void x_labels(struct uwb_canvas *c, const struct uwb_trend_layout *l, const struct uwb_trend *t)
{
    const struct uwb_plot *p = &l->plot;
    double ticks[64], step;
    int n = uwb_nice_ticks(p->x_min, p->x_max, X_TICKS, ticks, 64, &step);
    int days = l->unit_s >= 86400.0, last_right = -1000000;
    for (int i = 0; i < n; i++) {
        if (days && fabs(ticks[i] - round(ticks[i])) > 1e-6)
            continue; /* half days: a tick, no date */
        time_t when = l->t_ref + (time_t)llround(ticks[i] * l->unit_s);
        struct tm tm;
        char label[32];
        gmtime_r(&when, &tm);
        /* Seconds only where a tick falls between whole minutes. */
        const char *format = days ? "%m-%d" : fmod(step * l->unit_s, 60.0) > 1e-6 ? "%H:%M:%S" : "%H:%M";
        strftime(label, sizeof label, format, &tm);
        int col = uwb_plot_col(p, ticks[i]);
        int w = uwb_text_width(label, FONT_SCALE);
        /* A label the page would cut ("03:23:3") or that would run into
         * the one before: the tick alone. */
        int x = col - w / 2;
        if (x < 4 || x + w > c->width - 4 || x < last_right + 2 * UWB_FONT_ADVANCE * FONT_SCALE)
            continue;
        uwb_draw_text(c, x, p->y + p->h + 6 + 4, label, FONT_SCALE, ink);
        last_right = x + w;
    }
    char title[96];
    time_t first = 0, last = 0;
    if (first_last_time(t, &first, &last)) {
        struct tm a, b;
        gmtime_r(&first, &a);
        gmtime_r(&last, &b);
        if (days && a.tm_year == b.tm_year)
            snprintf(title, sizeof title, "date (UTC), %d", a.tm_year + 1900);
        else if (days)
            snprintf(title, sizeof title, "date (UTC), %d to %d", a.tm_year + 1900, b.tm_year + 1900);
        else
            snprintf(title, sizeof title, "time (UTC) from %04d-%02d-%02d", a.tm_year + 1900, a.tm_mon + 1,
                     a.tm_mday);
    } else {
        snprintf(title, sizeof title, "no dated verdicts");
    }
    int w = uwb_text_width(title, FONT_SCALE);
    uwb_draw_text(c, p->x + (p->w - w) / 2, p->y + p->h + 6 + 4 + UWB_FONT_CAP_HEIGHT * FONT_SCALE + 12,
                  title, FONT_SCALE, ink);
}

/* The longest y-axis title that fits the plot's height: one that runs
 * past it reaches into the strip's "no figure". */
static const char *y_title(int radial_figures, int plot_h)
{
    static const char *const axial[] = {"displacement, mm (up +)", "mm (up +)", "mm"};
    static const char *const both[] = {"mm (up +, radial nearer +)", "mm (+ up/nearer)", "mm"};
    const char *const *titles = radial_figures ? both : axial;
    for (int i = 0; i < 2; i++)
        if (uwb_text_width(titles[i], FONT_SCALE) <= plot_h - 4)
            return titles[i];
    return titles[2];
}

static void draw(struct uwb_canvas *c, const struct uwb_trend *t, const struct uwb_thresholds *th,
                 const char *site)
{
    struct uwb_trend_layout l;
    uwb_render_trend_layout(t, th, site, &l);
    const struct uwb_plot *p = &l.plot;
    caption(c, t, th, site);

    uwb_canvas_fill_rect(c, p->x, l.strip_y, p->w, l.strip_h, strip_fill);
    uwb_draw_text(c, 8, l.strip_y + (l.strip_h - UWB_FONT_CAP_HEIGHT) / 2, "no figure", 1, muted);
    /* The watch and alarm zones tinted (the lines bound them), as in the
     * comparison image: a figure in the red is an alarm. */
    uwb_tint_threshold_zones(c, p, 0.0, th, 1000.0, ZONE_TINT);
    thresholds(c, p, th);

    /* Baseline changes first, so the figures stay on top of them. */
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *q = &t->entries[i];
        if (!q->baseline_change || !q->has_time)
            continue;
        int col = uwb_trend_col(&l, q->t);
        uwb_canvas_line(c, col, l.strip_y, col, p->y + p->h - 1, baseline_ink, 1, 3, 3);
    }
    /* A thin line joins the figures of one baseline; a new baseline
     * starts a new line (its figures are against another reference). */
    int prev_col = 0, prev_row = 0, have_prev = 0;
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *q = &t->entries[i];
        if (q->baseline_change)
            have_prev = 0;
        if (!q->has_time)
            continue;
        if (!q->summary.has_displacement) {
            have_prev = 0; /* a verdict without a figure between: no line across it */
            continue;
        }
        int col = uwb_trend_col(&l, q->t), row = uwb_plot_row(p, q->summary.axial_displacement_mm);
        if (have_prev)
            uwb_canvas_line(c, prev_col, prev_row, col, row, series_grey, 1, 0, 0);
        prev_col = col;
        prev_row = row;
        have_prev = 1;
    }
    /* The radial series likewise, beside the axial one. */
    have_prev = 0;
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *q = &t->entries[i];
        if (q->baseline_change)
            have_prev = 0;
        if (!q->has_time)
            continue;
        if (!q->summary.radial_measured) {
            have_prev = 0;
            continue;
        }
        int col = uwb_trend_col(&l, q->t) + UWB_TREND_RADIAL_OFFSET,
            row = uwb_plot_row(p, q->summary.radial_max_change_mm);
        if (have_prev)
            uwb_canvas_line(c, prev_col, prev_row, col, row, radial_line, 1, 0, 0);
        prev_col = col;
        prev_row = row;
        have_prev = 1;
    }
    for (int i = 0; i < t->count; i++) {
        const struct uwb_trend_entry *q = &t->entries[i];
        if (!q->has_time)
            continue;
        if (q->summary.has_displacement)
            figure(c, p, uwb_trend_col(&l, q->t), q);
        else
            no_figure_mark(c, &l, q);
        if (q->summary.radial_measured)
            radial_figure(c, p, uwb_trend_col(&l, q->t) + UWB_TREND_RADIAL_OFFSET, q);
    }
    int radial_figures;
    latest_radial(t, &radial_figures);
    struct uwb_axis_style style = {
        .x_label_scale = 1.0,
        .y_label_scale = 1.0,
        .font_scale = FONT_SCALE,
        .x_ticks = X_TICKS,
        .y_ticks = p->h / 40 > 3 ? p->h / 40 : 3, /* labels at least 40 px apart: none touch */
        .x_labels = 0,
        .y_labels_left = 1,
        .y_title = y_title(radial_figures, p->h),
    };
    uwb_draw_axes(c, p, &style);
    x_labels(c, &l, t);
    if (t->count == 0) {
        const char *none = "no verdicts yet";
        int w = uwb_text_width(none, FONT_SCALE);
        uwb_draw_text(c, p->x + (p->w - w) / 2, p->y + p->h / 3, none, FONT_SCALE, muted);
    }
}

int uwb_render_trend_png(const char *path, const struct uwb_trend *t, const struct uwb_thresholds *th,
                         const char *site, char *err, size_t errlen)
{
    struct uwb_canvas c;
    if (uwb_canvas_init(&c, UWB_TREND_PNG_WIDTH, UWB_TREND_PNG_HEIGHT, white, err, errlen) != 0)
        return -1;
    draw(&c, t, th, site);
    char summary[1400];
    uwb_trend_summary(t, th, summary, sizeof summary);
    /* The description is ASCII ("+/-", "sigma"); a site label may be UTF-8,
     * which uwb_canvas_write_png stores as iTXt (tEXt is Latin-1). */
    struct uwb_png_text texts[] = {
        {"Title", "uwbd trend: axial displacement and radial change"},
        {"Description", summary},
        {"Asset", site && site[0] ? site : NULL},
        {"Software", "uwbd " UWBD_VERSION},
    };
    int rc = uwb_canvas_write_png(&c, path, texts, 4, err, errlen);
    uwb_canvas_free(&c);
    return rc;
}
