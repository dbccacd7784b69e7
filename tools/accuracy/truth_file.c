/* Reading a scan's truth file (see the header). */
#include "accuracy/truth_file.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/read_file.h"

#define TRUTH_MAX_BYTES (1 << 20)

int accuracy_truth_read(const char *scan_path, struct accuracy_truth *t, char *err, size_t errlen)
{
    char path[4096];
    size_t n = strlen(scan_path);
    if (n < 8 || n + 8 > sizeof path || strcmp(scan_path + n - 8, ".uwbscan") != 0) {
        snprintf(err, errlen, "%s: not a .uwbscan path", scan_path);
        return -1;
    }
    snprintf(path, sizeof path, "%.*s.truth.json", (int)(n - 8), scan_path);
    char *text = NULL;
    size_t len = 0;
    if (uwb_read_file(path, TRUTH_MAX_BYTES, &text, &len, err, errlen) != UWB_READ_OK)
        return -1;
    cJSON *o = cJSON_Parse(text);
    free(text);
    const cJSON *d = cJSON_GetObjectItem(o, "displacement_mm"),
                *h = cJSON_GetObjectItem(o, "height_change_mm"), *y1 = cJSON_GetObjectItem(o, "y1_m"),
                *y2 = cJSON_GetObjectItem(o, "y2_m");
    if (!cJSON_IsNumber(d)) {
        snprintf(err, errlen, "%s: no displacement_mm", path);
        cJSON_Delete(o);
        return -1;
    }
    memset(t, 0, sizeof *t);
    t->shift_mm = d->valuedouble;
    t->height_change_mm = cJSON_IsNumber(h) ? h->valuedouble : 0.0;
    t->has_span = cJSON_IsNumber(y1) && cJSON_IsNumber(y2);
    if (t->has_span) {
        t->y1_mm = y1->valuedouble * 1e3;
        t->y2_mm = y2->valuedouble * 1e3;
    }
    cJSON_Delete(o);
    return 0;
}
