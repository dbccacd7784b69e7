/* Scan progress and time left (see the header). */
#include "control/scan_progress.h"

#include <cjson/cJSON.h>
#include <math.h>

void uwbd_scan_progress_estimate(int done, int total, double started_s, double first_s, double last_s,
                                 double now_s, struct uwbd_scan_progress *out)
{
    uwbd_scan_progress_estimate_passes(1, 1, done, total, started_s, first_s, last_s, now_s, out);
}

void uwbd_scan_progress_estimate_passes(int pass, int passes, int done, int total, double started_s,
                                        double first_s, double last_s, double now_s,
                                        struct uwbd_scan_progress *out)
{
    if (done < 0)
        done = 0;
    if (total < done)
        total = done;
    if (pass < 1)
        pass = 1;
    if (passes < pass)
        passes = pass;
    out->done = done;
    out->total = total;
    out->pass = pass;
    out->passes = passes;
    /* Positions over the whole cycle: the passes before this one are whole. */
    long all_done = (long)(pass - 1) * total + done, all_total = (long)passes * total;
    out->fraction = all_total > 0 ? (double)all_done / (double)all_total : 0;
    out->elapsed_s = now_s > started_s ? now_s - started_s : 0;
    out->has_left = 0;
    out->left_s = 0;
    if (all_done == 0)
        return;
    double pace_s = all_done >= 2 ? (last_s - first_s) / (double)(all_done - 1) : first_s - started_s;
    if (!(pace_s > 0))
        pace_s = 0;
    double since_last = now_s > last_s ? now_s - last_s : 0;
    double left = (double)(all_total - all_done) * pace_s - since_last;
    out->has_left = 1;
    out->left_s = left > 0 ? left : 0;
}

int uwbd_progress_add_fields(cJSON *o, const struct uwbd_scan_progress *p)
{
    int ok = cJSON_AddNumberToObject(o, "position", p->done) &&
             cJSON_AddNumberToObject(o, "positions", p->total) &&
             cJSON_AddNumberToObject(o, "elapsed_s", round(p->elapsed_s * 10) / 10) &&
             (!p->has_left || cJSON_AddNumberToObject(o, "left_s", round(p->left_s * 10) / 10)) &&
             /* Added after the fields above, which keep their meaning within a pass. */
             cJSON_AddNumberToObject(o, "pass", p->pass) && cJSON_AddNumberToObject(o, "passes", p->passes) &&
             /* Floor to 4 places: 1 only when every position of every pass is in. */
             cJSON_AddNumberToObject(o, "fraction", floor(p->fraction * 1e4) / 1e4);
    return ok ? 0 : -1;
}

char *uwbd_reply_progress(const struct uwbd_scan_progress *p)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    char *text = NULL;
    if (cJSON_AddStringToObject(o, "class", "PROGRESS") && uwbd_progress_add_fields(o, p) == 0)
        text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}
