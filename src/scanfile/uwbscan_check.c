/* Rules of uwbscan/1 shared by the reader and the writer. */
#include "uwbscan_check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

static const char *const standard_keys[] = {
    "format", "positions",  "samples", "sample_interval_s", "t0_s",   "antenna_y_m", "tx_m",    "rx_m",
    "eps_r",  "target_z_m", "created", "scan_id",           "source", "stack",       "comment",
};

void uwbscan_fail(char *err, size_t errlen, const char *name, const char *fmt, ...)
{
    if (err == NULL || errlen == 0)
        return;
    int used = snprintf(err, errlen, "%s: ", name ? name : "uwbscan");
    if (used < 0 || (size_t)used >= errlen)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err + used, errlen - (size_t)used, fmt, ap);
    va_end(ap);
}

int uwbscan_is_standard_key(const char *key)
{
    for (size_t i = 0; i < sizeof standard_keys / sizeof standard_keys[0]; i++)
        if (strcmp(key, standard_keys[i]) == 0)
            return 1;
    return 0;
}

int uwbscan_utf8_valid(const unsigned char *s, size_t len, size_t *bad_offset)
{
    size_t i = 0;
    while (i < len) {
        unsigned char c = s[i];
        size_t extra;
        uint32_t cp, min;
        if (c < 0x80) {
            i++;
            continue;
        } else if ((c & 0xE0) == 0xC0) {
            extra = 1;
            cp = c & 0x1F;
            min = 0x80;
        } else if ((c & 0xF0) == 0xE0) {
            extra = 2;
            cp = c & 0x0F;
            min = 0x800;
        } else if ((c & 0xF8) == 0xF0) {
            extra = 3;
            cp = c & 0x07;
            min = 0x10000;
        } else {
            goto bad;
        }
        if (len - i <= extra)
            goto bad;
        for (size_t k = 1; k <= extra; k++) {
            if ((s[i + k] & 0xC0) != 0x80)
                goto bad;
            cp = (cp << 6) | (s[i + k] & 0x3F);
        }
        if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
            goto bad;
        i += extra + 1;
    }
    return 1;
bad:
    if (bad_offset)
        *bad_offset = i;
    return 0;
}

static int compare_key_pointers(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

const char *uwbscan_duplicate_key(const cJSON *object)
{
    size_t count = 0;
    for (const cJSON *item = object->child; item; item = item->next)
        count++;
    if (count < 2)
        return NULL;
    const char **keys = malloc(count * sizeof *keys);
    if (keys == NULL) {
        /* Out of memory: fall back to the slow pairwise scan rather than
         * let a duplicate through. */
        for (const cJSON *a = object->child; a; a = a->next)
            for (const cJSON *b = a->next; b; b = b->next)
                if (strcmp(a->string, b->string) == 0)
                    return a->string;
        return NULL;
    }
    size_t n = 0;
    for (const cJSON *item = object->child; item; item = item->next)
        keys[n++] = item->string;
    qsort(keys, n, sizeof *keys, compare_key_pointers);
    const char *duplicate = NULL;
    for (size_t i = 1; i < n && duplicate == NULL; i++)
        if (strcmp(keys[i - 1], keys[i]) == 0)
            duplicate = keys[i];
    free(keys);
    return duplicate;
}

uint64_t uwbscan_payload_bytes(int positions, int samples)
{
    if (positions <= 0 || samples <= 0)
        return 0;
    return (uint64_t)positions * (uint64_t)samples * 4u;
}

static int check_count(const char *key, int value, int limit, const char *name, char *err, size_t errlen)
{
    if (value < 1) {
        uwbscan_fail(err, errlen, name, "%s is %d, must be at least 1", key, value);
        return -1;
    }
    if (value > limit) {
        uwbscan_fail(err, errlen, name, "%s is %d, over the limit of %d", key, value, limit);
        return -1;
    }
    return 0;
}

static int check_finite(const char *what, double value, const char *name, char *err, size_t errlen)
{
    if (!isfinite(value)) {
        uwbscan_fail(err, errlen, name, "%s is not a finite number", what);
        return -1;
    }
    return 0;
}

static int check_string(const char *key, const char *value, const char *name, char *err, size_t errlen)
{
    size_t bad;
    if (value && !uwbscan_utf8_valid((const unsigned char *)value, strlen(value), &bad)) {
        uwbscan_fail(err, errlen, name, "%s is not valid UTF-8 (byte %zu)", key, bad);
        return -1;
    }
    return 0;
}

static int check_extra_json(const char *extra, const char *name, char *err, size_t errlen)
{
    if (extra == NULL)
        return 0;
    if (check_string("extra_json", extra, name, err, errlen) != 0)
        return -1;
    const char *end = NULL;
    cJSON *object = cJSON_ParseWithOpts(extra, &end, 1);
    if (object == NULL) {
        uwbscan_fail(err, errlen, name, "extra_json is not valid JSON (near byte %td)",
                     end ? end - extra : (ptrdiff_t)0);
        return -1;
    }
    int rc = -1;
    const char *duplicate;
    if (!cJSON_IsObject(object)) {
        uwbscan_fail(err, errlen, name, "extra_json must be a JSON object");
    } else if ((duplicate = uwbscan_duplicate_key(object)) != NULL) {
        uwbscan_fail(err, errlen, name, "extra_json key '%.80s' appears twice", duplicate);
    } else {
        rc = 0;
        for (const cJSON *item = object->child; item; item = item->next) {
            if (uwbscan_is_standard_key(item->string)) {
                uwbscan_fail(err, errlen, name, "extra_json key '%s' clashes with a standard header key",
                             item->string);
                rc = -1;
                break;
            }
        }
    }
    cJSON_Delete(object);
    return rc;
}

/* The rig's physical limits (uwb/scan.h), so that no accepted scan asks the
 * imaging for unbounded memory or time. */
static int check_rig_limits(const struct uwb_scan *scan, const char *name, char *err, size_t errlen)
{
    if (scan->sample_interval_s < UWBSCAN_MIN_SAMPLE_INTERVAL_S ||
        scan->sample_interval_s > UWBSCAN_MAX_SAMPLE_INTERVAL_S) {
        uwbscan_fail(err, errlen, name,
                     "sample_interval_s is %g s, outside what a UWB digitiser records (%g..%g s)",
                     scan->sample_interval_s, UWBSCAN_MIN_SAMPLE_INTERVAL_S, UWBSCAN_MAX_SAMPLE_INTERVAL_S);
        return -1;
    }
    if (fabs(scan->t0_s) > UWBSCAN_MAX_ABS_T0_S) {
        uwbscan_fail(err, errlen, name, "t0_s is %g s, beyond the limit of +-%g s", scan->t0_s,
                     UWBSCAN_MAX_ABS_T0_S);
        return -1;
    }
    for (int k = 1; k < scan->positions; k++) {
        double step = scan->antenna_y_m[k] - scan->antenna_y_m[k - 1];
        if (step <= 0.0) {
            uwbscan_fail(err, errlen, name,
                         "antenna_y_m[%d] = %g m %s antenna_y_m[%d] = %g m: positions must increase strictly "
                         "(a duplicated or reversed position is a carriage or recording fault)",
                         k, scan->antenna_y_m[k], step == 0.0 ? "repeats" : "is below", k - 1,
                         scan->antenna_y_m[k - 1]);
            return -1;
        }
        if (step < UWBSCAN_MIN_STEP_M - 1e-12) {
            uwbscan_fail(err, errlen, name,
                         "antenna_y_m[%d] is %g mm above antenna_y_m[%d], under the smallest step of %g mm",
                         k, step * 1e3, k - 1, UWBSCAN_MIN_STEP_M * 1e3);
            return -1;
        }
    }
    double travel = scan->antenna_y_m[scan->positions - 1] - scan->antenna_y_m[0];
    if (travel > UWBSCAN_MAX_TRAVEL_M) {
        uwbscan_fail(err, errlen, name, "antenna_y_m spans %g m, over the rig's largest travel of %g m",
                     travel, UWBSCAN_MAX_TRAVEL_M);
        return -1;
    }
    const double *offsets[2] = {scan->tx_m, scan->rx_m};
    for (int a = 0; a < 2; a++)
        for (int i = 0; i < 2; i++)
            if (fabs(offsets[a][i]) > UWBSCAN_MAX_ANTENNA_OFFSET_M) {
                uwbscan_fail(err, errlen, name,
                             "%s[%d] is %g m, over the limit of %g m from the reference point",
                             a ? "rx_m" : "tx_m", i, offsets[a][i], UWBSCAN_MAX_ANTENNA_OFFSET_M);
                return -1;
            }
    if (scan->eps_r > UWBSCAN_MAX_EPS_R) {
        uwbscan_fail(err, errlen, name, "eps_r is %g, over the limit of %g", scan->eps_r, UWBSCAN_MAX_EPS_R);
        return -1;
    }
    if (scan->has_target_z && (scan->target_z_m[0] < 0.0 || scan->target_z_m[1] > UWBSCAN_MAX_RANGE_M)) {
        uwbscan_fail(err, errlen, name, "target_z_m is [%g, %g] m, outside 0..%g m", scan->target_z_m[0],
                     scan->target_z_m[1], UWBSCAN_MAX_RANGE_M);
        return -1;
    }
    return 0;
}

int uwbscan_check_fields(const struct uwb_scan *scan, const char *name, char *err, size_t errlen)
{
    if (check_count("positions", scan->positions, UWBSCAN_MAX_POSITIONS, name, err, errlen) ||
        check_count("samples", scan->samples, UWBSCAN_MAX_SAMPLES, name, err, errlen))
        return -1;
    uint64_t count = (uint64_t)scan->positions * (uint64_t)scan->samples;
    if (count > UWBSCAN_MAX_SAMPLE_COUNT) {
        uwbscan_fail(err, errlen, name,
                     "%d positions x %d samples = %llu samples, over the limit of %zu (%d MiB of float32)",
                     scan->positions, scan->samples, (unsigned long long)count, UWBSCAN_MAX_SAMPLE_COUNT,
                     UWBSCAN_MAX_SAMPLE_MIB);
        return -1;
    }
    if (!isfinite(scan->sample_interval_s) || scan->sample_interval_s <= 0) {
        uwbscan_fail(err, errlen, name, "sample_interval_s is %g, must be a finite number > 0",
                     scan->sample_interval_s);
        return -1;
    }
    if (check_finite("t0_s", scan->t0_s, name, err, errlen))
        return -1;
    if (scan->antenna_y_m == NULL) {
        uwbscan_fail(err, errlen, name, "antenna_y_m is missing");
        return -1;
    }
    for (int k = 0; k < scan->positions; k++) {
        if (!isfinite(scan->antenna_y_m[k])) {
            uwbscan_fail(err, errlen, name, "antenna_y_m[%d] is not a finite number", k);
            return -1;
        }
    }
    if (check_finite("tx_m[0]", scan->tx_m[0], name, err, errlen) ||
        check_finite("tx_m[1]", scan->tx_m[1], name, err, errlen) ||
        check_finite("rx_m[0]", scan->rx_m[0], name, err, errlen) ||
        check_finite("rx_m[1]", scan->rx_m[1], name, err, errlen))
        return -1;
    if (!isfinite(scan->eps_r) || scan->eps_r < 1.0) {
        uwbscan_fail(err, errlen, name, "eps_r is %g, must be a finite number >= 1", scan->eps_r);
        return -1;
    }
    if (scan->has_target_z) {
        if (check_finite("target_z_m[0]", scan->target_z_m[0], name, err, errlen) ||
            check_finite("target_z_m[1]", scan->target_z_m[1], name, err, errlen))
            return -1;
        if (!(scan->target_z_m[0] < scan->target_z_m[1])) {
            uwbscan_fail(err, errlen, name, "target_z_m is [%g, %g], near must be less than far",
                         scan->target_z_m[0], scan->target_z_m[1]);
            return -1;
        }
    }
    if (scan->stack < 0) {
        uwbscan_fail(err, errlen, name, "stack is %d, must be a positive integer (0 = absent)", scan->stack);
        return -1;
    }
    if (check_rig_limits(scan, name, err, errlen) != 0)
        return -1;
    if (check_string("created", scan->created, name, err, errlen) ||
        check_string("scan_id", scan->scan_id, name, err, errlen) ||
        check_string("source", scan->source, name, err, errlen) ||
        check_string("comment", scan->comment, name, err, errlen))
        return -1;
    return check_extra_json(scan->extra_json, name, err, errlen);
}

const char *uwbscan_nonfinite_kind(uint32_t bits)
{
    return (bits & 0x007FFFFFu) ? "NaN" : "infinite";
}

int uwbscan_check_samples(const struct uwb_scan *scan, const char *name, char *err, size_t errlen)
{
    if (scan->data == NULL) {
        uwbscan_fail(err, errlen, name, "data is missing");
        return -1;
    }
    if (uwbscan_payload_bytes(scan->positions, scan->samples) > SIZE_MAX) {
        uwbscan_fail(err, errlen, name, "%d x %d samples do not fit in memory", scan->positions,
                     scan->samples);
        return -1;
    }
    size_t count = (size_t)scan->positions * (size_t)scan->samples;
    for (size_t i = 0; i < count; i++) {
        if (!isfinite(scan->data[i])) {
            uwbscan_fail(err, errlen, name, "sample %zu of position %zu is not finite (%s)",
                         i % (size_t)scan->samples, i / (size_t)scan->samples,
                         isnan(scan->data[i]) ? "NaN" : "infinite");
            return -1;
        }
    }
    return 0;
}
