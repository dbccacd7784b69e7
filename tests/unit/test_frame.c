/* Digitiser frames: encoding, checked decoding, resynchronisation. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "unity.h"
#include "uwb/digitiser.h"
#include "uwb/frame.h"

#define ASSERT_SIZE(want, got) TEST_ASSERT_EQUAL_UINT64((uint64_t)(want), (uint64_t)(got))

void setUp(void)
{
}
void tearDown(void)
{
}

/* A DATA frame of `samples` codes (code i = i * 7 - 300 + seq) into out. */
static size_t make_data_frame(uint32_t sequence, uint32_t samples, uint8_t *out, size_t outlen)
{
    int16_t *codes = malloc(samples * sizeof *codes);
    uint8_t *payload = malloc(uwb_trace_payload_size(samples));
    TEST_ASSERT_NOT_NULL(codes);
    TEST_ASSERT_NOT_NULL(payload);
    for (uint32_t i = 0; i < samples; i++)
        codes[i] = (int16_t)((int)i * 7 - 300 + (int)sequence);
    size_t plen =
        uwb_trace_payload_encode(codes, samples, 0.5f / 2048, payload, uwb_trace_payload_size(samples));
    ASSERT_SIZE(uwb_trace_payload_size(samples), plen);
    size_t n = uwb_frame_encode(UWB_FRAME_DATA, sequence, payload, plen, out, outlen);
    free(codes);
    free(payload);
    return n;
}

static void assert_data_frame(const struct uwb_frame *f, uint32_t sequence, uint32_t samples)
{
    TEST_ASSERT_EQUAL_UINT8(UWB_FRAME_DATA, f->type);
    TEST_ASSERT_EQUAL_UINT32(sequence, f->sequence);
    struct uwb_trace_view view;
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_trace_payload_parse(f, &view, err, sizeof err), err);
    TEST_ASSERT_EQUAL_UINT32(samples, view.samples);
    TEST_ASSERT_EQUAL_FLOAT(0.5f / 2048, view.volts_per_count);
    for (uint32_t i = 0; i < samples; i++)
        TEST_ASSERT_EQUAL_INT16((int16_t)((int)i * 7 - 300 + (int)sequence), uwb_trace_code(&view, i));
}

static void test_round_trip_keeps_every_field_and_sample(void)
{
    uint8_t buf[8192];
    size_t n = make_data_frame(41, 1000, buf, sizeof buf);
    ASSERT_SIZE(uwb_frame_size(uwb_trace_payload_size(1000)), n);
    TEST_ASSERT_EQUAL_MEMORY(uwb_frame_sync, buf, UWB_FRAME_SYNC_BYTES);
    struct uwb_frame f;
    size_t consumed;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_FOUND, uwb_frame_decode(buf, n, &f, &consumed));
    ASSERT_SIZE(n, consumed);
    TEST_ASSERT_EQUAL_UINT8(UWB_FRAME_VERSION, f.version);
    assert_data_frame(&f, 41, 1000);
}

static void test_negative_codes_and_extremes_survive(void)
{
    int16_t codes[4] = {-32768, -1, 0, 32767};
    uint8_t payload[64], buf[128];
    size_t plen = uwb_trace_payload_encode(codes, 4, 1e-3f, payload, sizeof payload);
    size_t n = uwb_frame_encode(UWB_FRAME_DATA, 7, payload, plen, buf, sizeof buf);
    struct uwb_frame f;
    size_t consumed;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_FOUND, uwb_frame_decode(buf, n, &f, &consumed));
    struct uwb_trace_view v;
    char err[128];
    TEST_ASSERT_EQUAL_INT(0, uwb_trace_payload_parse(&f, &v, err, sizeof err));
    for (int i = 0; i < 4; i++)
        TEST_ASSERT_EQUAL_INT16(codes[i], uwb_trace_code(&v, (uint32_t)i));
}

static void test_encode_refuses_a_too_small_buffer_or_payload(void)
{
    uint8_t buf[64];
    ASSERT_SIZE(0, uwb_frame_encode(UWB_FRAME_PING, 1, "abcdefghijklmnopqrstuvwxyzabcdefghijklmnopq", 43, buf,
                                    sizeof buf));
    ASSERT_SIZE(0, uwb_frame_encode(UWB_FRAME_DATA, 1, buf, UWB_FRAME_MAX_PAYLOAD + 1, buf, SIZE_MAX));
}

/* Every single corrupted byte is caught: never a FOUND frame. */
static void test_any_flipped_byte_is_rejected(void)
{
    uint8_t good[512], bad[512];
    size_t n = make_data_frame(3, 100, good, sizeof good);
    for (size_t i = 0; i < n; i++) {
        memcpy(bad, good, n);
        bad[i] ^= 0x10;
        struct uwb_frame f;
        size_t consumed;
        int status = uwb_frame_decode(bad, n, &f, &consumed);
        TEST_ASSERT_NOT_EQUAL_MESSAGE(UWB_FRAME_FOUND, status, "a corrupted frame was accepted");
        if (i < UWB_FRAME_SYNC_BYTES) { /* no sync marker here any more; maybe a false one later */
            TEST_ASSERT_TRUE(status == UWB_FRAME_NEED_MORE || status == UWB_FRAME_BAD_HEADER);
        } else if (i < UWB_FRAME_HEADER_BYTES) {
            TEST_ASSERT_EQUAL_INT(UWB_FRAME_BAD_HEADER, status);
        } else {
            TEST_ASSERT_EQUAL_INT(UWB_FRAME_BAD_CRC, status);
        }
    }
}

static void test_every_truncation_waits_for_more(void)
{
    uint8_t buf[512];
    size_t n = make_data_frame(9, 64, buf, sizeof buf);
    for (size_t len = 0; len < n; len++) {
        struct uwb_frame f;
        size_t consumed = 12345;
        TEST_ASSERT_EQUAL_INT(UWB_FRAME_NEED_MORE, uwb_frame_decode(buf, len, &f, &consumed));
        ASSERT_SIZE(0, consumed); /* nothing of a possible frame is thrown away */
    }
}

static void test_decoder_resyncs_after_garbage_and_false_syncs(void)
{
    struct uwb_frame_decoder dec;
    TEST_ASSERT_EQUAL_INT(0, uwb_frame_decoder_init(&dec));
    uint8_t stream[4096];
    size_t len = 0;
    const char *noise = "line noise \xA5\x55 and a false sync: ";
    memcpy(stream + len, noise, strlen(noise));
    len += strlen(noise);
    /* a full false header: sync marker then junk that fails the header CRC */
    memcpy(stream + len, uwb_frame_sync, 4);
    memset(stream + len + 4, 0x33, 20);
    len += 24;
    len += make_data_frame(0, 50, stream + len, sizeof stream - len);
    memcpy(stream + len, "\xA5\xA5\xA5", 3);
    len += 3;
    len += make_data_frame(1, 50, stream + len, sizeof stream - len);

    /* byte by byte, the hardest way for a decoder */
    int found = 0;
    for (size_t i = 0; i < len; i++) {
        ASSERT_SIZE(1, uwb_frame_decoder_feed(&dec, stream + i, 1));
        struct uwb_frame f;
        int status;
        while ((status = uwb_frame_decoder_next(&dec, &f)) != UWB_FRAME_NEED_MORE)
            if (status == UWB_FRAME_FOUND)
                assert_data_frame(&f, (uint32_t)found++, 50);
    }
    TEST_ASSERT_EQUAL_INT(2, found);
    TEST_ASSERT_EQUAL_UINT32(2, dec.frames);
    TEST_ASSERT_EQUAL_UINT32(1, dec.bad_headers);
    TEST_ASSERT_TRUE(dec.skipped_bytes >= strlen(noise) + 24 + 3);
    uwb_frame_decoder_free(&dec);
}

/* A frame cut short and then overrun by the next one: the first fails its
 * CRC, the second is found whole inside the bytes already buffered. */
static void test_truncated_frame_then_good_frame(void)
{
    struct uwb_frame_decoder dec;
    TEST_ASSERT_EQUAL_INT(0, uwb_frame_decoder_init(&dec));
    uint8_t a[1024], b[1024];
    size_t na = make_data_frame(5, 200, a, sizeof a);
    size_t nb = make_data_frame(6, 200, b, sizeof b);
    uwb_frame_decoder_feed(&dec, a, na / 2);
    struct uwb_frame f;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_NEED_MORE, uwb_frame_decoder_next(&dec, &f));
    uwb_frame_decoder_feed(&dec, b, nb);
    int status, found = 0, bad = 0;
    while ((status = uwb_frame_decoder_next(&dec, &f)) != UWB_FRAME_NEED_MORE) {
        if (status == UWB_FRAME_FOUND) {
            assert_data_frame(&f, 6, 200);
            found++;
        } else {
            bad++;
        }
    }
    TEST_ASSERT_EQUAL_INT(1, found);
    TEST_ASSERT_EQUAL_INT(1, bad);
    TEST_ASSERT_EQUAL_UINT32(1, dec.bad_crcs);
    uwb_frame_decoder_free(&dec);
}

static void test_reset_forgets_a_partial_frame(void)
{
    struct uwb_frame_decoder dec;
    TEST_ASSERT_EQUAL_INT(0, uwb_frame_decoder_init(&dec));
    uint8_t a[512], b[512];
    size_t na = make_data_frame(1, 20, a, sizeof a);
    size_t nb = make_data_frame(2, 20, b, sizeof b);
    uwb_frame_decoder_feed(&dec, a, na - 1);
    uwb_frame_decoder_reset(&dec);
    uwb_frame_decoder_feed(&dec, b, nb);
    struct uwb_frame f;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_FOUND, uwb_frame_decoder_next(&dec, &f));
    assert_data_frame(&f, 2, 20);
    TEST_ASSERT_EQUAL_UINT64(na - 1, dec.skipped_bytes);
    uwb_frame_decoder_free(&dec);
}

/* Rewrite a header's payload length (LE at 12) and fix up its CRC (LE at
 * 16, over the 16 bytes before it), so the header itself stays valid. */
static void rewrite_header_length(uint8_t *header, uint32_t length)
{
    for (int i = 0; i < 4; i++)
        header[12 + i] = (uint8_t)(length >> (8 * i));
    uint32_t crc = (uint32_t)crc32(crc32(0L, Z_NULL, 0), header, 16);
    for (int i = 0; i < 4; i++)
        header[16 + i] = (uint8_t)(crc >> (8 * i));
}

static void test_header_claiming_a_huge_length_is_rejected_at_once(void)
{
    uint8_t buf[64];
    size_t n = uwb_frame_encode(UWB_FRAME_PONG, 1, "x", 1, buf, sizeof buf);
    TEST_ASSERT_TRUE(n > 0);
    /* a valid header with a length past the limit: only the limit can stop it */
    rewrite_header_length(buf, UWB_FRAME_MAX_PAYLOAD + 1);
    struct uwb_frame f;
    size_t consumed;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_BAD_HEADER, uwb_frame_decode(buf, n, &f, &consumed));
    ASSERT_SIZE(1, consumed);
    /* the same header with a length inside the limit is waited for */
    rewrite_header_length(buf, UWB_FRAME_MAX_PAYLOAD);
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_NEED_MORE, uwb_frame_decode(buf, n, &f, &consumed));
}

static void test_payload_length_must_match_sample_count(void)
{
    int16_t codes[10] = {0};
    uint8_t payload[64], buf[128];
    size_t plen = uwb_trace_payload_encode(codes, 10, 1e-3f, payload, sizeof payload);
    /* claim 11 samples in a payload that holds 10 */
    payload[0] = 11;
    size_t n = uwb_frame_encode(UWB_FRAME_DATA, 4, payload, plen, buf, sizeof buf);
    struct uwb_frame f;
    size_t consumed;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_FOUND, uwb_frame_decode(buf, n, &f, &consumed));
    struct uwb_trace_view v;
    char err[256];
    TEST_ASSERT_EQUAL_INT(-1, uwb_trace_payload_parse(&f, &v, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "11 samples"));
}

static void test_sequence_gaps_and_stale_frames(void)
{
    TEST_ASSERT_EQUAL_INT(UWB_SEQUENCE_EXPECTED, uwb_digitiser_check_sequence(5, 5));
    TEST_ASSERT_EQUAL_INT(UWB_SEQUENCE_STALE, uwb_digitiser_check_sequence(5, 4));
    TEST_ASSERT_EQUAL_INT(UWB_SEQUENCE_AHEAD, uwb_digitiser_check_sequence(5, 7));
    /* across the 32-bit wrap */
    TEST_ASSERT_EQUAL_INT(UWB_SEQUENCE_AHEAD, uwb_digitiser_check_sequence(0xFFFFFFFFu, 1));
    TEST_ASSERT_EQUAL_INT(UWB_SEQUENCE_STALE, uwb_digitiser_check_sequence(1, 0xFFFFFFFFu));
}

static void test_configure_and_error_payloads(void)
{
    uint8_t p[UWB_FRAME_CONFIGURE_BYTES], buf[128];
    uwb_configure_payload_encode(2048, 1e-11, p);
    size_t n = uwb_frame_encode(UWB_FRAME_CONFIGURE, 3, p, sizeof p, buf, sizeof buf);
    struct uwb_frame f;
    size_t consumed;
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_FOUND, uwb_frame_decode(buf, n, &f, &consumed));
    uint32_t samples;
    double interval;
    TEST_ASSERT_EQUAL_INT(0, uwb_configure_payload_parse(&f, &samples, &interval));
    TEST_ASSERT_EQUAL_UINT32(2048, samples);
    TEST_ASSERT_EQUAL_DOUBLE(1e-11, interval);

    uint8_t e[64];
    size_t elen = uwb_error_payload_encode(3, "samples: too many", e, sizeof e);
    n = uwb_frame_encode(UWB_FRAME_ERROR, 3, e, elen, buf, sizeof buf);
    TEST_ASSERT_EQUAL_INT(UWB_FRAME_FOUND, uwb_frame_decode(buf, n, &f, &consumed));
    char text[128];
    uwb_error_payload_describe(&f, text, sizeof text);
    TEST_ASSERT_EQUAL_STRING("code 3: samples: too many", text);
}

/* Random bytes never crash the decoder and never yield a frame. */
static void test_random_bytes_decode_to_nothing(void)
{
    struct uwb_frame_decoder dec;
    TEST_ASSERT_EQUAL_INT(0, uwb_frame_decoder_init(&dec));
    uint32_t x = 12345;
    uint8_t chunk[4096];
    for (int round = 0; round < 64; round++) {
        for (size_t i = 0; i < sizeof chunk; i++) {
            x = x * 1103515245u + 12345u;
            chunk[i] = (uint8_t)(x >> 16);
            if (i % 97 == 0)
                chunk[i] = 0xA5; /* plenty of sync starts */
        }
        uwb_frame_decoder_feed(&dec, chunk, sizeof chunk);
        struct uwb_frame f;
        int status;
        while ((status = uwb_frame_decoder_next(&dec, &f)) != UWB_FRAME_NEED_MORE)
            TEST_ASSERT_NOT_EQUAL(UWB_FRAME_FOUND, status);
    }
    TEST_ASSERT_EQUAL_UINT32(0, dec.frames);
    uwb_frame_decoder_free(&dec);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_round_trip_keeps_every_field_and_sample);
    RUN_TEST(test_negative_codes_and_extremes_survive);
    RUN_TEST(test_encode_refuses_a_too_small_buffer_or_payload);
    RUN_TEST(test_any_flipped_byte_is_rejected);
    RUN_TEST(test_every_truncation_waits_for_more);
    RUN_TEST(test_decoder_resyncs_after_garbage_and_false_syncs);
    RUN_TEST(test_truncated_frame_then_good_frame);
    RUN_TEST(test_reset_forgets_a_partial_frame);
    RUN_TEST(test_header_claiming_a_huge_length_is_rejected_at_once);
    RUN_TEST(test_payload_length_must_match_sample_count);
    RUN_TEST(test_sequence_gaps_and_stale_frames);
    RUN_TEST(test_configure_and_error_payloads);
    RUN_TEST(test_random_bytes_decode_to_nothing);
    return UNITY_END();
}
