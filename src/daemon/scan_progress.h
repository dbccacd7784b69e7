/* How far the running scan is, and how long it has left: the `status`
 * reply's "progress" and the PROGRESS lines `watch` streams. The estimate
 * uses the pace the rig has shown between positions (homing, which comes
 * before the first position, is not a position's pace). Pure arithmetic. */
#ifndef UWB_DAEMON_SCAN_PROGRESS_H
#define UWB_DAEMON_SCAN_PROGRESS_H

struct uwbd_scan_progress {
    int done;         /* positions acquired */
    int total;        /* positions in the scan */
    double elapsed_s; /* since the scan started */
    int has_left;     /* 0 until a position has been acquired */
    double left_s;    /* estimated time to the last position */
};

/* started_s, first_s (the first position's completion), last_s (the latest
 * one's) and now_s on one monotonic clock; first_s/last_s unused while done
 * is 0. With two or more positions the pace is (last - first)/(done - 1);
 * with one, the first position's time from the start (an overestimate: it
 * includes homing). The estimate counts from last_s, less what has passed. */
void uwbd_scan_progress_estimate(int done, int total, double started_s, double first_s, double last_s,
                                 double now_s, struct uwbd_scan_progress *out);

/* The PROGRESS line (JSON, no newline; malloc'd, NULL when out of memory). */
char *uwbd_reply_progress(const struct uwbd_scan_progress *p);

#endif
