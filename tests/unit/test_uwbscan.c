/* uwbscan/1 reader and writer: every rejection the format names, round
 * trips that must be bit-exact, the FDTD fixtures, and bounds safety. */
#include "scratch_support.h"
#include "unity.h"

#include <dirent.h>
#include <float.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cJSON.h>

#include "uwb/scan.h"

#define NAME "t.uwbscan"

/* A valid 2 x 3 header; tests edit one key at a time. */
static const char GOOD_HEADER[] = "{\"format\":\"uwbscan/1\",\"positions\":2,\"samples\":3,"
                                  "\"sample_interval_s\":1e-11,\"t0_s\":-2e-10,\"antenna_y_m\":[0,0.1],"
                                  "\"tx_m\":[-0.02,0],\"rx_m\":[0.02,0]}";
#define GOOD_FLOATS 6

static char tmpdir[64];
static char err[512];

/* ---- helpers -------------------------------------------------------- */

static int count_entries(const char *dir)
{
    int n = 0;
    DIR *d = opendir(dir);
    TEST_ASSERT_NOT_NULL(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            n++;
    closedir(d);
    return n;
}

static void put_le32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* header + '\n' + nfloats samples (0, 0.25, 0.5, ...), little-endian. */
static unsigned char *build_file(const char *header, size_t nfloats, size_t *len)
{
    size_t hlen = strlen(header);
    *len = hlen + 1 + 4 * nfloats;
    unsigned char *buf = malloc(*len);
    TEST_ASSERT_NOT_NULL(buf);
    memcpy(buf, header, hlen);
    buf[hlen] = '\n';
    for (size_t i = 0; i < nfloats; i++)
        put_le32(buf + hlen + 1 + 4 * i, float_bits(0.25f * (float)i));
    return buf;
}

/* GOOD_HEADER with `key` set to the raw JSON `value` (removed if NULL). */
static char *header_with(const char *key, const char *value)
{
    cJSON *root = cJSON_Parse(GOOD_HEADER);
    TEST_ASSERT_NOT_NULL(root);
    cJSON_DeleteItemFromObjectCaseSensitive(root, key);
    if (value) /* raw: cJSON would turn 1e999 into null if it parsed it */
        cJSON_AddItemToObject(root, key, cJSON_CreateRaw(value));
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    TEST_ASSERT_NOT_NULL(text);
    return text;
}

static int is_zeroed(const struct uwb_scan *s)
{
    static const struct uwb_scan zero;
    return memcmp(s, &zero, sizeof zero) == 0;
}

/* Parse a heap copy of exactly len bytes (so ASan sees any over-read) and
 * require failure with a "t.uwbscan: ..." message containing `needle`. */
static void expect_reject_buffer(const unsigned char *buf, size_t len, const char *needle)
{
    unsigned char *copy = malloc(len ? len : 1);
    TEST_ASSERT_NOT_NULL(copy);
    if (len)
        memcpy(copy, buf, len);
    struct uwb_scan scan;
    memset(&scan, 0xA5, sizeof scan);
    err[0] = '\0';
    int rc = uwbscan_parse(copy, len, NAME, &scan, err, sizeof err);
    free(copy);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, rc, needle);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err, NAME ": ", strlen(NAME) + 2) == 0, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, needle), err);
    TEST_ASSERT_TRUE_MESSAGE(is_zeroed(&scan), "failed parse must leave the scan zeroed");
}

static void expect_reject(const char *header, size_t nfloats, const char *needle)
{
    size_t len;
    unsigned char *buf = build_file(header, nfloats, &len);
    expect_reject_buffer(buf, len, needle);
    free(buf);
}

static void expect_key_reject(const char *key, const char *value, const char *needle)
{
    char *header = header_with(key, value);
    expect_reject(header, GOOD_FLOATS, needle);
    free(header);
}

static void expect_key_accept(const char *key, const char *value, struct uwb_scan *scan)
{
    char *header = header_with(key, value);
    size_t len;
    unsigned char *buf = build_file(header, GOOD_FLOATS, &len);
    int rc = uwbscan_parse(buf, len, NAME, scan, err, sizeof err);
    free(buf);
    free(header);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, err);
}

/* A scan using every field, with values that test the encoding's edges. */
static void make_full_scan(struct uwb_scan *s, int positions, int samples)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_scan_alloc(s, positions, samples, err, sizeof err), err);
    s->sample_interval_s = 1.0 / 212e9;
    s->t0_s = -7.071067811865476e-10;
    for (int k = 0; k < positions; k++)
        s->antenna_y_m[k] = 0.1 + 0.2 * k / 3.0;
    s->tx_m[0] = -0.02;
    s->tx_m[1] = -0.0; /* sign of zero must survive the header */
    s->rx_m[0] = 0.1 + 0.2;
    s->rx_m[1] = 5e-324; /* subnormal double */
    s->eps_r = 2.2;
    s->has_target_z = 1;
    s->target_z_m[0] = 0.3;
    s->target_z_m[1] = 0.6;
    s->stack = 64;
    s->created = strdup("2024-05-01T12:00:00Z");
    s->scan_id = strdup("TX7-0042");
    s->source = strdup("uwbd test \xc3\xa9\xe2\x82\xac"); /* é€: non-ASCII UTF-8 */
    s->comment = strdup("line one\nline \"two\"\t\\ end");
    s->extra_json = strdup("{\"operator\":\"ana\",\"cal\":{\"gain_db\":[1.5,-3],\"ok\":true},"
                           "\"note\":null}");
    const float special[] = {0.0f,      -0.0f,   1.0f,     -2.5f,       FLT_MIN, FLT_MIN / 8.0f,
                             -1.4e-45f, FLT_MAX, -FLT_MAX, 3.14159265f, 1e-30f};
    size_t n = (size_t)positions * (size_t)samples;
    for (size_t i = 0; i < n; i++)
        s->data[i] = i < sizeof special / sizeof special[0] ? special[i] : (float)sin(0.37 * (double)i);
}

static void assert_same_double(double a, double b, const char *what)
{
    TEST_ASSERT_TRUE_MESSAGE(memcmp(&a, &b, sizeof a) == 0, what);
}

static void assert_same_string(const char *a, const char *b, const char *what)
{
    if (a == NULL || b == NULL) {
        TEST_ASSERT_TRUE_MESSAGE(a == b, what);
    } else {
        TEST_ASSERT_EQUAL_STRING_MESSAGE(a, b, what);
    }
}

static void assert_same_scan(const struct uwb_scan *a, const struct uwb_scan *b)
{
    TEST_ASSERT_EQUAL_INT(a->positions, b->positions);
    TEST_ASSERT_EQUAL_INT(a->samples, b->samples);
    assert_same_double(a->sample_interval_s, b->sample_interval_s, "sample_interval_s");
    assert_same_double(a->t0_s, b->t0_s, "t0_s");
    for (int k = 0; k < a->positions; k++)
        assert_same_double(a->antenna_y_m[k], b->antenna_y_m[k], "antenna_y_m");
    assert_same_double(a->tx_m[0], b->tx_m[0], "tx_m[0]");
    assert_same_double(a->tx_m[1], b->tx_m[1], "tx_m[1]");
    assert_same_double(a->rx_m[0], b->rx_m[0], "rx_m[0]");
    assert_same_double(a->rx_m[1], b->rx_m[1], "rx_m[1]");
    assert_same_double(a->eps_r, b->eps_r, "eps_r");
    TEST_ASSERT_EQUAL_INT(a->has_target_z, b->has_target_z);
    if (a->has_target_z) {
        assert_same_double(a->target_z_m[0], b->target_z_m[0], "target_z_m[0]");
        assert_same_double(a->target_z_m[1], b->target_z_m[1], "target_z_m[1]");
    }
    TEST_ASSERT_EQUAL_INT(a->stack, b->stack);
    assert_same_string(a->created, b->created, "created");
    assert_same_string(a->scan_id, b->scan_id, "scan_id");
    assert_same_string(a->source, b->source, "source");
    assert_same_string(a->comment, b->comment, "comment");
    if (a->extra_json == NULL || b->extra_json == NULL) {
        TEST_ASSERT_TRUE_MESSAGE(a->extra_json == b->extra_json, "extra_json");
    } else {
        cJSON *ja = cJSON_Parse(a->extra_json), *jb = cJSON_Parse(b->extra_json);
        TEST_ASSERT_TRUE_MESSAGE(cJSON_Compare(ja, jb, 1), b->extra_json);
        cJSON_Delete(ja);
        cJSON_Delete(jb);
    }
    size_t n = (size_t)a->positions * (size_t)a->samples;
    TEST_ASSERT_TRUE_MESSAGE(memcmp(a->data, b->data, n * sizeof(float)) == 0,
                             "samples must be bit-identical");
}

void setUp(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/test_uwbscan.XXXXXX");
    TEST_ASSERT_NOT_NULL(mkdtemp(tmpdir));
    err[0] = '\0';
}

void tearDown(void)
{
    cJSON_InitHooks(NULL); /* a failed test may leave the failing allocator in place */
    scratch_remove_tree(tmpdir);
}

/* ---- the good header really is good ---------------------------------- */

static void test_good_header_parses(void)
{
    struct uwb_scan scan;
    expect_key_accept("comment", NULL, &scan);
    TEST_ASSERT_EQUAL_INT(2, scan.positions);
    TEST_ASSERT_EQUAL_INT(3, scan.samples);
    TEST_ASSERT_EQUAL_DOUBLE(1e-11, scan.sample_interval_s);
    TEST_ASSERT_EQUAL_DOUBLE(-2e-10, scan.t0_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.1, scan.antenna_y_m[1]);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, scan.eps_r); /* default */
    TEST_ASSERT_EQUAL_INT(0, scan.has_target_z);
    TEST_ASSERT_EQUAL_INT(0, scan.stack);
    TEST_ASSERT_NULL(scan.created);
    TEST_ASSERT_NULL(scan.extra_json);
    TEST_ASSERT_EQUAL_FLOAT(1.25f, scan.data[5]); /* position 1, sample 2 */
    uwb_scan_free(&scan);
}

/* ---- rejections listed in the format document ------------------------ */

static void test_rejects_empty_input(void)
{
    expect_reject_buffer((const unsigned char *)"", 0, "file is empty");
}

static void test_rejects_header_without_newline(void)
{
    expect_reject_buffer((const unsigned char *)GOOD_HEADER, strlen(GOOD_HEADER),
                         "header line has no terminating newline");
}

static void test_rejects_malformed_json_header(void)
{
    expect_reject("{\"format\":\"uwbscan/1\",\"positions\":2,", GOOD_FLOATS, "header is not valid JSON");
}

static void test_rejects_header_that_is_not_an_object(void)
{
    expect_reject("[\"uwbscan/1\",2,3]", GOOD_FLOATS, "header is not a JSON object");
}

static void test_rejects_text_after_header_object(void)
{
    char header[512];
    snprintf(header, sizeof header, "%s {}", GOOD_HEADER);
    expect_reject(header, GOOD_FLOATS, "header line has text after the JSON value");
}

static void test_rejects_each_missing_required_key(void)
{
    static const char *const required[] = {"format", "positions",   "samples", "sample_interval_s",
                                           "t0_s",   "antenna_y_m", "tx_m",    "rx_m"};
    for (size_t i = 0; i < sizeof required / sizeof required[0]; i++) {
        char needle[128];
        snprintf(needle, sizeof needle, NAME ": header key '%s' is missing", required[i]);
        expect_key_reject(required[i], NULL, needle);
    }
}

static void test_rejects_wrongly_typed_keys(void)
{
    static const struct {
        const char *key, *value, *needle;
    } cases[] = {
        {"format", "1", "header key 'format' must be a string"},
        {"positions", "\"2\"", "header key 'positions' must be a number"},
        {"samples", "true", "header key 'samples' must be a number"},
        {"sample_interval_s", "\"1e-11\"", "header key 'sample_interval_s' must be a number"},
        {"t0_s", "null", "header key 't0_s' must be a number"},
        {"antenna_y_m", "0", "header key 'antenna_y_m' must be an array of numbers"},
        {"antenna_y_m", "[0,\"0.1\"]", "antenna_y_m[1] must be a number"},
        {"tx_m", "{\"dy\":0,\"dz\":0}", "header key 'tx_m' must be an array of exactly two"},
        {"rx_m", "\"0.02,0\"", "header key 'rx_m' must be an array of exactly two"},
        {"eps_r", "\"2.2\"", "header key 'eps_r' must be a number"},
        {"target_z_m", "0.4", "header key 'target_z_m' must be an array of exactly two"},
        {"stack", "\"64\"", "header key 'stack' must be a number"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        expect_key_reject(cases[i].key, cases[i].value, cases[i].needle);
}

static void test_rejects_payload_too_short(void)
{
    char *header = header_with("comment", NULL);
    expect_reject(header, GOOD_FLOATS - 1,
                  NAME ": payload has 20 bytes, header promises 2 x 3 float32 = 24 bytes "
                       "(too short)");
    /* A partial sample is short too. */
    size_t len;
    unsigned char *buf = build_file(header, GOOD_FLOATS, &len);
    expect_reject_buffer(buf, len - 1, "payload has 23 bytes");
    free(buf);
    free(header);
}

static void test_rejects_trailing_bytes(void)
{
    size_t len;
    unsigned char *buf = build_file(GOOD_HEADER, GOOD_FLOATS, &len);
    unsigned char *longer = malloc(len + 3);
    TEST_ASSERT_NOT_NULL(longer);
    memcpy(longer, buf, len);
    memcpy(longer + len, "xyz", 3);
    expect_reject_buffer(longer, len + 3,
                         "payload has 27 bytes, header promises 2 x 3 float32 = 24 bytes "
                         "(3 trailing bytes)");
    free(longer);
    free(buf);
}

static void test_rejects_nan_sample(void)
{
    size_t len;
    unsigned char *buf = build_file(GOOD_HEADER, GOOD_FLOATS, &len);
    /* position 1, sample 2 = float index 5; a quiet NaN. */
    put_le32(buf + strlen(GOOD_HEADER) + 1 + 4 * 5, 0x7FC00000u);
    expect_reject_buffer(buf, len, NAME ": sample 2 of position 1 is not finite (NaN)");
    free(buf);
}

static void test_rejects_infinite_sample(void)
{
    size_t len;
    unsigned char *buf = build_file(GOOD_HEADER, GOOD_FLOATS, &len);
    put_le32(buf + strlen(GOOD_HEADER) + 1 + 4 * 1, 0xFF800000u); /* -inf */
    expect_reject_buffer(buf, len, NAME ": sample 1 of position 0 is not finite (infinite)");
    free(buf);
}

static void test_rejects_zero_positions_and_samples(void)
{
    expect_key_reject("positions", "0", "header key 'positions' is 0, must be at least 1");
    expect_key_reject("samples", "0", "header key 'samples' is 0, must be at least 1");
    expect_key_reject("positions", "-3", "header key 'positions' is -3, must be at least 1");
}

static void test_rejects_too_many_positions(void)
{
    expect_key_reject("positions", "4097", "header key 'positions' is 4097, over the limit of 4096");
    expect_key_reject("positions", "1e300", "header key 'positions' is 1e+300, over the limit of 4096");
}

static void test_rejects_too_many_samples(void)
{
    expect_key_reject("samples", "1048577", "header key 'samples' is 1048577, over the limit of 1048576");
}

static void test_rejects_nonpositive_sample_interval(void)
{
    expect_key_reject("sample_interval_s", "0", "header key 'sample_interval_s' is 0, must be > 0");
    expect_key_reject("sample_interval_s", "-4.7e-12",
                      "header key 'sample_interval_s' is -4.7e-12, must be > 0");
}

static void test_rejects_antenna_count_mismatch(void)
{
    expect_key_reject("antenna_y_m", "[0]", NAME ": antenna_y_m has 1 value, positions is 2");
    expect_key_reject("antenna_y_m", "[0,0.1,0.2]", "antenna_y_m has 3 values, positions is 2");
}

/* ---- further rejections ---------------------------------------------- */

static void test_rejects_header_over_one_mebibyte(void)
{
    /* No newline at all within the limit: must stop looking, not scan on. */
    size_t len = UWBSCAN_MAX_HEADER_BYTES + 100;
    unsigned char *buf = malloc(len);
    TEST_ASSERT_NOT_NULL(buf);
    memset(buf, ' ', len);
    buf[0] = '{';
    buf[len - 1] = '\n';
    expect_reject_buffer(buf, len, "header line is longer than the limit of 1048576 bytes");
    free(buf);
}

/* Pad GOOD_HEADER with blanks after '{' to exactly `header_len` bytes. */
static unsigned char *padded_file(size_t header_len, size_t *len)
{
    size_t good = strlen(GOOD_HEADER);
    char *header = malloc(header_len + 1);
    TEST_ASSERT_NOT_NULL(header);
    header[0] = '{';
    memset(header + 1, ' ', header_len - good);
    memcpy(header + 1 + (header_len - good), GOOD_HEADER + 1, good - 1);
    header[header_len] = '\0';
    unsigned char *buf = build_file(header, GOOD_FLOATS, len);
    free(header);
    return buf;
}

static void test_header_limit_is_exactly_one_mebibyte(void)
{
    size_t len;
    unsigned char *buf = padded_file(UWBSCAN_MAX_HEADER_BYTES, &len);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &scan, err, sizeof err), err);
    uwb_scan_free(&scan);
    free(buf);

    buf = padded_file(UWBSCAN_MAX_HEADER_BYTES + 1, &len);
    expect_reject_buffer(buf, len, "header line is longer than the limit");
    free(buf);
}

static void test_rejects_control_bytes_in_header(void)
{
    char header[512];
    snprintf(header, sizeof header, "%s", GOOD_HEADER);
    header[1] = '\x01';
    expect_reject(header, GOOD_FLOATS, "header contains control byte 0x01 at offset 1");

    /* An embedded NUL must not cut the header short silently. */
    size_t len;
    unsigned char *buf = build_file(GOOD_HEADER, GOOD_FLOATS, &len);
    buf[5] = '\0';
    expect_reject_buffer(buf, len, "header contains control byte 0x00 at offset 5");
    free(buf);
}

static void test_rejects_escaped_nul(void)
{
    char header[512];
    snprintf(header, sizeof header, "{\"comment\":\"a\\u0000b\",%s", GOOD_HEADER + 1);
    expect_reject(header, GOOD_FLOATS, "header contains the escape \\u0000 at offset 13");

    /* An escaped backslash followed by "u0000" is just text. */
    struct uwb_scan scan;
    expect_key_accept("comment", "\"a\\\\u0000\"", &scan);
    TEST_ASSERT_EQUAL_STRING("a\\u0000", scan.comment);
    uwb_scan_free(&scan);
}

static void test_rejects_invalid_utf8(void)
{
    /* Overlong '/', a lone continuation byte, and a UTF-16 surrogate. */
    static const char *const bad[] = {"\xc0\xaf", "\x80", "\xed\xa0\x80", "\xf4\x90\x80\x80"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char header[512];
        snprintf(header, sizeof header, "{\"comment\":\"%s\",%s", bad[i], GOOD_HEADER + 1);
        expect_reject(header, GOOD_FLOATS, "header is not valid UTF-8 (byte 12)");
    }
}

static void test_rejects_byte_order_mark(void)
{
    char header[512];
    snprintf(header, sizeof header, "\xef\xbb\xbf%s", GOOD_HEADER);
    expect_reject(header, GOOD_FLOATS, "header starts with a UTF-8 byte-order mark");
}

static void test_rejects_duplicate_key(void)
{
    char header[512];
    snprintf(header, sizeof header, "{\"positions\":3,%s", GOOD_HEADER + 1);
    expect_reject(header, GOOD_FLOATS, "header key 'positions' appears more than once");
}

static void test_rejects_wrong_format_value(void)
{
    expect_key_reject("format", "\"uwbscan/2\"",
                      NAME ": header key 'format' is \"uwbscan/2\", expected \"uwbscan/1\"");
    expect_key_reject("format", "\"UWBSCAN/1\"", "expected \"uwbscan/1\"");
}

static void test_rejects_fractional_positions_and_samples(void)
{
    expect_key_reject("positions", "21.5", "header key 'positions' must be an integer (got 21.5)");
    expect_key_reject("samples", "2.000001", "header key 'samples' must be an integer");
}

static void test_accepts_integral_number_written_with_exponent(void)
{
    struct uwb_scan scan;
    expect_key_accept("samples", "3.0e0", &scan);
    TEST_ASSERT_EQUAL_INT(3, scan.samples);
    uwb_scan_free(&scan);
}

static void test_rejects_nonfinite_numbers(void)
{
    /* 1e999 overflows to infinity when parsed. */
    expect_key_reject("sample_interval_s", "1e999", "header key 'sample_interval_s' is not a finite number");
    expect_key_reject("t0_s", "-1e999", "header key 't0_s' is not a finite number");
    expect_key_reject("antenna_y_m", "[0,1e999]", "antenna_y_m[1] is not a finite number");
    expect_key_reject("tx_m", "[1e999,0]", "header key 'tx_m' holds a number that is not finite");
}

static void test_rejects_tx_rx_not_pairs(void)
{
    static const char *const bad[] = {"[]", "[0.02]", "[0.02,0,0]", "[0.02,\"0\"]", "[[0.02],0]", "[null,0]"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        expect_key_reject("tx_m", bad[i], "header key 'tx_m' must be an array of exactly two numbers");
        expect_key_reject("rx_m", bad[i], "header key 'rx_m' must be an array of exactly two numbers");
    }
}

static void test_rejects_bad_target_z(void)
{
    expect_key_reject("target_z_m", "[0.6,0.3]",
                      "header key 'target_z_m' is [0.6, 0.3], "
                      "near must be less than far");
    expect_key_reject("target_z_m", "[0.4,0.4]", "near must be less than far");
    expect_key_reject("target_z_m", "[0.4]", "header key 'target_z_m' must be an array");
    expect_key_reject("target_z_m", "[0.3,0.4,0.5]", "header key 'target_z_m' must be an array");
}

static void test_rejects_bad_eps_r(void)
{
    expect_key_reject("eps_r", "0.5", "header key 'eps_r' is 0.5, must be at least 1");
    expect_key_reject("eps_r", "-2.2", "header key 'eps_r' is -2.2, must be at least 1");
    expect_key_reject("eps_r", "1e999", "header key 'eps_r' is not a finite number");
    expect_key_reject("eps_r", "null", "header key 'eps_r' must be a number");
}

static void test_rejects_stack_not_positive_integer(void)
{
    expect_key_reject("stack", "0", "header key 'stack' is 0, must be at least 1");
    expect_key_reject("stack", "-8", "header key 'stack' is -8, must be at least 1");
    expect_key_reject("stack", "2.5", "header key 'stack' must be an integer (got 2.5)");
    expect_key_reject("stack", "3e10", "header key 'stack' is 30000000000, over the limit");
}

static void test_rejects_optional_strings_of_wrong_type(void)
{
    static const char *const keys[] = {"created", "scan_id", "source", "comment"};
    static const char *const values[] = {"1", "null", "[\"a\"]", "{}", "true"};
    for (size_t k = 0; k < 4; k++) {
        for (size_t v = 0; v < 5; v++) {
            char needle[128];
            snprintf(needle, sizeof needle, "header key '%s' must be a string", keys[k]);
            expect_key_reject(keys[k], values[v], needle);
        }
    }
}

/* Issue 17, break 5: the paper fixture's positions spread over 600 m took
 * 38 s and 3.3 GB and gave a confident figure; a 1 nm step ended in a grid
 * of -2147483647 rows. Break 9: a duplicated position gave a confident
 * alarm. The rig's limits (uwb/scan.h) are checked when the file is read. */
static void test_rejects_what_the_rig_cannot_record(void)
{
    expect_key_reject("antenna_y_m", "[0,600]",
                      "antenna_y_m spans 600 m, over the rig's largest travel of 5 m");
    expect_key_reject("antenna_y_m", "[0,1e-9]", "under the smallest step of 1 mm");
    expect_key_reject("antenna_y_m", "[0.1,0.1]", "antenna_y_m[1] = 0.1 m repeats antenna_y_m[0] = 0.1 m");
    expect_key_reject("antenna_y_m", "[0.1,0]", "antenna_y_m[1] = 0 m is below antenna_y_m[0] = 0.1 m");
    expect_key_reject("sample_interval_s", "1e-3",
                      "sample_interval_s is 0.001 s, outside what a UWB digitiser records");
    expect_key_reject("sample_interval_s", "1e-300", "outside what a UWB digitiser records");
    expect_key_reject("t0_s", "-1e302", "t0_s is -1e+302 s, beyond the limit");
    expect_key_reject("tx_m", "[-1e302,0]", "tx_m[0] is -1e+302 m, over the limit of 1 m");
    expect_key_reject("rx_m", "[0,2]", "rx_m[1] is 2 m, over the limit");
    expect_key_reject("eps_r", "1e300", "eps_r is 1e+300, over the limit of 100");
    expect_key_reject("target_z_m", "[0.3,1e302]", "target_z_m is [0.3, 1e+302] m, outside 0..10 m");
    expect_key_reject("target_z_m", "[-5,1]", "outside 0..10 m");
    /* the limits themselves are accepted */
    char *header = header_with("antenna_y_m", "[0,5]");
    size_t len;
    unsigned char *buf = build_file(header, GOOD_FLOATS, &len);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &scan, err, sizeof err), err);
    uwb_scan_free(&scan);
    free(buf);
    free(header);
    header = header_with("antenna_y_m", "[0,0.001]");
    buf = build_file(header, GOOD_FLOATS, &len);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &scan, err, sizeof err), err);
    uwb_scan_free(&scan);
    free(buf);
    free(header);
}

/* GOOD_HEADER for a scan of `positions` x `samples`, positions 1 mm apart. */
static char *header_shaped(int positions, int samples)
{
    cJSON *root = cJSON_Parse(GOOD_HEADER);
    TEST_ASSERT_NOT_NULL(root);
    cJSON_ReplaceItemInObjectCaseSensitive(root, "positions", cJSON_CreateNumber(positions));
    cJSON_ReplaceItemInObjectCaseSensitive(root, "samples", cJSON_CreateNumber(samples));
    cJSON *ys = cJSON_CreateArray();
    for (int k = 0; k < positions; k++)
        cJSON_AddItemToArray(ys, cJSON_CreateNumber(k * 0.001));
    cJSON_ReplaceItemInObjectCaseSensitive(root, "antenna_y_m", ys);
    char *header = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    return header;
}

static void test_huge_dimensions_are_checked_without_overflow(void)
{
    /* 4096 x 1048576 x 4 = 2^34 bytes: must be reported, not wrapped or allocated. */
    char *header = header_shaped(4096, 1048576);
    expect_reject(header, 2,
                  "4096 positions x 1048576 samples = 4294967296 samples, over the limit of 16777216");
    free(header);
}

static void expect_writer_refuses(const struct uwb_scan *scan, const char *needle);

/* issue 27, break 11: a replay's memory grew with the file (a 268 MB scan
 * took 1.37 GB); the format allowed 16 GiB. A scan past 64 MiB of samples
 * is refused at its header, before its payload is allocated, and the
 * writer never writes one. */
static void test_scans_past_64_mib_of_samples_are_refused(void)
{
    char *header = header_shaped(512, 32769);
    expect_reject(header, 2,
                  "512 positions x 32769 samples = 16777728 samples, over the limit of 16777216 (64 MiB "
                  "of float32)");
    free(header);

    struct uwb_scan scan = {0};
    scan.positions = 4096;
    scan.samples = 4097;
    scan.sample_interval_s = 1e-11;
    expect_writer_refuses(&scan, "4096 positions x 4097 samples = 16781312 samples, over the limit");
}

static void test_error_buffer_may_be_small_or_absent(void)
{
    size_t len;
    unsigned char *buf = build_file("{}", 0, &len);
    struct uwb_scan scan;
    char tiny[8];
    memset(tiny, 'x', sizeof tiny);
    TEST_ASSERT_EQUAL_INT(-1, uwbscan_parse(buf, len, NAME, &scan, tiny, sizeof tiny));
    TEST_ASSERT_EQUAL_STRING("t.uwbsc", tiny); /* truncated, still terminated */
    TEST_ASSERT_EQUAL_INT(-1, uwbscan_parse(buf, len, NAME, &scan, NULL, 0));
    free(buf);
}

/* ---- bounds safety (the parser will be fuzzed) ------------------------ */

static void test_every_truncation_is_rejected_cleanly(void)
{
    size_t len;
    unsigned char *buf = build_file(GOOD_HEADER, GOOD_FLOATS, &len);
    for (size_t cut = 0; cut < len; cut++) {
        unsigned char *copy = malloc(cut ? cut : 1); /* exact size: ASan flags over-reads */
        TEST_ASSERT_NOT_NULL(copy);
        memcpy(copy, buf, cut);
        struct uwb_scan scan;
        err[0] = '\0';
        TEST_ASSERT_EQUAL_INT(-1, uwbscan_parse(copy, cut, NAME, &scan, err, sizeof err));
        TEST_ASSERT_TRUE(err[0] != '\0');
        TEST_ASSERT_TRUE(is_zeroed(&scan));
        free(copy);
    }
    free(buf);
}

static void test_single_byte_corruptions_never_misbehave(void)
{
    static const unsigned char replacements[] = {0x00, '\n', '"',  '}',  ']',  ',',
                                                 '9',  '-',  0xFF, 0xC3, '\\', 'e'};
    size_t len;
    unsigned char *buf = build_file(GOOD_HEADER, GOOD_FLOATS, &len);
    size_t header_len = strlen(GOOD_HEADER);
    for (size_t at = 0; at <= header_len; at++) {
        for (size_t r = 0; r < sizeof replacements; r++) {
            unsigned char *copy = malloc(len);
            TEST_ASSERT_NOT_NULL(copy);
            memcpy(copy, buf, len);
            copy[at] = replacements[r];
            struct uwb_scan scan;
            err[0] = '\0';
            int rc = uwbscan_parse(copy, len, NAME, &scan, err, sizeof err);
            if (rc == 0) {
                TEST_ASSERT_TRUE(scan.positions >= 1 && scan.samples >= 1);
                TEST_ASSERT_EQUAL_UINT64(len - header_len - 1,
                                         4 * (size_t)scan.positions * (size_t)scan.samples);
                uwb_scan_free(&scan);
            } else {
                TEST_ASSERT_EQUAL_INT(-1, rc);
                TEST_ASSERT_TRUE(strncmp(err, NAME ": ", strlen(NAME) + 2) == 0);
                TEST_ASSERT_TRUE(is_zeroed(&scan));
            }
            free(copy);
        }
    }
    free(buf);
}

/* ---- byte order ------------------------------------------------------- */

static void test_samples_are_little_endian_binary32(void)
{
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&scan, 1, 3, err, sizeof err));
    scan.sample_interval_s = 1e-11;
    scan.data[0] = 1.0f;     /* 0x3F800000 */
    scan.data[1] = -2.5f;    /* 0xC0200000 */
    scan.data[2] = 1.4e-45f; /* 0x00000001, smallest subnormal */
    unsigned char *buf;
    size_t len;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&scan, &buf, &len, err, sizeof err), err);
    static const unsigned char expected[12] = {0x00, 0x00, 0x80, 0x3F, 0x00, 0x00,
                                               0x20, 0xC0, 0x01, 0x00, 0x00, 0x00};
    TEST_ASSERT_TRUE(len > 12);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(expected, buf + len - 12, 12);
    TEST_ASSERT_EQUAL_UINT8('\n', buf[len - 13]);

    /* And the reader decodes those bytes back to the same values. */
    struct uwb_scan back;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &back, err, sizeof err), err);
    TEST_ASSERT_EQUAL_HEX32(0x3F800000u, float_bits(back.data[0]));
    TEST_ASSERT_EQUAL_HEX32(0xC0200000u, float_bits(back.data[1]));
    TEST_ASSERT_EQUAL_HEX32(0x00000001u, float_bits(back.data[2]));
    free(buf);
    uwb_scan_free(&back);
    uwb_scan_free(&scan);
}

/* ---- round trips ------------------------------------------------------ */

static void test_round_trip_in_memory_is_exact(void)
{
    struct uwb_scan scan, back;
    make_full_scan(&scan, 5, 7);
    unsigned char *buf;
    size_t len;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&scan, &buf, &len, err, sizeof err), err);

    /* One header line, format first, negative zero kept, then exactly the samples. */
    unsigned char *newline = memchr(buf, '\n', len);
    TEST_ASSERT_NOT_NULL(newline);
    TEST_ASSERT_EQUAL_UINT64(5 * 7 * 4, len - (size_t)(newline - buf) - 1);
    TEST_ASSERT_EQUAL_INT(0, memcmp(buf, "{\"format\":\"uwbscan/1\",", 22));
    TEST_ASSERT_NOT_NULL(strstr((const char *)buf, "\"tx_m\":[-0.02,-0]"));

    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &back, err, sizeof err), err);
    assert_same_scan(&scan, &back);
    /* The unknown keys came back as unknown keys, in order. */
    TEST_ASSERT_EQUAL_STRING(scan.extra_json, back.extra_json);

    /* Serialising what we read gives the very same bytes. */
    unsigned char *again;
    size_t again_len;
    TEST_ASSERT_EQUAL_INT(0, uwbscan_serialise(&back, &again, &again_len, err, sizeof err));
    TEST_ASSERT_EQUAL_UINT64(len, again_len);
    TEST_ASSERT_EQUAL_INT(0, memcmp(buf, again, len));
    free(again);
    free(buf);
    uwb_scan_free(&back);
    uwb_scan_free(&scan);
}

/* cJSON's allocations fail after this many succeed (-1: never). */
static long allocations_left = -1;

static void *failing_malloc(size_t n)
{
    if (allocations_left == 0)
        return NULL;
    if (allocations_left > 0)
        allocations_left--;
    return malloc(n);
}

/* Every allocation the header needs failing in turn (cJSON's hooks): each
 * failure is a clean -1 naming the scan and the cause, nothing returned
 * (ASan: nothing leaked), and once enough succeed the very same bytes. */
static void test_header_out_of_memory_at_each_allocation_fails_cleanly(void)
{
    struct uwb_scan scan;
    make_full_scan(&scan, 5, 7);
    unsigned char *want, *buf;
    size_t want_len, len;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&scan, &want, &want_len, err, sizeof err), err);
    cJSON_Hooks hooks = {.malloc_fn = failing_malloc, .free_fn = free};
    cJSON_InitHooks(&hooks);
    int failures = 0, header_failures = 0;
    for (long n = 0; n < 10000; n++) {
        allocations_left = n;
        buf = (unsigned char *)"untouched";
        int rc = uwbscan_serialise(&scan, &buf, &len, err, sizeof err);
        if (rc == 0)
            break;
        failures++;
        TEST_ASSERT_EQUAL_INT(-1, rc);
        TEST_ASSERT_NULL(buf);
        TEST_ASSERT_EQUAL_UINT64(0, len);
        /* The field checks parse extra_json first, and cJSON_Parse says NULL
         * alike for bad JSON and for no memory: those failures read as
         * extra_json's. The rest are the header's own. */
        if (strstr(err, "scan: cannot build header: "))
            header_failures++;
        else
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "scan: extra_json is not valid JSON"), err);
    }
    cJSON_InitHooks(NULL);
    allocations_left = -1;
    TEST_ASSERT_TRUE_MESSAGE(header_failures > 20 && failures > header_failures,
                             "fewer failures than allocations");
    TEST_ASSERT_EQUAL_UINT64(want_len, len);
    TEST_ASSERT_EQUAL_INT(0, memcmp(want, buf, len));
    free(buf);
    free(want);
    uwb_scan_free(&scan);
}

static void test_round_trip_minimal_scan_keeps_absent_fields_absent(void)
{
    struct uwb_scan scan, back;
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&scan, 1, 1, err, sizeof err));
    scan.sample_interval_s = 2.5e-12;
    unsigned char *buf;
    size_t len;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&scan, &buf, &len, err, sizeof err), err);
    TEST_ASSERT_NULL(strstr((const char *)buf, "target_z_m"));
    TEST_ASSERT_NULL(strstr((const char *)buf, "stack"));
    TEST_ASSERT_NULL(strstr((const char *)buf, "comment"));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &back, err, sizeof err), err);
    assert_same_scan(&scan, &back);
    free(buf);
    uwb_scan_free(&back);
    uwb_scan_free(&scan);
}

static void test_unknown_keys_survive_read_and_rewrite(void)
{
    char header[512];
    snprintf(header, sizeof header, "{\"site\":\"Substation 4\",%s", GOOD_HEADER + 1);
    header[strlen(header) - 1] = '\0';
    strcat(header, ",\"temps_c\":[21.5,22],\"Positions\":7}");
    size_t len;
    unsigned char *buf = build_file(header, GOOD_FLOATS, &len);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_parse(buf, len, NAME, &scan, err, sizeof err), err);
    /* Key names are case-sensitive: "Positions" is someone else's key. */
    TEST_ASSERT_EQUAL_STRING("{\"site\":\"Substation 4\",\"temps_c\":[21.5,22],\"Positions\":7}",
                             scan.extra_json);
    TEST_ASSERT_EQUAL_INT(2, scan.positions);

    char path[128];
    snprintf(path, sizeof path, "%s/rewrite.uwbscan", tmpdir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_write_file(path, &scan, err, sizeof err), err);
    struct uwb_scan back;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(path, &back, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING(scan.extra_json, back.extra_json);
    assert_same_scan(&scan, &back);
    free(buf);
    uwb_scan_free(&back);
    uwb_scan_free(&scan);
}

static void test_round_trip_through_file_leaves_only_the_file(void)
{
    struct uwb_scan scan, back;
    make_full_scan(&scan, 4, 300);
    char path[128];
    snprintf(path, sizeof path, "%s/scan.uwbscan", tmpdir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_write_file(path, &scan, err, sizeof err), err);
    /* Overwrite it once more: the replace path, too, must leave nothing behind. */
    scan.data[0] = 42.0f;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_write_file(path, &scan, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(1, count_entries(tmpdir));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(path, &back, err, sizeof err), err);
    assert_same_scan(&scan, &back);

    /* The file holds exactly what uwbscan_serialise produces. */
    unsigned char *buf;
    size_t len;
    TEST_ASSERT_EQUAL_INT(0, uwbscan_serialise(&scan, &buf, &len, err, sizeof err));
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL(fp);
    unsigned char *disk = malloc(len + 1);
    TEST_ASSERT_EQUAL_UINT64(len, fread(disk, 1, len + 1, fp));
    fclose(fp);
    TEST_ASSERT_EQUAL_INT(0, memcmp(buf, disk, len));
    free(disk);
    free(buf);
    uwb_scan_free(&back);
    uwb_scan_free(&scan);
}

/* ---- the writer refuses what the reader would reject ------------------- */

static void expect_writer_refuses(const struct uwb_scan *scan, const char *needle)
{
    unsigned char *buf = (unsigned char *)"untouched";
    size_t len = 99;
    err[0] = '\0';
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, uwbscan_serialise(scan, &buf, &len, err, sizeof err), needle);
    TEST_ASSERT_NULL(buf);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, needle), err);

    char path[128];
    snprintf(path, sizeof path, "%s/refused.uwbscan", tmpdir);
    TEST_ASSERT_EQUAL_INT(-1, uwbscan_write_file(path, scan, err, sizeof err));
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err, path, strlen(path)) == 0, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, needle), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, count_entries(tmpdir), "a refused scan leaves no file");
}

static void test_writer_refuses_invalid_scans(void)
{
    struct uwb_scan scan;
    make_full_scan(&scan, 2, 5);

    scan.eps_r = 0.5;
    expect_writer_refuses(&scan, "eps_r is 0.5, must be a finite number >= 1");
    scan.eps_r = 1.0;

    scan.data[7] = NAN;
    expect_writer_refuses(&scan, "sample 2 of position 1 is not finite (NaN)");
    scan.data[7] = INFINITY;
    expect_writer_refuses(&scan, "sample 2 of position 1 is not finite (infinite)");
    scan.data[7] = 0.0f;

    scan.sample_interval_s = 0.0;
    expect_writer_refuses(&scan, "sample_interval_s is 0, must be a finite number > 0");
    scan.sample_interval_s = 1e-11;

    scan.antenna_y_m[1] = NAN;
    expect_writer_refuses(&scan, "antenna_y_m[1] is not a finite number");
    scan.antenna_y_m[1] = 0.3; /* above antenna_y_m[0] = 0.1 */

    scan.t0_s = INFINITY;
    expect_writer_refuses(&scan, "t0_s is not a finite number");
    scan.t0_s = 0.0;

    scan.rx_m[1] = NAN;
    expect_writer_refuses(&scan, "rx_m[1] is not a finite number");
    scan.rx_m[1] = 0.0;

    scan.target_z_m[1] = scan.target_z_m[0];
    expect_writer_refuses(&scan, "near must be less than far");
    scan.target_z_m[1] = 0.9;

    scan.stack = -1;
    expect_writer_refuses(&scan, "stack is -1, must be a positive integer");
    scan.stack = 0;

    scan.positions = 0;
    expect_writer_refuses(&scan, "positions is 0, must be at least 1");
    scan.positions = 5000;
    expect_writer_refuses(&scan, "positions is 5000, over the limit of 4096");
    scan.positions = 2;

    char *saved = scan.comment;
    scan.comment = "bad \xff byte";
    expect_writer_refuses(&scan, "comment is not valid UTF-8 (byte 4)");

    /* A header past the limit would be unreadable. */
    char *huge = malloc(UWBSCAN_MAX_HEADER_BYTES + 1);
    TEST_ASSERT_NOT_NULL(huge);
    memset(huge, 'a', UWBSCAN_MAX_HEADER_BYTES);
    huge[UWBSCAN_MAX_HEADER_BYTES] = '\0';
    scan.comment = huge;
    expect_writer_refuses(&scan, "over the limit of 1048576");
    free(huge);
    scan.comment = saved;

    saved = scan.extra_json;
    scan.extra_json = "{\"eps_r\":2}";
    expect_writer_refuses(&scan, "extra_json key 'eps_r' clashes with a standard header key");
    scan.extra_json = "[1,2]";
    expect_writer_refuses(&scan, "extra_json must be a JSON object");
    scan.extra_json = "{\"a\":";
    expect_writer_refuses(&scan, "extra_json is not valid JSON");
    scan.extra_json = "{\"a\":1,\"a\":2}";
    expect_writer_refuses(&scan, "extra_json key 'a' appears twice");
    scan.extra_json = saved;

    /* Back to valid: now it is accepted, so the refusals were about those fields. */
    unsigned char *buf;
    size_t len;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&scan, &buf, &len, err, sizeof err), err);
    free(buf);
    uwb_scan_free(&scan);
}

/* ---- files ------------------------------------------------------------ */

static void test_read_file_reports_path_and_reason(void)
{
    char path[128];
    snprintf(path, sizeof path, "%s/absent.uwbscan", tmpdir);
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(-1, uwbscan_read_file(path, &scan, err, sizeof err));
    char expected[256];
    snprintf(expected, sizeof expected, "%s: cannot open: No such file or directory", path);
    TEST_ASSERT_EQUAL_STRING(expected, err);
    TEST_ASSERT_TRUE(is_zeroed(&scan));

    TEST_ASSERT_EQUAL_INT(-1, uwbscan_read_file(tmpdir, &scan, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "Is a directory"), err);
    TEST_ASSERT_TRUE(strncmp(err, tmpdir, strlen(tmpdir)) == 0);

    /* A content error in a file is named by that file's path. */
    FILE *fp = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(fp);
    fputs("{\"format\":\"uwbscan/1\"}\n", fp);
    fclose(fp);
    TEST_ASSERT_EQUAL_INT(-1, uwbscan_read_file(path, &scan, err, sizeof err));
    snprintf(expected, sizeof expected, "%s: header key 'positions' is missing", path);
    TEST_ASSERT_EQUAL_STRING(expected, err);
}

static void check_fixture(const char *path)
{
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(path, &scan, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(21, scan.positions);
    TEST_ASSERT_EQUAL_INT(1697, scan.samples);
    TEST_ASSERT_TRUE(scan.sample_interval_s == 4.717308673499368e-12);
    TEST_ASSERT_TRUE(scan.t0_s == -7.071067811865476e-10);
    TEST_ASSERT_TRUE(scan.antenna_y_m[0] == 0.0);
    TEST_ASSERT_TRUE(scan.antenna_y_m[1] == 0.03);
    TEST_ASSERT_TRUE(scan.antenna_y_m[20] == 0.6);
    TEST_ASSERT_TRUE(scan.tx_m[0] == -0.02 && scan.tx_m[1] == 0.0);
    TEST_ASSERT_TRUE(scan.rx_m[0] == 0.02 && scan.rx_m[1] == 0.0);
    TEST_ASSERT_TRUE(scan.eps_r == 1.0);
    TEST_ASSERT_EQUAL_INT(0, scan.has_target_z);
    TEST_ASSERT_EQUAL_STRING("gprMax 4.0.1 2-D FDTD", scan.source);
    TEST_ASSERT_EQUAL_STRING("synthetic", scan.comment);
    TEST_ASSERT_NULL(scan.extra_json);

    /* Samples decoded independently from the file's bytes must match. */
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL(fp);
    static unsigned char file[200000];
    size_t len = fread(file, 1, sizeof file, fp);
    fclose(fp);
    unsigned char *payload = (unsigned char *)memchr(file, '\n', len) + 1;
    TEST_ASSERT_EQUAL_UINT64(21 * 1697 * 4, len - (size_t)(payload - file));
    float peak = 0.0f;
    for (size_t i = 0; i < 21 * 1697; i++) {
        const unsigned char *p = payload + 4 * i;
        uint32_t bits = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
        TEST_ASSERT_EQUAL_HEX32(bits, float_bits(scan.data[i]));
        if (fabsf(scan.data[i]) > peak)
            peak = fabsf(scan.data[i]);
    }
    TEST_ASSERT_TRUE_MESSAGE(peak > 0.0f, "fixture holds a signal");

    /* Rewriting the fixture reproduces its payload byte for byte. */
    unsigned char *buf;
    size_t blen;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&scan, &buf, &blen, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, memcmp(buf + blen - 21 * 1697 * 4, payload, 21 * 1697 * 4));
    free(buf);
    uwb_scan_free(&scan);
}

static void test_reads_fdtd_fixture_intact(void)
{
    check_fixture("tests/fixtures/fdtd2d-paper-intact.uwbscan");
}

static void test_reads_fdtd_fixture_up20mm(void)
{
    check_fixture("tests/fixtures/fdtd2d-paper-up20mm.uwbscan");
}

/* ---- memory ----------------------------------------------------------- */

static void test_alloc_zeroes_and_checks_limits(void)
{
    struct uwb_scan scan;
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&scan, 3, 4, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(3, scan.positions);
    TEST_ASSERT_EQUAL_INT(4, scan.samples);
    TEST_ASSERT_TRUE(scan.eps_r == 1.0);
    TEST_ASSERT_NULL(scan.comment);
    TEST_ASSERT_NULL(scan.extra_json);
    for (int i = 0; i < 12; i++)
        TEST_ASSERT_EQUAL_HEX32(0, float_bits(scan.data[i]));
    for (int k = 0; k < 3; k++)
        TEST_ASSERT_TRUE(scan.antenna_y_m[k] == 0.0);
    uwb_scan_free(&scan);
    TEST_ASSERT_TRUE(is_zeroed(&scan));
    uwb_scan_free(&scan); /* freeing twice is harmless */

    TEST_ASSERT_EQUAL_INT(-1, uwb_scan_alloc(&scan, 0, 4, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan: positions is 0, must be between 1 and 4096", err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_scan_alloc(&scan, 2, UWBSCAN_MAX_SAMPLES + 1, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan: samples is 1048577, must be between 1 and 1048576", err);
    TEST_ASSERT_NULL(scan.data);
}

static void test_copy_is_deep(void)
{
    struct uwb_scan scan, copy;
    make_full_scan(&scan, 3, 4);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_scan_copy(&copy, &scan, err, sizeof err), err);
    assert_same_scan(&scan, &copy);
    TEST_ASSERT_TRUE(copy.data != scan.data);
    TEST_ASSERT_TRUE(copy.antenna_y_m != scan.antenna_y_m);
    TEST_ASSERT_TRUE(copy.comment != scan.comment);
    TEST_ASSERT_TRUE(copy.extra_json != scan.extra_json);
    copy.data[0] = 99.0f;
    copy.antenna_y_m[0] = 9.0;
    copy.comment[0] = 'X';
    TEST_ASSERT_TRUE(scan.data[0] == 0.0f);
    TEST_ASSERT_TRUE(scan.antenna_y_m[0] == 0.1);
    TEST_ASSERT_EQUAL_INT('l', scan.comment[0]);
    uwb_scan_free(&copy);
    uwb_scan_free(&scan);
}

/* A copy of a scan without its optional strings has none either; a scan
 * that could not be held is refused, by its limits, before any copying;
 * freeing nothing is harmless. */
static void test_copy_keeps_absent_strings_absent_and_refuses_bad_sizes(void)
{
    struct uwb_scan scan, copy;
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(&scan, 2, 3, err, sizeof err));
    scan.data[5] = 7.5f;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_scan_copy(&copy, &scan, err, sizeof err), err);
    TEST_ASSERT_NULL(copy.created);
    TEST_ASSERT_NULL(copy.scan_id);
    TEST_ASSERT_NULL(copy.source);
    TEST_ASSERT_NULL(copy.comment);
    TEST_ASSERT_NULL(copy.extra_json);
    TEST_ASSERT_TRUE(copy.data[5] == 7.5f);
    uwb_scan_free(&copy);
    uwb_scan_free(&scan); /* now all zero: positions 0 */
    TEST_ASSERT_EQUAL_INT(-1, uwb_scan_copy(&copy, &scan, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan: positions is 0, must be between 1 and 4096", err);
    TEST_ASSERT_NULL(copy.data);
    TEST_ASSERT_NULL(copy.antenna_y_m);
    uwb_scan_free(NULL);
}

/* The writer names the path when the temporary file cannot be made or
 * written (the disk full, here the file-size limit); the file already
 * there stays as it was and no temporary is left beside it. */
static void test_write_file_failures_name_the_path_and_keep_the_old_file(void)
{
    struct uwb_scan scan;
    make_full_scan(&scan, 4, 3000);
    char path[128];
    snprintf(path, sizeof path, "%s/missing-dir/scan.uwbscan", tmpdir);
    TEST_ASSERT_EQUAL_INT(-1, uwbscan_write_file(path, &scan, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "missing-dir/scan.uwbscan"), err);

    snprintf(path, sizeof path, "%s/scan.uwbscan", tmpdir);
    scratch_spit(path, "the scan before");
    struct rlimit saved, tight;
    TEST_ASSERT_EQUAL_INT(0, getrlimit(RLIMIT_FSIZE, &saved));
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    tight = saved;
    tight.rlim_cur = 20000; /* the scan is 48000 bytes of samples */
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &tight));
    int rc = uwbscan_write_file(path, &scan, err, sizeof err);
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &saved));
    signal(SIGXFSZ, old_handler);
    TEST_ASSERT_EQUAL_INT(-1, rc);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err, path, strlen(path)) == 0, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "cannot write temporary file: File too large"), err);
    char *text = scratch_slurp(path, NULL);
    TEST_ASSERT_EQUAL_STRING("the scan before", text);
    free(text);
    TEST_ASSERT_EQUAL_INT(1, count_entries(tmpdir));
    uwb_scan_free(&scan);
}
int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_good_header_parses);
    /* rejections named by the format document */
    RUN_TEST(test_rejects_empty_input);
    RUN_TEST(test_rejects_header_without_newline);
    RUN_TEST(test_rejects_malformed_json_header);
    RUN_TEST(test_rejects_header_that_is_not_an_object);
    RUN_TEST(test_rejects_text_after_header_object);
    RUN_TEST(test_rejects_each_missing_required_key);
    RUN_TEST(test_rejects_wrongly_typed_keys);
    RUN_TEST(test_rejects_payload_too_short);
    RUN_TEST(test_rejects_trailing_bytes);
    RUN_TEST(test_rejects_nan_sample);
    RUN_TEST(test_rejects_infinite_sample);
    RUN_TEST(test_rejects_zero_positions_and_samples);
    RUN_TEST(test_rejects_too_many_positions);
    RUN_TEST(test_rejects_too_many_samples);
    RUN_TEST(test_rejects_nonpositive_sample_interval);
    RUN_TEST(test_rejects_antenna_count_mismatch);
    /* further rejections */
    RUN_TEST(test_rejects_header_over_one_mebibyte);
    RUN_TEST(test_header_limit_is_exactly_one_mebibyte);
    RUN_TEST(test_rejects_control_bytes_in_header);
    RUN_TEST(test_rejects_escaped_nul);
    RUN_TEST(test_rejects_invalid_utf8);
    RUN_TEST(test_rejects_byte_order_mark);
    RUN_TEST(test_rejects_duplicate_key);
    RUN_TEST(test_rejects_wrong_format_value);
    RUN_TEST(test_rejects_fractional_positions_and_samples);
    RUN_TEST(test_accepts_integral_number_written_with_exponent);
    RUN_TEST(test_rejects_nonfinite_numbers);
    RUN_TEST(test_rejects_tx_rx_not_pairs);
    RUN_TEST(test_rejects_bad_target_z);
    RUN_TEST(test_rejects_bad_eps_r);
    RUN_TEST(test_rejects_stack_not_positive_integer);
    RUN_TEST(test_rejects_optional_strings_of_wrong_type);
    RUN_TEST(test_rejects_what_the_rig_cannot_record);
    RUN_TEST(test_huge_dimensions_are_checked_without_overflow);
    RUN_TEST(test_scans_past_64_mib_of_samples_are_refused);
    RUN_TEST(test_error_buffer_may_be_small_or_absent);
    /* bounds safety */
    RUN_TEST(test_every_truncation_is_rejected_cleanly);
    RUN_TEST(test_single_byte_corruptions_never_misbehave);
    /* encoding and round trips */
    RUN_TEST(test_samples_are_little_endian_binary32);
    RUN_TEST(test_round_trip_in_memory_is_exact);
    RUN_TEST(test_round_trip_minimal_scan_keeps_absent_fields_absent);
    RUN_TEST(test_unknown_keys_survive_read_and_rewrite);
    RUN_TEST(test_round_trip_through_file_leaves_only_the_file);
    RUN_TEST(test_writer_refuses_invalid_scans);
    /* files and memory */
    RUN_TEST(test_read_file_reports_path_and_reason);
    RUN_TEST(test_reads_fdtd_fixture_intact);
    RUN_TEST(test_reads_fdtd_fixture_up20mm);
    RUN_TEST(test_alloc_zeroes_and_checks_limits);
    RUN_TEST(test_copy_is_deep);
    RUN_TEST(test_copy_keeps_absent_strings_absent_and_refuses_bad_sizes);
    RUN_TEST(test_write_file_failures_name_the_path_and_keep_the_old_file);
    RUN_TEST(test_header_out_of_memory_at_each_allocation_fails_cleanly);
    return UNITY_END();
}
