/* Owning a struct uwb_scan: allocate, free, deep-copy. */
#include "uwb/scan.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "uwbscan_check.h"

int uwb_scan_alloc(struct uwb_scan *scan, int positions, int samples, char *err, size_t errlen)
{
    memset(scan, 0, sizeof *scan);
    scan->eps_r = 1.0;
    /* The format's limits also bound memory: a scan we hold can always be written. */
    if (positions < 1 || positions > UWBSCAN_MAX_POSITIONS) {
        uwbscan_fail(err, errlen, "scan", "positions is %d, must be between 1 and %d", positions,
                     UWBSCAN_MAX_POSITIONS);
        return -1;
    }
    if (samples < 1 || samples > UWBSCAN_MAX_SAMPLES) {
        uwbscan_fail(err, errlen, "scan", "samples is %d, must be between 1 and %d", samples,
                     UWBSCAN_MAX_SAMPLES);
        return -1;
    }
    uint64_t data_bytes = uwbscan_payload_bytes(positions, samples);
    if (data_bytes > SIZE_MAX) { /* only a 32-bit size_t gets here: the limits make 16 GiB */
        uwbscan_fail(err, errlen, "scan", "%d x %d samples do not fit in memory", positions, samples);
        return -1;
    }
    scan->antenna_y_m = calloc((size_t)positions, sizeof *scan->antenna_y_m);
    scan->data = calloc((size_t)positions * (size_t)samples, sizeof *scan->data);
    if (scan->antenna_y_m == NULL || scan->data == NULL) {
        uwb_scan_free(scan);
        scan->eps_r = 1.0;
        uwbscan_fail(err, errlen, "scan", "cannot allocate %d x %d samples: %s", positions, samples,
                     strerror(ENOMEM));
        return -1;
    }
    scan->positions = positions;
    scan->samples = samples;
    return 0;
}

void uwb_scan_free(struct uwb_scan *scan)
{
    if (scan == NULL)
        return;
    free(scan->antenna_y_m);
    free(scan->created);
    free(scan->scan_id);
    free(scan->source);
    free(scan->comment);
    free(scan->extra_json);
    free(scan->data);
    memset(scan, 0, sizeof *scan);
}

static int copy_string(char **dst, const char *src)
{
    *dst = NULL;
    if (src == NULL)
        return 0;
    *dst = strdup(src);
    return *dst ? 0 : -1;
}

int uwb_scan_copy(struct uwb_scan *dst, const struct uwb_scan *src, char *err, size_t errlen)
{
    if (uwb_scan_alloc(dst, src->positions, src->samples, err, errlen) != 0)
        return -1;
    /* Copy the scalars wholesale, then give dst its own copies of every pointer. */
    double *antenna = dst->antenna_y_m;
    float *data = dst->data;
    *dst = *src;
    dst->antenna_y_m = antenna;
    dst->data = data;
    dst->created = dst->scan_id = dst->source = dst->comment = dst->extra_json = NULL;
    if (src->antenna_y_m)
        memcpy(dst->antenna_y_m, src->antenna_y_m, (size_t)src->positions * sizeof *antenna);
    if (src->data)
        memcpy(dst->data, src->data, (size_t)src->positions * (size_t)src->samples * sizeof *data);
    if (copy_string(&dst->created, src->created) || copy_string(&dst->scan_id, src->scan_id) ||
        copy_string(&dst->source, src->source) || copy_string(&dst->comment, src->comment) ||
        copy_string(&dst->extra_json, src->extra_json)) {
        uwb_scan_free(dst);
        uwbscan_fail(err, errlen, "scan", "cannot copy header strings: %s", strerror(ENOMEM));
        return -1;
    }
    return 0;
}
