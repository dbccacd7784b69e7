/* Fuzzing the digitiser frame decoder (include/uwb/frame.h): the input is
 * the byte stream of a digitiser link. It goes through the incremental
 * decoder in uneven pieces (as reads deliver it), and every frame found
 * goes through the payload parser its type calls for. A corrupt stream
 * mostly fails the CRCs, so the input is also wrapped into frames with
 * good CRCs (one frame per 0xFF-separated piece, first byte = type), which
 * lets the payload parsers see arbitrary payloads.
 *
 * Contract: the decoder never reports more bytes consumed than it holds,
 * a found frame lies inside the bytes fed and passes its own checks
 * again, the decoder's counts add up, and payload parsers either accept
 * values inside their limits or refuse with a message. */
#include <math.h>
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/frame.h"

/* Read sizes a link might deliver, cycled through. */
static const size_t piece_sizes[] = {1, 7, 19, 4096, 3, 64, 1024};

static int check_payload(const struct uwb_frame *f, char *why, size_t whylen)
{
    char err[512];
    if (f->type == UWB_FRAME_DATA) {
        struct uwb_trace_view view;
        err[0] = '\0';
        if (uwb_trace_payload_parse(f, &view, err, sizeof err) != 0) {
            if (!err[0])
                return fuzz_broken(why, whylen, "DATA payload refused without a message");
            return FUZZ_REJECTED;
        }
        if (view.samples > UWB_FRAME_MAX_SAMPLES || uwb_trace_payload_size(view.samples) != f->length ||
            !(view.volts_per_count > 0) || !isfinite(view.volts_per_count))
            return fuzz_broken(why, whylen, "DATA payload accepted with %u samples, %g V per count, %u bytes",
                               (unsigned)view.samples, (double)view.volts_per_count, (unsigned)f->length);
        /* Every code must be readable inside the payload. */
        long sum = 0;
        for (uint32_t i = 0; i < view.samples; i++)
            sum += uwb_trace_code(&view, i);
        (void)sum;
        return FUZZ_ACCEPTED;
    }
    if (f->type == UWB_FRAME_CONFIGURE || f->type == UWB_FRAME_CONFIGURED) {
        uint32_t samples;
        double interval;
        int rc = uwb_configure_payload_parse(f, &samples, &interval);
        if ((rc == 0) != (f->length == UWB_FRAME_CONFIGURE_BYTES))
            return fuzz_broken(why, whylen, "CONFIGURE payload of %u bytes: parse returned %d",
                               (unsigned)f->length, rc);
        return rc == 0 ? FUZZ_ACCEPTED : FUZZ_REJECTED;
    }
    if (f->type == UWB_FRAME_ERROR) {
        char text[300];
        memset(text, 'x', sizeof text);
        uwb_error_payload_describe(f, text, sizeof text);
        if (!memchr(text, '\0', sizeof text) || !text[0])
            return fuzz_broken(why, whylen, "ERROR payload description unterminated or empty");
        return FUZZ_ACCEPTED;
    }
    return FUZZ_ACCEPTED;
}

/* Feeds `stream` to a decoder in uneven pieces; counts frames found. */
static int decode_stream(const uint8_t *stream, size_t size, unsigned long *found, char *why, size_t whylen)
{
    struct uwb_frame_decoder dec;
    if (uwb_frame_decoder_init(&dec) != 0)
        return fuzz_broken(why, whylen, "decoder init failed");
    int rc = FUZZ_ACCEPTED;
    size_t fed = 0, piece = 0;
    unsigned long statuses = 0;
    while (rc != FUZZ_BROKEN && fed < size) {
        size_t n = piece_sizes[piece++ % (sizeof piece_sizes / sizeof piece_sizes[0])];
        if (n > size - fed)
            n = size - fed;
        size_t taken = uwb_frame_decoder_feed(&dec, stream + fed, n);
        if (taken > n) {
            rc = fuzz_broken(why, whylen, "decoder took %zu of %zu bytes", taken, n);
            break;
        }
        fed += taken;
        for (;;) {
            struct uwb_frame f;
            int status = uwb_frame_decoder_next(&dec, &f);
            if (dec.start > dec.len || dec.len > dec.cap) {
                rc = fuzz_broken(why, whylen, "decoder state start %zu len %zu cap %zu", dec.start, dec.len,
                                 dec.cap);
                break;
            }
            if (status == UWB_FRAME_NEED_MORE)
                break;
            statuses++;
            if (status == UWB_FRAME_BAD_HEADER || status == UWB_FRAME_BAD_CRC)
                continue;
            if (status != UWB_FRAME_FOUND) {
                rc = fuzz_broken(why, whylen, "decoder returned %d", status);
                break;
            }
            if (f.version != UWB_FRAME_VERSION || f.length > UWB_FRAME_MAX_PAYLOAD || f.payload < dec.buf ||
                f.payload + f.length > dec.buf + dec.cap) {
                rc = fuzz_broken(why, whylen, "frame found outside the decoder's buffer or limits");
                break;
            }
            /* The frame, re-encoded, decodes to the same frame. */
            static uint8_t again[UWB_FRAME_MAX_BYTES];
            size_t len = uwb_frame_encode(f.type, f.sequence, f.payload, f.length, again, sizeof again);
            struct uwb_frame g;
            size_t consumed;
            if (!len || uwb_frame_decode(again, len, &g, &consumed) != UWB_FRAME_FOUND || consumed != len ||
                g.type != f.type || g.sequence != f.sequence || g.length != f.length ||
                memcmp(g.payload, f.payload, f.length) != 0) {
                rc = fuzz_broken(why, whylen, "a found frame does not survive re-encoding");
                break;
            }
            (*found)++;
            if (check_payload(&f, why, whylen) == FUZZ_BROKEN) {
                rc = FUZZ_BROKEN;
                break;
            }
        }
        if (taken == 0 && rc != FUZZ_BROKEN) {
            rc = fuzz_broken(why, whylen, "decoder took no bytes with %zu undecoded", dec.len - dec.start);
            break;
        }
    }
    if (rc != FUZZ_BROKEN && dec.frames + dec.bad_headers + dec.bad_crcs != statuses)
        rc = fuzz_broken(why, whylen,
                         "decoder counts %lu frames, %lu bad headers, %lu bad CRCs for %lu results",
                         dec.frames, dec.bad_headers, dec.bad_crcs, statuses);
    uwb_frame_decoder_free(&dec);
    return rc;
}

/* Wraps 0xFF-separated pieces of the input into good frames. */
static int decode_wrapped(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    static uint8_t stream[4 * 65536];
    size_t at = 0, start = 0;
    uint32_t sequence = 0;
    for (size_t i = 0; i <= size; i++) {
        if (i < size && data[i] != 0xFF)
            continue;
        if (i > start) {
            size_t payload_len = i - start - 1;
            size_t n = uwb_frame_encode(data[start], sequence, data + start + 1, payload_len, stream + at,
                                        sizeof stream - at);
            if (n == 0)
                break;
            at += n;
            sequence++;
        }
        start = i + 1;
    }
    unsigned long found = 0;
    int rc = decode_stream(stream, at, &found, why, whylen);
    if (rc != FUZZ_BROKEN && found != sequence)
        rc = fuzz_broken(why, whylen, "%u good frames in a row, %lu found", (unsigned)sequence, found);
    return rc;
}

int fuzz_frame_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    unsigned long found = 0;
    int rc = decode_stream(data, size, &found, why, whylen);
    if (rc == FUZZ_BROKEN)
        return rc;
    rc = decode_wrapped(data, size, why, whylen);
    if (rc == FUZZ_BROKEN)
        return rc;
    if (found == 0) {
        snprintf(why, whylen, "no frame with good CRCs in %zu bytes", size);
        return FUZZ_REJECTED;
    }
    return FUZZ_ACCEPTED;
}

UWB_FUZZ_TARGET(fuzz_frame_input)
UWB_FUZZ_FRAME_MUTATOR
