/* Reading uwbscan/1: a one-line JSON header, then little-endian binary32
 * samples. Every byte is distrusted: the parser is meant to be fuzzed, so it
 * never reads past `len` and never allocates what the input only claims. */
#include "uwb/scan.h"

#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "uwb/read_file.h"
#include "uwbscan_check.h"

_Static_assert(sizeof(float) == 4, "uwbscan/1 samples are IEEE-754 binary32");

struct reader {
    const char *name;
    char *err;
    size_t errlen;
};

#define FAIL(rd, ...) uwbscan_fail((rd)->err, (rd)->errlen, (rd)->name, __VA_ARGS__)

/* ---- header keys ---------------------------------------------------- */

static const cJSON *key_item(const struct reader *rd, const cJSON *root, const char *key, int required)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (item == NULL && required)
        FAIL(rd, "header key '%s' is missing", key);
    return item;
}

static int read_number(const struct reader *rd, const cJSON *item, const char *key, double *out)
{
    if (!cJSON_IsNumber(item)) {
        FAIL(rd, "header key '%s' must be a number", key);
        return -1;
    }
    if (!isfinite(item->valuedouble)) {
        FAIL(rd, "header key '%s' is not a finite number", key);
        return -1;
    }
    *out = item->valuedouble;
    return 0;
}

/* JSON has only one number type; "integer" means a whole value in range.
 * The range is checked on the double so the conversion to int is defined. */
static int read_integer(const struct reader *rd, const cJSON *item, const char *key, int min, int max,
                        int *out)
{
    double value;
    if (read_number(rd, item, key, &value) != 0)
        return -1;
    if (value != floor(value)) {
        FAIL(rd, "header key '%s' must be an integer (got %.15g)", key, value);
        return -1;
    }
    if (value < min) {
        FAIL(rd, "header key '%s' is %.15g, must be at least %d", key, value, min);
        return -1;
    }
    if (value > max) {
        FAIL(rd, "header key '%s' is %.15g, over the limit of %d", key, value, max);
        return -1;
    }
    *out = (int)value;
    return 0;
}

static int read_pair(const struct reader *rd, const cJSON *item, const char *key, double out[2])
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 2 || !cJSON_IsNumber(item->child) ||
        !cJSON_IsNumber(item->child->next)) {
        FAIL(rd, "header key '%s' must be an array of exactly two numbers", key);
        return -1;
    }
    out[0] = item->child->valuedouble;
    out[1] = item->child->next->valuedouble;
    if (!isfinite(out[0]) || !isfinite(out[1])) {
        FAIL(rd, "header key '%s' holds a number that is not finite", key);
        return -1;
    }
    return 0;
}

static int read_optional_string(const struct reader *rd, const cJSON *root, const char *key, char **out)
{
    const cJSON *item = key_item(rd, root, key, 0);
    if (item == NULL)
        return 0;
    if (!cJSON_IsString(item) || item->valuestring == NULL) {
        FAIL(rd, "header key '%s' must be a string", key);
        return -1;
    }
    *out = strdup(item->valuestring);
    if (*out == NULL) {
        FAIL(rd, "out of memory");
        return -1;
    }
    return 0;
}

static int read_antenna_heights(const struct reader *rd, const cJSON *root, struct uwb_scan *scan)
{
    const cJSON *item = key_item(rd, root, "antenna_y_m", 1);
    if (item == NULL)
        return -1;
    if (!cJSON_IsArray(item)) {
        FAIL(rd, "header key 'antenna_y_m' must be an array of numbers");
        return -1;
    }
    /* Count without cJSON_GetArraySize's int so a long array cannot wrap. */
    size_t count = 0;
    for (const cJSON *v = item->child; v; v = v->next)
        count++;
    if (count != (size_t)scan->positions) {
        FAIL(rd, "antenna_y_m has %zu value%s, positions is %d", count, count == 1 ? "" : "s",
             scan->positions);
        return -1;
    }
    // NOLINTNEXTLINE(clang-analyzer-optin.portability.UnixAPI): count == positions >= 1 (read_integer above)
    scan->antenna_y_m = calloc(count, sizeof *scan->antenna_y_m);
    if (scan->antenna_y_m == NULL) {
        FAIL(rd, "out of memory");
        return -1;
    }
    size_t k = 0;
    for (const cJSON *v = item->child; v; v = v->next, k++) {
        if (!cJSON_IsNumber(v)) {
            FAIL(rd, "antenna_y_m[%zu] must be a number", k);
            return -1;
        }
        if (!isfinite(v->valuedouble)) {
            FAIL(rd, "antenna_y_m[%zu] is not a finite number", k);
            return -1;
        }
        scan->antenna_y_m[k] = v->valuedouble;
    }
    return 0;
}

static int read_extra_keys(const struct reader *rd, const cJSON *root, struct uwb_scan *scan)
{
    cJSON *extra = NULL;
    for (const cJSON *item = root->child; item; item = item->next) {
        if (uwbscan_is_standard_key(item->string))
            continue;
        if (extra == NULL && (extra = cJSON_CreateObject()) == NULL)
            goto oom;
        cJSON *copy = cJSON_Duplicate(item, 1);
        if (copy == NULL)
            goto oom;
        cJSON_AddItemToObject(extra, item->string, copy);
    }
    if (extra == NULL)
        return 0;
    scan->extra_json = cJSON_PrintUnformatted(extra);
    cJSON_Delete(extra);
    if (scan->extra_json == NULL) {
        FAIL(rd, "out of memory");
        return -1;
    }
    return 0;
oom:
    cJSON_Delete(extra);
    FAIL(rd, "out of memory");
    return -1;
}

static int read_header_keys(const struct reader *rd, const cJSON *root, struct uwb_scan *scan)
{
    const cJSON *item = key_item(rd, root, "format", 1);
    if (item == NULL)
        return -1;
    if (!cJSON_IsString(item) || item->valuestring == NULL) {
        FAIL(rd, "header key 'format' must be a string");
        return -1;
    }
    if (strcmp(item->valuestring, UWBSCAN_FORMAT) != 0) {
        FAIL(rd, "header key 'format' is \"%.64s\", expected \"%s\"", item->valuestring, UWBSCAN_FORMAT);
        return -1;
    }

    if ((item = key_item(rd, root, "positions", 1)) == NULL ||
        read_integer(rd, item, "positions", 1, UWBSCAN_MAX_POSITIONS, &scan->positions) ||
        (item = key_item(rd, root, "samples", 1)) == NULL ||
        read_integer(rd, item, "samples", 1, UWBSCAN_MAX_SAMPLES, &scan->samples) ||
        (item = key_item(rd, root, "sample_interval_s", 1)) == NULL ||
        read_number(rd, item, "sample_interval_s", &scan->sample_interval_s))
        return -1;
    if (scan->sample_interval_s <= 0) {
        FAIL(rd, "header key 'sample_interval_s' is %.15g, must be > 0", scan->sample_interval_s);
        return -1;
    }
    if ((item = key_item(rd, root, "t0_s", 1)) == NULL || read_number(rd, item, "t0_s", &scan->t0_s) ||
        read_antenna_heights(rd, root, scan) || (item = key_item(rd, root, "tx_m", 1)) == NULL ||
        read_pair(rd, item, "tx_m", scan->tx_m) || (item = key_item(rd, root, "rx_m", 1)) == NULL ||
        read_pair(rd, item, "rx_m", scan->rx_m))
        return -1;

    scan->eps_r = 1.0;
    if ((item = key_item(rd, root, "eps_r", 0)) != NULL) {
        if (read_number(rd, item, "eps_r", &scan->eps_r))
            return -1;
        if (scan->eps_r < 1.0) {
            FAIL(rd, "header key 'eps_r' is %.15g, must be at least 1", scan->eps_r);
            return -1;
        }
    }
    if ((item = key_item(rd, root, "target_z_m", 0)) != NULL) {
        if (read_pair(rd, item, "target_z_m", scan->target_z_m))
            return -1;
        if (!(scan->target_z_m[0] < scan->target_z_m[1])) {
            FAIL(rd, "header key 'target_z_m' is [%.15g, %.15g], near must be less than far",
                 scan->target_z_m[0], scan->target_z_m[1]);
            return -1;
        }
        scan->has_target_z = 1;
    }
    if ((item = key_item(rd, root, "stack", 0)) != NULL &&
        read_integer(rd, item, "stack", 1, INT_MAX, &scan->stack))
        return -1;
    if (read_optional_string(rd, root, "created", &scan->created) ||
        read_optional_string(rd, root, "scan_id", &scan->scan_id) ||
        read_optional_string(rd, root, "source", &scan->source) ||
        read_optional_string(rd, root, "comment", &scan->comment))
        return -1;
    return read_extra_keys(rd, root, scan);
}

/* ---- line 1 --------------------------------------------------------- */

/* Finds and parses the header line; *payload_at is where the samples begin. */
static int read_header(const struct reader *rd, const unsigned char *buf, size_t len, struct uwb_scan *scan,
                       size_t *payload_at)
{
    if (len == 0) {
        FAIL(rd, "file is empty (no uwbscan/1 header)");
        return -1;
    }
    /* Bounded search: a file without a newline must not make us walk it all. */
    size_t window = len < (size_t)UWBSCAN_MAX_HEADER_BYTES + 1 ? len : UWBSCAN_MAX_HEADER_BYTES + 1;
    const unsigned char *newline = memchr(buf, '\n', window);
    if (newline == NULL) {
        if (len > UWBSCAN_MAX_HEADER_BYTES)
            FAIL(rd, "header line is longer than the limit of %zu bytes (no newline within it)",
                 UWBSCAN_MAX_HEADER_BYTES);
        else
            FAIL(rd, "header line has no terminating newline (truncated, or not a uwbscan/1 "
                     "file)");
        return -1;
    }
    size_t header_len = (size_t)(newline - buf);
    *payload_at = header_len + 1;

    /* cJSON is lenient where JSON is not (it skips a byte-order mark and takes
     * any control byte as blank); other readers of our files may not be. */
    if (header_len >= 3 && buf[0] == 0xEF && buf[1] == 0xBB && buf[2] == 0xBF) {
        FAIL(rd, "header starts with a UTF-8 byte-order mark");
        return -1;
    }
    for (size_t i = 0; i < header_len; i++) {
        if (buf[i] < 0x20 && buf[i] != '\t' && buf[i] != '\r') {
            FAIL(rd, "header contains control byte 0x%02x at offset %zu", buf[i], i);
            return -1;
        }
    }
    /* An escaped NUL would silently cut a key or string short in C. */
    for (size_t i = 0; i + 1 < header_len; i++) {
        if (buf[i] != '\\')
            continue;
        if (buf[i + 1] == 'u' && header_len - i >= 6 && memcmp(buf + i + 2, "0000", 4) == 0) {
            FAIL(rd, "header contains the escape \\u0000 at offset %zu (NUL is not allowed)", i);
            return -1;
        }
        i++; /* skip the escaped character: an escaped backslash before u0000 is text */
    }
    size_t bad;
    if (!uwbscan_utf8_valid(buf, header_len, &bad)) {
        FAIL(rd, "header is not valid UTF-8 (byte %zu)", bad);
        return -1;
    }
    /* cJSON wants a terminated string; copy rather than trust a byte past len. */
    char *text = malloc(header_len + 1);
    if (text == NULL) {
        FAIL(rd, "out of memory");
        return -1;
    }
    memcpy(text, buf, header_len);
    text[header_len] = '\0';
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, header_len + 1, &end, 0);
    int rc = -1;
    const char *duplicate;
    if (root == NULL) {
        FAIL(rd, "header is not valid JSON (error near byte %td)", end ? end - text : (ptrdiff_t)0);
    } else if (end + strspn(end, " \t\r") != text + header_len) {
        FAIL(rd, "header line has text after the JSON value (byte %td)", end - text);
    } else if (!cJSON_IsObject(root)) {
        FAIL(rd, "header is not a JSON object");
    } else if ((duplicate = uwbscan_duplicate_key(root)) != NULL) {
        FAIL(rd, "header key '%.80s' appears more than once", duplicate);
    } else {
        rc = read_header_keys(rd, root, scan);
    }
    cJSON_Delete(root);
    free(text);
    return rc;
}

/* ---- payload -------------------------------------------------------- */

/* Assemble the value from bytes so the host's byte order never matters. */
static uint32_t load_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static int read_payload(const struct reader *rd, const unsigned char *payload, size_t have,
                        struct uwb_scan *scan)
{
    uint64_t want = uwbscan_payload_bytes(scan->positions, scan->samples);
    if ((uint64_t)have != want) {
        char why[64];
        if ((uint64_t)have < want)
            snprintf(why, sizeof why, "too short");
        else
            snprintf(why, sizeof why, "%" PRIu64 " trailing bytes", (uint64_t)have - want);
        FAIL(rd, "payload has %zu bytes, header promises %d x %d float32 = %" PRIu64 " bytes (%s)", have,
             scan->positions, scan->samples, want, why);
        return -1;
    }
    /* have == want, so want fits in size_t and the allocation is backed by input. */
    size_t count = have / 4;
    scan->data = malloc(count * sizeof *scan->data);
    if (scan->data == NULL) {
        FAIL(rd, "out of memory for %zu samples", count);
        return -1;
    }
    for (size_t i = 0; i < count; i++) {
        uint32_t bits = load_le32(payload + 4 * i);
        if ((bits & 0x7F800000u) == 0x7F800000u) {
            FAIL(rd, "sample %zu of position %zu is not finite (%s)", i % (size_t)scan->samples,
                 i / (size_t)scan->samples, uwbscan_nonfinite_kind(bits));
            return -1;
        }
        memcpy(&scan->data[i], &bits, sizeof bits);
    }
    return 0;
}

/* ---- entry points --------------------------------------------------- */

int uwbscan_parse(const void *buf, size_t len, const char *name, struct uwb_scan *scan, char *err,
                  size_t errlen)
{
    struct reader rd = {name ? name : "uwbscan", err, errlen};
    memset(scan, 0, sizeof *scan);
    if (buf == NULL && len > 0) {
        FAIL(&rd, "no buffer");
        return -1;
    }
    size_t payload_at = 0;
    if (read_header(&rd, buf, len, scan, &payload_at) != 0 ||
        uwbscan_check_fields(scan, rd.name, err, errlen) != 0 ||
        read_payload(&rd, (const unsigned char *)buf + payload_at, len - payload_at, scan) != 0) {
        uwb_scan_free(scan);
        return -1;
    }
    return 0;
}

/* Largest file that could be valid: header line plus the biggest payload.
 * A bigger one is refused by its size, before anything is read. */
#define UWBSCAN_MAX_FILE_BYTES \
    ((uint64_t)UWBSCAN_MAX_HEADER_BYTES + 1 + (uint64_t)UWBSCAN_MAX_SAMPLE_COUNT * 4u)

int uwbscan_read_file(const char *path, struct uwb_scan *scan, char *err, size_t errlen)
{
    memset(scan, 0, sizeof *scan);
    char *buf;
    size_t len;
    size_t max_bytes = UWBSCAN_MAX_FILE_BYTES > SIZE_MAX ? SIZE_MAX : (size_t)UWBSCAN_MAX_FILE_BYTES;
    enum uwb_read_result read_result = uwb_read_file(path, max_bytes, &buf, &len, err, errlen);
    if (read_result == UWB_READ_TOO_BIG && err != NULL && errlen > 0) {
        size_t used = strlen(err);
        snprintf(err + used, errlen - used,
                 ": larger than any scan uwbd reads (over the limit of %zu samples, %d MiB of float32, "
                 "and a 1 MiB header)",
                 UWBSCAN_MAX_SAMPLE_COUNT, UWBSCAN_MAX_SAMPLE_MIB);
    }
    if (read_result != UWB_READ_OK)
        return -1;
    int rc = uwbscan_parse(buf, len, path, scan, err, errlen);
    free(buf);
    return rc;
}
