/* Writing uwbscan/1. The scan is checked with the reader's own rules first,
 * so a file we write is always a file we can read back. */
#include "uwb/scan.h"

#include <errno.h>
#include <locale.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "uwb/atomic_file.h"
#include "uwbscan_check.h"

/* ---- header --------------------------------------------------------- */

/* Shortest of %.15g..%.17g that reads back as exactly the same double
 * (sign of zero included), written with '.' whatever the locale. */
static void format_double(double value, char out[40])
{
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(out, 40, "%.*g", digits, value);
        double back = strtod(out, NULL);
        if (back == value && signbit(back) == signbit(value))
            break;
    }
    const char *point = localeconv()->decimal_point;
    if (point[0] != '.' && point[0] != '\0' && point[1] == '\0') {
        char *p = strchr(out, point[0]);
        if (p)
            *p = '.';
    }
}

/* cJSON prints -0.0 as 0 and picks its own digits; a raw item keeps ours. */
static cJSON *number_item(double value)
{
    char text[40];
    format_double(value, text);
    return cJSON_CreateRaw(text);
}

static cJSON *pair_item(const double pair[2])
{
    cJSON *array = cJSON_CreateArray();
    cJSON *a = number_item(pair[0]), *b = number_item(pair[1]);
    if (array == NULL || a == NULL || b == NULL) {
        cJSON_Delete(array);
        cJSON_Delete(a);
        cJSON_Delete(b);
        return NULL;
    }
    cJSON_AddItemToArray(array, a);
    cJSON_AddItemToArray(array, b);
    return array;
}

/* Adds item under key; -1 when item could not be made (NULL) or added
 * (cJSON copies the key: no memory), and then the item is deleted. */
static int add(cJSON *object, const char *key, cJSON *item)
{
    if (item == NULL)
        return -1;
    if (!cJSON_AddItemToObject(object, key, item)) {
        cJSON_Delete(item);
        return -1;
    }
    return 0;
}

static int add_string(cJSON *object, const char *key, const char *value)
{
    return value ? add(object, key, cJSON_CreateString(value)) : 0;
}

static cJSON *header_object(const struct uwb_scan *scan)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *antenna = cJSON_CreateArray();
    cJSON *extra = NULL;
    if (root == NULL || antenna == NULL)
        goto fail;
    for (int k = 0; k < scan->positions; k++) {
        cJSON *v = number_item(scan->antenna_y_m[k]);
        if (v == NULL)
            goto fail;
        cJSON_AddItemToArray(antenna, v);
    }
    char count[16];
    if (add(root, "format", cJSON_CreateString(UWBSCAN_FORMAT)))
        goto fail;
    snprintf(count, sizeof count, "%d", scan->positions);
    if (add(root, "positions", cJSON_CreateRaw(count)))
        goto fail;
    snprintf(count, sizeof count, "%d", scan->samples);
    if (add(root, "samples", cJSON_CreateRaw(count)) ||
        add(root, "sample_interval_s", number_item(scan->sample_interval_s)) ||
        add(root, "t0_s", number_item(scan->t0_s)))
        goto fail;
    cJSON *positions = antenna;
    antenna = NULL; /* add() owns it now, added or deleted */
    if (add(root, "antenna_y_m", positions))
        goto fail;
    if (add(root, "tx_m", pair_item(scan->tx_m)) || add(root, "rx_m", pair_item(scan->rx_m)) ||
        add(root, "eps_r", number_item(scan->eps_r)))
        goto fail;
    if (scan->has_target_z && add(root, "target_z_m", pair_item(scan->target_z_m)))
        goto fail;
    if (scan->stack > 0) {
        snprintf(count, sizeof count, "%d", scan->stack);
        if (add(root, "stack", cJSON_CreateRaw(count)))
            goto fail;
    }
    if (add_string(root, "created", scan->created) || add_string(root, "scan_id", scan->scan_id) ||
        add_string(root, "source", scan->source) || add_string(root, "comment", scan->comment))
        goto fail;
    if (scan->extra_json) {
        /* Already checked to be an object with no standard or repeated keys. */
        extra = cJSON_Parse(scan->extra_json);
        if (extra == NULL)
            goto fail;
        while (extra->child) {
            cJSON *item = cJSON_DetachItemViaPointer(extra, extra->child);
            if (!cJSON_AddItemToObject(root, item->string, item)) {
                cJSON_Delete(item);
                cJSON_Delete(extra);
                goto fail;
            }
        }
        cJSON_Delete(extra);
    }
    return root;
fail:
    cJSON_Delete(antenna);
    cJSON_Delete(root);
    return NULL;
}

/* The header line's text (without '\n'), malloc'd, after every check. */
static char *checked_header(const struct uwb_scan *scan, const char *name, char *err, size_t errlen)
{
    if (uwbscan_check_fields(scan, name, err, errlen) != 0 ||
        uwbscan_check_samples(scan, name, err, errlen) != 0)
        return NULL;
    cJSON *root = header_object(scan);
    char *text = root ? cJSON_PrintUnformatted(root) : NULL;
    cJSON_Delete(root);
    if (text == NULL) {
        uwbscan_fail(err, errlen, name, "cannot build header: %s", strerror(ENOMEM));
        return NULL;
    }
    size_t len = strlen(text);
    if (len > UWBSCAN_MAX_HEADER_BYTES) {
        uwbscan_fail(err, errlen, name, "header would be %zu bytes, over the limit of %zu", len,
                     UWBSCAN_MAX_HEADER_BYTES);
        free(text);
        return NULL;
    }
    return text;
}

/* ---- payload -------------------------------------------------------- */

/* Byte by byte, so the file is little-endian whatever the host is. */
static void encode_samples(const float *data, size_t count, unsigned char *out)
{
    for (size_t i = 0; i < count; i++) {
        uint32_t bits;
        memcpy(&bits, &data[i], sizeof bits);
        out[4 * i + 0] = (unsigned char)(bits & 0xFF);
        out[4 * i + 1] = (unsigned char)((bits >> 8) & 0xFF);
        out[4 * i + 2] = (unsigned char)((bits >> 16) & 0xFF);
        out[4 * i + 3] = (unsigned char)((bits >> 24) & 0xFF);
    }
}

/* ---- entry points --------------------------------------------------- */

int uwbscan_serialise(const struct uwb_scan *scan, unsigned char **buf, size_t *len, char *err, size_t errlen)
{
    *buf = NULL;
    *len = 0;
    const char *name = "scan";
    char *header = checked_header(scan, name, err, errlen);
    if (header == NULL)
        return -1;
    size_t header_len = strlen(header);
    uint64_t payload = uwbscan_payload_bytes(scan->positions, scan->samples);
    if (payload > SIZE_MAX - header_len - 1) { /* only a 32-bit size_t gets here */
        free(header);
        uwbscan_fail(err, errlen, name, "%d x %d samples do not fit in memory", scan->positions,
                     scan->samples);
        return -1;
    }
    size_t total = header_len + 1 + (size_t)payload;
    unsigned char *out = malloc(total);
    if (out == NULL) {
        free(header);
        uwbscan_fail(err, errlen, name, "cannot allocate %zu bytes: %s", total, strerror(ENOMEM));
        return -1;
    }
    // NOLINTNEXTLINE(bugprone-not-null-terminated-result): bytes of a file, not a C string
    memcpy(out, header, header_len);
    out[header_len] = '\n';
    free(header);
    encode_samples(scan->data, (size_t)payload / 4, out + header_len + 1);
    *buf = out;
    *len = total;
    return 0;
}

int uwbscan_write_file(const char *path, const struct uwb_scan *scan, char *err, size_t errlen)
{
    char *header = checked_header(scan, path, err, errlen);
    if (header == NULL)
        return -1;
    struct atomic_file af;
    if (uwb_atomic_file_open(&af, path, err, errlen) != 0) {
        free(header);
        return -1;
    }
    size_t header_len = strlen(header);
    int ok = fwrite(header, 1, header_len, af.fp) == header_len && fputc('\n', af.fp) != EOF;
    free(header);

    /* Stream the samples in blocks: no second copy of a large scan in memory. */
    enum { BLOCK = 4096 };
    unsigned char bytes[4 * BLOCK];
    size_t count = (size_t)scan->positions * (size_t)scan->samples;
    for (size_t done = 0; ok && done < count;) {
        size_t n = count - done < BLOCK ? count - done : BLOCK;
        encode_samples(scan->data + done, n, bytes);
        ok = fwrite(bytes, 4, n, af.fp) == n;
        done += n;
    }
    if (!ok) {
        int e = errno;
        uwb_atomic_file_abort(&af);
        uwbscan_fail(err, errlen, path, "cannot write temporary file: %s", strerror(e));
        return -1;
    }
    return uwb_atomic_file_commit(&af, err, errlen);
}
