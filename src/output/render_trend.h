/* The trend PNG: a winding's axial displacement over time, each figure
 * with its 2-sigma (95 %) bar, the radial change beside it (where the
 * verdicts carry one), the watch and alarm thresholds as lines,
 * baseline changes as vertical lines, and every verdict without a figure
 * (inconclusive, error, edges only) as a mark in a strip below the plot,
 * never as a point. Written atomically (atomic_file.h) like every image. */
#ifndef UWB_RENDER_TREND_H
#define UWB_RENDER_TREND_H

#include <stddef.h>
#include <time.h>

#include "output/render_internal.h"
#include "verdict/trend.h"
#include "uwb/verdict.h"

#define UWB_TREND_PNG_WIDTH 1000
#define UWB_TREND_PNG_HEIGHT 720
/* The bars' half-length in sigmas of the verdict's uncertainty. */
#define UWB_TREND_BAR_SIGMAS UWB_SIGMAS_95
/* The radial change is a second series: diamonds in their status colour
 * with bars in this ink, this many px right of the axial figure's column. */
#define UWB_TREND_RADIAL_OFFSET 7
extern const struct uwb_rgb UWB_TREND_RADIAL_INK;

/* Where uwb_render_trend_png draws: plot.x data is (time - t_ref) / unit_s,
 * plot.y data is displacement in mm; the strip of verdicts without a
 * figure spans rows strip_y .. strip_y + strip_h - 1 above the plot;
 * its marks: "?" inconclusive, "X" error, "B" became the baseline, "E"
 * edges only. */
struct uwb_trend_layout {
    struct uwb_plot plot;
    time_t t_ref;  /* midnight UTC of the first dated verdict's day */
    double unit_s; /* 86400 (days), 3600 (hours: a span under two days), 60 (minutes: under two hours) */
    int strip_y, strip_h;
    int caption_h;
};

void uwb_render_trend_layout(const struct uwb_trend *t, const struct uwb_thresholds *th, const char *site,
                             struct uwb_trend_layout *out);
/* Pixel column of a time in that layout. */
int uwb_trend_col(const struct uwb_trend_layout *l, time_t when);

/* site: who the trend belongs to (asset, phase, label), or NULL. Returns 0,
 * or -1 with "PATH: problem"; the old file stays on failure. */
int uwb_render_trend_png(const char *path, const struct uwb_trend *t, const struct uwb_thresholds *th,
                         const char *site, char *err, size_t errlen);

/* The trend in one line (the PNG's Description text, ASCII only). */
void uwb_trend_summary(const struct uwb_trend *t, const struct uwb_thresholds *th, char *buf, size_t len);

#endif
