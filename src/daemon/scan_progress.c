/* Scan progress and time left (see the header). */
#include "daemon/scan_progress.h"

#include <cjson/cJSON.h>
#include <math.h>

void uwbd_scan_progress_estimate(int done, int total, double started_s, double first_s, double last_s,
                                 double now_s, struct uwbd_scan_progress *out)
{
    if (done < 0)
        done = 0;
    if (total < done)
        total = done;
    out->done = done;
    out->total = total;
    out->elapsed_s = now_s > started_s ? now_s - started_s : 0;
    out->has_left = 0;
    out->left_s = 0;
    if (done == 0)
        return;
    double pace_s = done >= 2 ? (last_s - first_s) / (done - 1) : first_s - started_s;
    if (!(pace_s > 0))
        pace_s = 0;
    double since_last = now_s > last_s ? now_s - last_s : 0;
    double left = (total - done) * pace_s - since_last;
    out->has_left = 1;
    out->left_s = left > 0 ? left : 0;
}

char *uwbd_reply_progress(const struct uwbd_scan_progress *p)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "class", "PROGRESS");
    cJSON_AddNumberToObject(o, "position", p->done);
    cJSON_AddNumberToObject(o, "positions", p->total);
    cJSON_AddNumberToObject(o, "elapsed_s", round(p->elapsed_s * 10) / 10);
    if (p->has_left)
        cJSON_AddNumberToObject(o, "left_s", round(p->left_s * 10) / 10);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}
