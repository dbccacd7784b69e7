/* How far the running scan is, and how long it has left: the `status`
 * reply's "progress" and the PROGRESS lines `watch` streams. The estimate
 * uses the pace the rig has shown between positions (homing, which comes
 * before the first position, is not a position's pace). Pure arithmetic. */
#ifndef UWB_CONTROL_SCAN_PROGRESS_H
#define UWB_CONTROL_SCAN_PROGRESS_H

struct uwbd_scan_progress {
    int done;         /* positions acquired in this pass */
    int total;        /* positions in a pass */
    int pass, passes; /* this pass, of how many: `baseline set N` acquires N scans in one cycle */
    double fraction;  /* of the whole cycle's positions (all passes) acquired, 0..1 */
    double elapsed_s; /* since the cycle's first pass started */
    int has_left;     /* 0 until a position has been acquired */
    double left_s;    /* estimated time to the last position of the last pass */
};

/* started_s, first_s (the first position's completion), last_s (the latest
 * one's) and now_s on one monotonic clock; first_s/last_s unused while done
 * is 0. With two or more positions the pace is (last - first)/(done - 1);
 * with one, the first position's time from the start (an overestimate: it
 * includes homing). The estimate counts from last_s, less what has passed. */
void uwbd_scan_progress_estimate(int done, int total, double started_s, double first_s, double last_s,
                                 double now_s, struct uwbd_scan_progress *out);

/* The same over a cycle of `passes` scans of `total` positions each, in
 * pass `pass` (1-based) with `done` of its positions acquired: the pace and
 * the time left run over every pass, first_s being the first position of the
 * first pass (so the homing between passes counts in the pace). */
void uwbd_scan_progress_estimate_passes(int pass, int passes, int done, int total, double started_s,
                                        double first_s, double last_s, double now_s,
                                        struct uwbd_scan_progress *out);

/* The progress's fields added to object o (a cJSON *), in the PROGRESS
 * line's order: 0, or -1 when out of memory. The `status` reply nests them
 * under "progress", the PROGRESS line follows its "class" with them. */
struct cJSON;
int uwbd_progress_add_fields(struct cJSON *o, const struct uwbd_scan_progress *p);

/* The PROGRESS line (JSON, no newline; malloc'd, NULL when out of memory). */
char *uwbd_reply_progress(const struct uwbd_scan_progress *p);

#endif
