/* The daemon's side of the trend: `trend [N]` read from verdicts.jsonl,
 * its TREND reply line, and trend.png in the state directory, rewritten
 * (atomically) after every recorded verdict. */
#ifndef UWB_DAEMON_TREND_H
#define UWB_DAEMON_TREND_H

#include <stddef.h>

#include "config/config_load.h"
#include "state/store.h"
#include "verdict/trend.h"

/* How many of the newest verdicts trend.png shows. */
#define UWBD_TREND_PNG_VERDICTS 200
#define UWBD_TREND_PNG_NAME "trend.png"
/* How many of the newest verdicts the rate is read from, whatever `trend
 * N` shows: the same as trend.png, so the reply and the image agree. */
#define UWBD_TREND_RATE_VERDICTS UWBD_TREND_PNG_VERDICTS

/* The last n verdicts of the log; lines that are not verdicts count in
 * t->unreadable. t->rate is over the last UWBD_TREND_RATE_VERDICTS (or n,
 * if more) whatever n is. Returns 0 (a missing log is an empty trend) or -1 with err. */
int uwbd_trend_read(const struct uwbd_store *store, int n, struct uwb_trend *t, char *err, size_t errlen);

/* <state>/trend.png from the last UWBD_TREND_PNG_VERDICTS verdicts.
 * site names the asset in the caption (NULL: none). 0, or -1 with err. */
int uwbd_trend_png_update(const struct uwbd_config *cfg, const struct uwbd_store *store, const char *site,
                          char *err, size_t errlen);
/* Who the trend (and every image) belongs to, for captions and the Asset
 * text: "T3-north, phase B, Hillside GT2" from site.asset_id, site.phase
 * and site.label; "" when none is set. */
void uwbd_trend_site_text(const struct uwbd_config *cfg, char *buf, size_t n);
/* Its path: 0, or -1 if it does not fit. */
int uwbd_trend_png_path(const struct uwbd_store *store, char *path, size_t n);

/* The TREND reply: every verdict's time, status, displacement and its
 * 1-sigma, height change, baseline and baseline changes; the rate since
 * the last baseline change; the thresholds; the image if there is one
 * (image may be NULL). malloc'd line, NULL when out of memory. */
char *uwbd_reply_trend(const struct uwb_trend *t, int requested, const struct uwb_thresholds *th,
                       const char *image);

#endif
