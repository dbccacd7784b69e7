/* A winding's displacement over time, read back from the verdict lines
 * uwbd keeps (verdicts.jsonl): what `trend` replies with and what the
 * trend PNG draws. Pure: no files, no daemon state. */
#ifndef UWB_TREND_H
#define UWB_TREND_H

#include <stddef.h>
#include <time.h>

#include "uwb/verdict.h"
#include "uwb/verdict_record.h"

/* A verdict on the trend: the summary of its published record as read
 * back (the TREND reply's entry is written from it: uwb/verdict_json.h),
 * and what the series makes of it. A figure only where
 * the verdict graded one: the reading clears a displacement, height
 * change or radial change an inconclusive or error verdict (an older
 * line) may carry, so has_displacement and radial_measured say "a point
 * on the line". */
struct uwb_trend_entry {
    struct uwb_verdict_summary summary;
    int became_baseline; /* this scan was made the baseline (baseline_set) */
    int has_time;
    time_t t;            /* created, as UTC seconds */
    int baseline_change; /* became the baseline, or compared against another baseline than the scans before */
};

/* A rate only where it can mean something. A winding moves over weeks
 * and months; over minutes or hours the figures differ by their noise and
 * by the day's load and temperature, which their sigmas do not cover, and
 * a slope through them is that noise divided by a tiny span (two scans a
 * minute apart read -167069 mm/year). So: a week or more, taking in
 * several daily cycles, and four figures or more, two beyond the two
 * that any line fits exactly, so their scatter about the line can be
 * weighed against their own sigmas. */
#define UWB_TREND_RATE_MIN_FIGURES 4
#define UWB_TREND_RATE_MIN_DAYS 7.0

/* Least-squares slope of displacement over time, each point weighted by
 * 1/sigma^2, over the figures since the newest baseline change (a new
 * baseline starts a new series). */
struct uwb_trend_rate {
    int known;  /* 0: withheld, see withheld */
    int points; /* dated figures since the newest baseline change */
    double mm_per_day;
    /* Its 1-sigma from the figures' sigmas, widened by sqrt(chi2/(n-2))
     * when they scatter about the line more than their sigmas say. */
    double sigma_mm_per_day;
    double days;        /* time the figures span */
    char withheld[160]; /* why there is no rate ("" when known), ASCII */
};

struct uwb_trend {
    int count;
    struct uwb_trend_entry *entries; /* oldest first */
    int unreadable;                  /* lines that were not a verdict */
    struct uwb_trend_rate rate;
};

/* Parse verdict lines (oldest first; anything that is not a VERDICT
 * object is counted in unreadable and left out). Returns 0, or -1 out of
 * memory. */
int uwb_trend_from_lines(char *const *lines, int count, struct uwb_trend *out);
void uwb_trend_free(struct uwb_trend *t);

#endif
