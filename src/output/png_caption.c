/* The caption every PNG carries, so the picture alone says which scan,
 * when, and what uwbd concluded: title, scan id and time, baseline id,
 * the verdict with displacement +/- uncertainty, and the edges in mm. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "uwb/version.h"

static const struct uwb_rgb ink = {25, 25, 25};
static const struct uwb_rgb muted = {90, 90, 90};
static const struct uwb_rgb rule = {170, 170, 170};
static const struct uwb_rgb white = {255, 255, 255};
static const struct uwb_rgb baseline_ink = {150, 20,
                                            110}; /* a darker UWB_RGB_BASELINE_EDGE, readable on white */

#define MM(m) ((m)*1000.0)

#define CAPTION_TOP 10
#define TITLE_GAP 6

static int line_step(int scale)
{
    return UWB_FONT_LINE_HEIGHT * scale + 3;
}

static const char *or_unknown(const char *s)
{
    return s && *s ? s : "(unknown)";
}

/* The verdict's scan id, else the name the caller knows the scan by (a
 * replayed file's stem), else "(unknown)". */
static const char *scan_name(const struct uwb_verdict *v, const struct uwb_provenance *prov)
{
    if (v && v->scan_id[0])
        return v->scan_id;
    return or_unknown(prov ? prov->scan_name : NULL);
}

void uwb_describe_provenance(const struct uwb_verdict *v, const struct uwb_provenance *prov, char *buf,
                             size_t len)
{
    char stack[48] = "", eps[48] = "", snr[48] = "";
    if (prov && prov->stack > 0)
        snprintf(stack, sizeof stack, "   stack %d pulses/position", prov->stack);
    if (prov && prov->eps_r > 0.0 && isfinite(prov->eps_r))
        snprintf(eps, sizeof eps, "   eps_r %.2f", prov->eps_r);
    if (v && isfinite(v->current.snr_db) && (v->current.found || v->current.snr_db != 0.0))
        snprintf(snr, sizeof snr, "   SNR %.1f dB", v->current.snr_db);
    snprintf(buf, len, "asset %s%s%s%s   uwbd %s",
             prov && prov->asset && prov->asset[0] ? prov->asset : "(not set)", stack, eps, snr,
             UWBD_VERSION);
}

static void upper_case(char *dst, size_t len, const char *src)
{
    size_t i = 0;
    for (; src && src[i] && i + 1 < len; i++)
        dst[i] = (src[i] >= 'a' && src[i] <= 'z') ? (char)(src[i] - 'a' + 'A') : src[i];
    if (len)
        dst[i] = '\0';
}

static int displacement_known(const struct uwb_verdict *v)
{
    return v->has_baseline && !v->axial_withheld &&
           (v->status == UWB_STATUS_OK || v->status == UWB_STATUS_WATCH || v->status == UWB_STATUS_ALARM) &&
           v->current.found && v->baseline.found;
}

int uwb_displacement_measured(const struct uwb_verdict *v)
{
    return v && displacement_known(v);
}

/* A commissioning scan: it had no baseline and became the baseline. */
static int became_baseline(const struct uwb_verdict *v, const struct uwb_provenance *prov)
{
    return prov && prov->became_baseline && v && !v->has_baseline;
}

/* The displacement in words; a commissioning scan says what became of it
 * rather than that no baseline was given. */
static void describe_result(const struct uwb_verdict *v, const struct uwb_provenance *prov, char *buf,
                            size_t len)
{
    if (became_baseline(v, prov) && v->status == UWB_STATUS_EDGES)
        snprintf(buf, len, "edges only: this scan became the baseline");
    else
        uwb_describe_displacement(v, buf, len);
}

void uwb_describe_displacement(const struct uwb_verdict *v, char *buf, size_t len)
{
    if (!v) {
        snprintf(buf, len, "no verdict");
    } else if (displacement_known(v)) {
        double d = MM(v->axial_displacement_m);
        /* The ± is one sigma; the 95 % interval has its own line beside the
         * meter. A withheld height change is no number here either. */
        char height[48];
        if (v->height_change_withheld[0])
            snprintf(height, sizeof height, "height change withheld");
        else
            snprintf(height, sizeof height, "height change %+.2f mm", MM(v->height_change_m));
        snprintf(buf, len, "displacement %+.2f \u00b1 %.2f mm (1\u03c3) %s  %s", d, MM(v->uncertainty_m),
                 d > 0   ? "up"
                 : d < 0 ? "down"
                         : "none",
                 height);
    } else if (v->status == UWB_STATUS_INCONCLUSIVE || v->status == UWB_STATUS_ERROR) {
        snprintf(buf, len, "no displacement: %s", v->reason[0] ? v->reason : uwb_status_name(v->status));
    } else if (v->axial_withheld) {
        /* The status is the radial change's; the reason says both. */
        snprintf(buf, len, "axial figure withheld: %s", v->reason);
    } else if (!v->has_baseline) {
        snprintf(buf, len, "no baseline given: edges only");
    } else {
        snprintf(buf, len, "no displacement: %s",
                 !v->current.found ? "edges of this scan not found" : "baseline edges not found");
    }
}

/* The radial change in words (the radial panel's label and the caption). */
void uwb_describe_radial(const struct uwb_verdict *v, char *buf, size_t len)
{
    if (!v || !v->has_baseline) {
        snprintf(buf, len, "radial: no baseline");
        return;
    }
    const struct uwb_radial_verdict *r = &v->radial;
    if (!r->measured && r->change_least_m != 0.0) {
        snprintf(buf, len, "radial: %s", r->withheld);
        return;
    }
    if (!r->measured) {
        snprintf(buf, len, "radial: not measured (%s)", r->withheld[0] ? r->withheld : "no reason given");
        return;
    }
    /* A change whose 95 % interval holds zero is no shape: naming it a
     * dent or a bulge (as for -0.04 mm in an ok verdict) says too much. */
    int beyond_noise = fabs(r->max_change_m) > UWB_SIGMAS_95 * r->uncertainty_m;
    const char *kind = !beyond_noise           ? "within its noise"
                       : r->max_change_m > 0.0 ? "bulge toward the antenna"
                                               : "dent, away from the antenna";
    char change[32];
    uwb_format_signed(change, sizeof change, r->max_change_m * 1e3, 1);
    int n = snprintf(buf, len, "radial %s \u00b1 %.1f mm at %.0f mm (%s)", change, r->uncertainty_m * 1e3,
                     r->at_m * 1e3, kind);
    if (n < 0 || (size_t)n >= len)
        return;
    if (r->status == UWB_STATUS_INCONCLUSIVE)
        snprintf(buf + n, len - (size_t)n, ", inconclusive: %s", r->withheld);
}

void uwb_describe_edges(const struct uwb_edges *e, char *buf, size_t len)
{
    if (!e->found) {
        snprintf(buf, len, "not found%s%s", e->reason[0] ? ": " : "", e->reason);
        return;
    }
    /* The centre is what the displacement is made of, so it alone gets its
     * uncertainty here; the JSON has the others. */
    snprintf(buf, len, "lower %.1f  upper %.1f  centre %.1f \u00b1 %.1f mm (1\u03c3)  face z %.1f mm",
             MM(e->lower_m), MM(e->upper_m), MM(e->center_m), MM(e->sigma_center_m), MM(e->face_z_m));
}

/* A verdict the radial change decided: its axial figure withheld, or
 * the radial change at watch or alarm. */
static int radial_decided(const struct uwb_verdict *v)
{
    const struct uwb_radial_verdict *r = &v->radial;
    return v->has_baseline && r->measured &&
           (v->axial_withheld || r->status == UWB_STATUS_WATCH || r->status == UWB_STATUS_ALARM);
}

void uwb_verdict_summary(const struct uwb_verdict *v, const struct uwb_provenance *prov, char *buf,
                         size_t len)
{
    char source[320];
    uwb_describe_provenance(v, prov, source, sizeof source);
    if (!v) {
        snprintf(buf, len, "no verdict; %s", source);
        return;
    }
    char disp[320], now[320], base[320];
    describe_result(v, prov, disp, sizeof disp);
    if (v->current.found && v->edges_withheld[0])
        snprintf(now, sizeof now, "withheld: %.250s", v->edges_withheld);
    else
        uwb_describe_edges(&v->current, now, sizeof now);
    if (v->has_baseline)
        uwb_describe_edges(&v->baseline, base, sizeof base);
    char limits[320] = "";
    if (uwb_displacement_measured(v)) {
        double d = v->axial_displacement_m * 1e3, s95 = UWB_SIGMAS_95 * v->uncertainty_m * 1e3;
        size_t n = strlen(disp);
        snprintf(disp + n, sizeof disp - n, "; 95 %% interval %+.2f..%+.2f mm", d - s95, d + s95);
    }
    if (prov && uwb_thresholds_usable(prov->thresholds))
        snprintf(limits, sizeof limits, "; thresholds watch %.2f mm, alarm %.2f mm",
                 prov->thresholds->watch_m * 1e3, prov->thresholds->alarm_m * 1e3);
    if (prov && radial_decided(v) && uwb_thresholds_usable(prov->radial_thresholds)) {
        size_t n = strlen(limits);
        snprintf(limits + n, sizeof limits - n, "; radial thresholds watch %.2f mm, alarm %.2f mm",
                 prov->radial_thresholds->watch_m * 1e3, prov->radial_thresholds->alarm_m * 1e3);
    }
    char radial[320] = "";
    if (v->has_baseline) {
        radial[0] = ';';
        radial[1] = ' ';
        uwb_describe_radial(v, radial + 2, sizeof radial - 2);
    }
    snprintf(buf, len, "scan %s created %s; status %s; %s%s; edges %s%s%s%s%s%s%s; %s", scan_name(v, prov),
             or_unknown(v->created), uwb_status_name(v->status), disp, radial, now,
             v->has_baseline ? "; baseline " : "", v->has_baseline ? or_unknown(v->baseline_scan_id) : "",
             v->has_baseline ? " edges " : "", v->has_baseline ? base : "",
             prov && prov->became_baseline ? "; this scan became the baseline" : "", limits, source);
}

/* Bytes of the first n of `text` that fit in max_w pixels, cut at a code
 * point. The font is monospaced: k glyphs take (k * advance - 1) * scale. */
static size_t fitting_prefix(const char *text, size_t n, int max_w, int scale)
{
    long glyphs = ((long)max_w / scale + 1) / UWB_FONT_ADVANCE;
    size_t i = 0;
    while (i < n && glyphs > 0) {
        i++;
        while (i < n && ((unsigned char)text[i] & 0xC0) == 0x80)
            i++; /* rest of a UTF-8 sequence */
        glyphs--;
    }
    return i;
}

size_t uwb_wrap_line_length(const char *text, int max_w, int scale)
{
    size_t n = strlen(text);
    size_t fit = fitting_prefix(text, n, max_w, scale);
    if (fit == 0 && n > 0)
        fit = fitting_prefix(text, n, UWB_FONT_ADVANCE * scale, scale); /* one glyph a line */
    if (fit < n) {
        /* break at the last space that fits, if there is one */
        size_t cut = fit;
        while (cut > 0 && text[cut] != ' ')
            cut--;
        if (cut > 0)
            fit = cut;
    }
    return fit;
}

/* Shorten `text` in place, ending in "...", until it fits max_w pixels. */
static void fit_text(char *text, int max_w, int scale)
{
    size_t n = strlen(text);
    if (uwb_text_width(text, scale) <= max_w)
        return;
    size_t keep =
        fitting_prefix(text, n, max_w - uwb_text_width("...", scale) - UWB_FONT_ADVANCE * scale, scale);
    if (keep + 3 <= n)
        memcpy(text + keep, "...", 4);
    else
        text[fitting_prefix(text, n, max_w, scale)] = '\0';
}

/* Where caption lines go; with canvas NULL nothing is drawn and only the
 * height is found, so layout and drawing can never disagree. */
struct pen {
    struct uwb_canvas *c;
    int width, scale, x, y;
    int has_meter; /* set by threshold_line */
    struct uwb_meter meter;
};

static void pen_text(struct pen *p, int x, int y, const char *text, int scale, struct uwb_rgb colour)
{
    if (p->c)
        uwb_draw_text(p->c, x, y, text, scale, colour);
}

/* A label, then `text` word-wrapped over as many lines as it needs in
 * the column after the label: nothing in a caption is cut, since the
 * words cut off (a source line's SNR, a reason's end) are the ones the
 * reader was looking for. */
static void labelled_text(struct pen *p, const char *label, const char *text, struct uwb_rgb colour)
{
    int tx = p->x + uwb_text_width(label, p->scale) + UWB_FONT_ADVANCE * p->scale;
    int max_w = p->width - tx - 8;
    pen_text(p, p->x, p->y, label, p->scale, muted);
    const char *rest = text;
    do {
        while (*rest == ' ')
            rest++;
        size_t fit = uwb_wrap_line_length(rest, max_w, p->scale);
        char buf[1024];
        snprintf(buf, sizeof buf, "%.*s", (int)fit, rest);
        pen_text(p, tx, p->y, buf, p->scale, colour);
        p->y += line_step(p->scale);
        rest += fit;
        while (*rest == ' ')
            rest++;
    } while (*rest);
}

/* The thresholds as three words in their zones' colours,
 * "ok < 2.00   watch >= 2.00   alarm >= 5.00 mm", then on a line of its
 * own (room for its numbers: beside the words they crowded) a meter of
 * the figure in the same colours, its numbers under it. Returns 1 if
 * the meter had room (*meter: where). */
static int limits_and_meter(struct pen *p, const char *label, const struct uwb_meter_figure *f,
                            const struct uwb_thresholds *th, struct uwb_meter *meter)
{
    int column = p->x + uwb_text_width(label, p->scale) + UWB_FONT_ADVANCE * p->scale, x = column;
    pen_text(p, p->x, p->y, label, p->scale, muted);
    char part[3][64];
    snprintf(part[0], sizeof part[0], "ok < %.2f", th->watch_m * 1e3);
    snprintf(part[1], sizeof part[1], "watch >= %.2f", th->watch_m * 1e3);
    snprintf(part[2], sizeof part[2], "alarm >= %.2f mm", th->alarm_m * 1e3);
    static const enum uwb_status zone[3] = {UWB_STATUS_OK, UWB_STATUS_WATCH, UWB_STATUS_ALARM};
    for (int i = 0; i < 3; i++) {
        pen_text(p, x, p->y, part[i], p->scale, uwb_status_colour(zone[i]));
        x += uwb_text_width(part[i], p->scale) + 3 * UWB_FONT_ADVANCE * p->scale;
    }
    p->y += line_step(p->scale);
    int right = p->width - 12, h = UWB_FONT_CAP_HEIGHT * p->scale;
    x = column;
    int has_meter = right - x >= 60;
    if (has_meter) {
        uwb_meter_layout(f, th, x, p->y, right - x, h, meter);
        if (p->c) {
            uwb_draw_meter(p->c, meter, f, th);
            uwb_draw_meter_labels(p->c, meter, f, th, p->scale);
        }
    }
    if (has_meter)
        p->y += line_step(p->scale) + uwb_meter_labels_height(p->scale); /* the meter and its numbers */
    return has_meter;
}

/* The axial limits and meter, the 95 % interval; then, on a verdict the
 * radial change decided, the radial limits and a meter of that change
 * (a radial alarm showed only the axial limits). */
static void threshold_line(struct pen *p, const struct uwb_verdict *v, const struct uwb_thresholds *th,
                           const struct uwb_thresholds *radial_th)
{
    struct uwb_meter_figure axial = {uwb_displacement_measured(v), v->axial_displacement_m, v->uncertainty_m};
    p->has_meter = limits_and_meter(p, "limits  ", &axial, th, &p->meter);
    if (uwb_displacement_measured(v)) {
        double d = v->axial_displacement_m * 1e3, s95 = UWB_SIGMAS_95 * v->uncertainty_m * 1e3;
        char interval[160];
        snprintf(interval, sizeof interval,
                 "%+.2f .. %+.2f mm (\u00b1%.0f\u03c3: the black bar on the meter)", d - s95, d + s95,
                 UWB_SIGMAS_95);
        labelled_text(p, "95 %    ", interval, ink);
    }
    if (radial_decided(v) && uwb_thresholds_usable(radial_th)) {
        struct uwb_meter_figure radial = {1, v->radial.max_change_m, v->radial.uncertainty_m};
        struct uwb_meter unused;
        limits_and_meter(p, "radial  ", &radial, radial_th, &unused);
    }
}

static int caption(struct uwb_canvas *c, int width, const char *title, const struct uwb_verdict *v,
                   const struct uwb_provenance *prov, int scale, struct uwb_meter *meter)
{
    struct pen p = {c, width, scale, 12, CAPTION_TOP, 0, {0, 0, 0, 0, 0.0}};
    int title_scale = scale + 1;
    char a[1024];
    snprintf(a, sizeof a, "%s", title ? title : "");
    fit_text(a, width - 2 * p.x, title_scale);
    pen_text(&p, p.x, p.y, a, title_scale, ink);
    p.y += UWB_FONT_LINE_HEIGHT * title_scale + TITLE_GAP;

    if (!v) {
        labelled_text(&p, "verdict ", "none available: image only", ink);
    } else {
        /* Labels are padded to one width so the figures of this scan and
         * of the baseline line up under each other. */
        snprintf(a, sizeof a, "%s   created %s", scan_name(v, prov), or_unknown(v->created));
        labelled_text(&p, "scan    ", a, ink);

        /* Verdict: a status badge in its colour, then the figure or why
         * there is none. */
        char status[64];
        upper_case(status, sizeof status, uwb_status_name(v->status));
        int bx = p.x + uwb_text_width("verdict ", scale) + UWB_FONT_ADVANCE * scale;
        int bw = uwb_text_width(status, scale) + 8 * scale, pad = 2 * scale;
        if (c) {
            uwb_draw_text(c, p.x, p.y, "verdict ", scale, muted);
            uwb_canvas_fill_rect(c, bx, p.y - pad, bw, UWB_FONT_CAP_HEIGHT * scale + 2 * pad,
                                 uwb_status_colour(v->status));
            uwb_draw_text(c, bx + 4 * scale, p.y, status, scale, white);
        }
        struct pen after_badge = p;
        after_badge.x = bx + bw + 8 * scale - UWB_FONT_ADVANCE * scale; /* text column after the badge */
        describe_result(v, prov, a, sizeof a);
        labelled_text(&after_badge, "", a, ink);
        p.y = after_badge.y;

        uwb_describe_edges(&v->current, a, sizeof a);
        labelled_text(&p, "edges   ", a, ink);
        if (v->has_baseline) {
            /* The colour ties these lines to the dashed baseline overlay. */
            char id[300];
            snprintf(id, sizeof id, "%s%s", or_unknown(v->baseline_scan_id),
                     prov && prov->became_baseline ? "   (replaced by this scan)" : "");
            labelled_text(&p, "baseline", id, baseline_ink);
            uwb_describe_edges(&v->baseline, a, sizeof a);
            labelled_text(&p, "        ", a, baseline_ink);
        } else if (became_baseline(v, prov)) {
            labelled_text(&p, "baseline", "none before: this scan is now the baseline", baseline_ink);
        } else {
            labelled_text(&p, "baseline", "none given", ink);
        }
        if (prov && uwb_thresholds_usable(prov->thresholds))
            threshold_line(&p, v, prov->thresholds, prov->radial_thresholds);
    }
    uwb_describe_provenance(v, prov, a, sizeof a);
    labelled_text(&p, "source  ", a, muted);
    if (meter) {
        *meter = p.meter;
        if (!p.has_meter)
            meter->w = 0;
    }
    int height = p.y + 8;
    if (c)
        uwb_canvas_fill_rect(c, 0, height - 4, width, 1, rule);
    return height;
}

int uwb_caption_height(const struct uwb_verdict *v, const struct uwb_provenance *prov, int width,
                       int font_scale)
{
    return caption(NULL, width, "", v, prov, font_scale, NULL);
}

int uwb_draw_caption(struct uwb_canvas *c, const char *title, const struct uwb_verdict *v,
                     const struct uwb_provenance *prov, int font_scale)
{
    return caption(c, c->width, title, v, prov, font_scale, NULL);
}

int uwb_caption_meter(const struct uwb_verdict *v, const struct uwb_provenance *prov, int width,
                      int font_scale, struct uwb_meter *m)
{
    memset(m, 0, sizeof *m);
    caption(NULL, width, "", v, prov, font_scale, m);
    return m->w > 0;
}

int uwb_canvas_save_with_verdict(struct uwb_canvas *c, const char *path, const char *title,
                                 const struct uwb_verdict *v, const struct uwb_provenance *prov, char *err,
                                 size_t errlen)
{
    char summary[2048], stack[32] = "", eps[32] = "", snr[32] = "", radial[320] = "";
    uwb_verdict_summary(v, prov, summary, sizeof summary);
    if (v && v->has_baseline)
        uwb_describe_radial(v, radial, sizeof radial);
    if (prov && prov->stack > 0)
        snprintf(stack, sizeof stack, "%d", prov->stack);
    if (prov && prov->eps_r > 0.0 && isfinite(prov->eps_r))
        snprintf(eps, sizeof eps, "%.3g", prov->eps_r);
    if (v && isfinite(v->current.snr_db) && (v->current.found || v->current.snr_db != 0.0))
        snprintf(snr, sizeof snr, "%.1f", v->current.snr_db);
    /* Machine-readable provenance beside the prose; an unknown value is
     * left out rather than written as a guess. */
    struct uwb_png_text texts[] = {
        {"Title", title},
        {"Description", summary},
        {"Software", "uwbd " UWBD_VERSION},
        {"Scan", v && v->scan_id[0]                              ? v->scan_id
                 : prov && prov->scan_name && prov->scan_name[0] ? prov->scan_name
                                                                 : NULL},
        {"Asset", prov && prov->asset && prov->asset[0] ? prov->asset : NULL},
        {"Stack", stack[0] ? stack : NULL},
        {"eps_r", eps[0] ? eps : NULL},
        {"SNR dB", snr[0] ? snr : NULL},
        {"Radial", radial[0] ? radial : NULL},
    };
    int rc = uwb_canvas_write_png(c, path, texts, (int)(sizeof texts / sizeof texts[0]), err, errlen);
    uwb_canvas_free(c);
    return rc;
}
