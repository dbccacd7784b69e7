/* A winding's displacement over time, read back from the verdict lines
 * uwbd keeps (verdicts.jsonl): what `trend` replies with and what the
 * trend PNG draws. Pure: no files, no daemon state. */
#ifndef UWB_TREND_H
#define UWB_TREND_H

#include <stddef.h>
#include <time.h>

#include "uwb/verdict.h"

#define UWB_TREND_ID_MAX 100

struct uwb_trend_point {
    char created[32]; /* as the verdict says it, "" when missing */
    int has_time;
    time_t t; /* created, as UTC seconds */
    char scan_id[UWB_TREND_ID_MAX + 1];
    enum uwb_status status;
    int has_displacement;             /* a figure (ok, watch, alarm); otherwise see reason */
    double displacement_mm, sigma_mm; /* sigma: 1-sigma, as uncertainty_mm in the verdict */
    int has_height_change;
    double height_change_mm;
    /* The face's radial change (+ toward the antenna): has_radial where the
     * verdict carried one (older lines do not), a figure only where it was
     * measured and graded ok, watch or alarm. */
    int has_radial;
    enum uwb_status radial_status;
    int has_radial_change;
    double radial_mm, radial_sigma_mm;      /* sigma: 1-sigma */
    char baseline_id[UWB_TREND_ID_MAX + 1]; /* the baseline compared against, "" when none */
    int became_baseline;                    /* this scan was made the baseline (baseline_set) */
    int baseline_change; /* became_baseline, or compared against another baseline than the scans before */
    char reason[256];    /* why there is no figure (inconclusive, error): the verdict's, whole */
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
    struct uwb_trend_point *points; /* oldest first */
    int unreadable;                 /* lines that were not a verdict */
    struct uwb_trend_rate rate;
};

/* Parse verdict lines (oldest first; anything that is not a VERDICT
 * object is counted in unreadable and left out). Returns 0, or -1 out of
 * memory. */
int uwb_trend_from_lines(char *const *lines, int count, struct uwb_trend *out);
void uwb_trend_free(struct uwb_trend *t);

#endif
