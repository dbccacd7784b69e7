/* Verdict lines -> a displacement series and its rate (see verdict/trend.h). */
#include "verdict/trend.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/utc_time.h"
#include "uwb/verdict_json.h"

static int graded(enum uwb_status status)
{
    return status == UWB_STATUS_OK || status == UWB_STATUS_WATCH || status == UWB_STATUS_ALARM;
}

/* A verdict line as an entry, read through the record (r: room for one). */
static int read_entry(const char *line, struct uwb_verdict_record *r, struct uwb_trend_entry *e)
{
    char err[256];
    memset(e, 0, sizeof *e);
    if (uwb_record_from_json(line, r, err, sizeof err) != 0)
        return -1;
    /* A figure only where the verdict made one: an inconclusive or error
     * verdict never becomes a point on the line. */
    if (!graded(r->status) || r->uncertainty_mm < 0)
        r->has_displacement = 0;
    if (!graded(r->status))
        r->has_height_change = 0;
    if (!r->has_radial || !graded(r->radial_status))
        r->radial_measured = 0;
    e->summary = r->summary;
    e->became_baseline = e->baseline_change = r->cycle.baseline_set;
    e->has_time = uwb_utc_parse(r->created, &e->t) == 0;
    return 0;
}

/* A span in the unit a person reads it in: "1 min", "5.5 h", "2.0 days". */
static void describe_span(double days, char *buf, size_t n)
{
    if (days < 1.0 / 24.0)
        snprintf(buf, n, "%.0f min", days * 1440.0);
    else if (days < 2.0)
        snprintf(buf, n, "%.1f h", days * 24.0);
    else
        snprintf(buf, n, "%.1f days", days);
}

static void withhold_rate(struct uwb_trend_rate *r)
{
    char span[32] = "";
    if (r->points >= 2)
        describe_span(r->days, span, sizeof span);
    snprintf(
        r->withheld, sizeof r->withheld,
        "%d figure%s%s%s since the last baseline change; a rate needs at least %d figures over %.0f days",
        r->points, r->points == 1 ? "" : "s", span[0] ? " over " : "", span, UWB_TREND_RATE_MIN_FIGURES,
        UWB_TREND_RATE_MIN_DAYS);
}

/* The figures the rate is fitted to: dated, with a displacement. */
static int is_fitted(const struct uwb_trend_entry *p)
{
    return p->summary.has_displacement && p->has_time;
}

static double days_since(const struct uwb_trend_entry *p, double t0)
{
    return ((double)p->t - t0) / 86400.0;
}

/* A sigma of 0 (rounded) counts as 0.01 mm, the verdict's resolution. */
static double fit_sigma_mm(const struct uwb_trend_entry *p)
{
    return fmax(p->summary.uncertainty_mm, 0.01);
}

static void find_rate(struct uwb_trend *t)
{
    memset(&t->rate, 0, sizeof t->rate);
    int from = 0;
    for (int i = 0; i < t->count; i++)
        if (t->entries[i].baseline_change)
            from = i;
    /* Weighted least squares in days from the first figure. */
    double sw = 0, swx = 0, swy = 0, swxx = 0, swxy = 0, t0 = 0, first = 0, last = 0;
    int n = 0;
    for (int i = from; i < t->count; i++) {
        const struct uwb_trend_entry *p = &t->entries[i];
        if (!is_fitted(p))
            continue;
        if (n == 0)
            t0 = (double)p->t;
        double x = days_since(p, t0);
        double s = fit_sigma_mm(p);
        double w = 1.0 / (s * s);
        sw += w;
        swx += w * x;
        swy += w * p->summary.axial_displacement_mm;
        swxx += w * x * x;
        swxy += w * x * p->summary.axial_displacement_mm;
        if (n == 0)
            first = x;
        last = x;
        n++;
    }
    t->rate.points = n;
    t->rate.days = last - first;
    double det = sw * swxx - swx * swx;
    if (n < UWB_TREND_RATE_MIN_FIGURES || t->rate.days < UWB_TREND_RATE_MIN_DAYS || !(det > 0)) {
        withhold_rate(&t->rate);
        return;
    }
    double slope = (sw * swxy - swx * swy) / det, intercept = (swy - slope * swx) / sw;
    /* Scatter beyond what the figures' sigmas say (a movement that is not
     * a straight line, or sigmas too small) widens the rate's sigma. */
    double chi2 = 0;
    for (int i = from; i < t->count; i++) {
        const struct uwb_trend_entry *p = &t->entries[i];
        if (!is_fitted(p))
            continue;
        double r =
            (p->summary.axial_displacement_mm - intercept - slope * days_since(p, t0)) / fit_sigma_mm(p);
        chi2 += r * r;
    }
    t->rate.known = 1;
    t->rate.mm_per_day = slope;
    t->rate.sigma_mm_per_day = sqrt(sw / det) * fmax(1.0, sqrt(chi2 / (n - 2)));
}

int uwb_trend_from_lines(char *const *lines, int count, struct uwb_trend *out)
{
    memset(out, 0, sizeof *out);
    if (count <= 0)
        return 0;
    out->entries = calloc((size_t)count, sizeof *out->entries);
    struct uwb_verdict_record *record = malloc(sizeof *record);
    if (!out->entries || !record) {
        free(record);
        uwb_trend_free(out);
        return -1;
    }
    const char *known_baseline = "";
    for (int i = 0; i < count; i++) {
        struct uwb_trend_entry *e = &out->entries[out->count];
        if (read_entry(lines[i], record, e) != 0) {
            out->unreadable++;
            continue;
        }
        /* A new baseline shows as this scan having become one, or as a
         * verdict against another baseline than the one before. */
        const struct uwb_verdict_summary *r = &e->summary;
        if (r->baseline_scan_id[0] && known_baseline[0] && strcmp(r->baseline_scan_id, known_baseline) != 0)
            e->baseline_change = 1;
        if (e->became_baseline)
            known_baseline = r->scan_id;
        else if (r->baseline_scan_id[0])
            known_baseline = r->baseline_scan_id;
        out->count++;
    }
    free(record);
    find_rate(out);
    return 0;
}

void uwb_trend_free(struct uwb_trend *t)
{
    free(t->entries);
    memset(t, 0, sizeof *t);
}
