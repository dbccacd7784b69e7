/* The verdict as one JSON object (gpsd style: a "class", no nulls: what is
 * not known is left out), written from the published record and read back
 * into it here and nowhere else (uwb/verdict_record.h). */
#ifndef UWB_VERDICT_JSON_H
#define UWB_VERDICT_JSON_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "uwb/verdict.h"
#include "uwb/verdict_record.h"

/* The VERDICT object (free with cJSON_Delete), or NULL when out of memory. */
cJSON *uwb_record_object(const struct uwb_verdict_record *r);
/* malloc'd single-line JSON text of uwb_record_object, or NULL when out of memory. */
char *uwb_record_to_json(const struct uwb_verdict_record *r);

/* A VERDICT object or line back into *r. Returns 0, or -1 with err saying
 * what is wrong (not a VERDICT, an unknown status, a field of the wrong
 * type or too long). Unknown keys are ignored, as a newer uwbd may add some. */
int uwb_record_from_object(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen);
int uwb_record_from_json(const char *text, struct uwb_verdict_record *r, char *err, size_t errlen);

/* One entry of a HISTORY reply (a uwb_record_history_entry, or the
 * summary an older uwbd gave: no class) into *r: what it does not say is
 * left out of *r, and a height change given without its sigma has the
 * sigma NAN (not known). 0, or -1 with err as above. */
int uwb_record_from_summary(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen);

/* Each verdict of a HISTORY reply line, oldest first, read by
 * uwb_record_from_summary and given to each(r, ctx), which returns 0 to go
 * on. 0, or -1 with err (not a HISTORY reply, an entry unreadable, each
 * failed). */
int uwb_history_each(const char *reply, int (*each)(const struct uwb_verdict_record *r, void *ctx), void *ctx,
                     char *err, size_t errlen);

/* The evaluation's verdict straight to an object or text (uwbd --replay). */
cJSON *uwb_verdict_object(const struct uwb_verdict *v);
char *uwb_verdict_to_json(const struct uwb_verdict *v);

/* The one-line summary of a verdict that `status` gives: scan_id, created,
 * status, reason, displacement, centre, height change, baseline_set. NULL
 * when out of memory. */
cJSON *uwb_record_summary(const struct uwb_verdict_record *r);
/* A verdict as `history` lists it: the summary's keys, then every other
 * field a CSV row shows (uwb/verdict_csv.h): the height change's sigma or
 * why it was withheld, the edges, height, face range, SNR, the baseline
 * object, fault, trigger, asset_id and the radial object. NULL when out
 * of memory. */
cJSON *uwb_record_history_entry(const struct uwb_verdict_record *r);

/* A verdict's summary as a TREND reply lists it (the field table's trend places,
 * flat: radial_status, radial_max_change_mm, baseline for the baseline's
 * scan_id; the reason only where there is no displacement; baseline_set
 * when it became the baseline), and such an entry back into *r (what it
 * does not say left out). NULL when out of memory; 0, or -1 with err. */
cJSON *uwb_record_trend_entry(const struct uwb_verdict_summary *s, int became_baseline);
int uwb_record_from_trend_entry(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen);

/* Picoseconds to 0.1 ps, as every verdict and reply prints them. */
void uwb_json_add_ps(cJSON *obj, const char *key, double seconds);

#endif
