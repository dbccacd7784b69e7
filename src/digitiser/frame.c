/* Digitiser frames: layout in board/digitiser-protocol.md. The header has
 * its own CRC so that a corrupted length is caught before the decoder
 * waits for bytes that will never come; the trailer CRC covers the whole
 * frame. CRC-32 is zlib's. */
#include "uwb/frame.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

const uint8_t uwb_frame_sync[UWB_FRAME_SYNC_BYTES] = {0xA5, 0x55, 0x57, 0x42};

static void put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint16_t get_u16(const uint8_t *p)
{
    return (uint16_t)(p[0] | p[1] << 8);
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint32_t crc_of(const uint8_t *p, size_t n)
{
    return (uint32_t)crc32(crc32(0L, Z_NULL, 0), p, (uInt)n);
}

size_t uwb_frame_size(size_t payload_len)
{
    return UWB_FRAME_HEADER_BYTES + payload_len + UWB_FRAME_TRAILER_BYTES;
}

size_t uwb_frame_encode(uint8_t type, uint32_t sequence, const void *payload, size_t payload_len,
                        uint8_t *out, size_t outlen)
{
    if (payload_len > UWB_FRAME_MAX_PAYLOAD || outlen < uwb_frame_size(payload_len))
        return 0;
    memcpy(out, uwb_frame_sync, UWB_FRAME_SYNC_BYTES);
    out[4] = type;
    out[5] = UWB_FRAME_VERSION;
    put_u16(out + 6, 0);
    put_u32(out + 8, sequence);
    put_u32(out + 12, (uint32_t)payload_len);
    put_u32(out + 16, crc_of(out, 16));
    if (payload_len)
        memcpy(out + UWB_FRAME_HEADER_BYTES, payload, payload_len);
    size_t body = UWB_FRAME_HEADER_BYTES + payload_len;
    put_u32(out + body, crc_of(out, body));
    return body + UWB_FRAME_TRAILER_BYTES;
}

/* Offset of the first full sync marker, or of a partial one at the very
 * end (which the next bytes may complete), or len. */
static size_t find_sync(const uint8_t *buf, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (buf[i] != uwb_frame_sync[0])
            continue;
        size_t n = len - i < UWB_FRAME_SYNC_BYTES ? len - i : UWB_FRAME_SYNC_BYTES;
        if (memcmp(buf + i, uwb_frame_sync, n) == 0)
            return i;
    }
    return len;
}

int uwb_frame_decode(const uint8_t *buf, size_t len, struct uwb_frame *frame, size_t *consumed)
{
    size_t at = find_sync(buf, len);
    *consumed = at;
    if (len - at < UWB_FRAME_HEADER_BYTES)
        return UWB_FRAME_NEED_MORE;
    const uint8_t *h = buf + at;
    uint32_t length = get_u32(h + 12);
    if (get_u32(h + 16) != crc_of(h, 16) || h[5] != UWB_FRAME_VERSION || length > UWB_FRAME_MAX_PAYLOAD) {
        *consumed = at + 1;
        return UWB_FRAME_BAD_HEADER;
    }
    size_t size = uwb_frame_size(length);
    if (len - at < size)
        return UWB_FRAME_NEED_MORE;
    size_t body = UWB_FRAME_HEADER_BYTES + length;
    if (get_u32(h + body) != crc_of(h, body)) {
        *consumed = at + 1;
        return UWB_FRAME_BAD_CRC;
    }
    frame->type = h[4];
    frame->version = h[5];
    frame->flags = get_u16(h + 6);
    frame->sequence = get_u32(h + 8);
    frame->length = length;
    frame->payload = h + UWB_FRAME_HEADER_BYTES;
    *consumed = at + size;
    return UWB_FRAME_FOUND;
}

int uwb_frame_decoder_init(struct uwb_frame_decoder *dec)
{
    memset(dec, 0, sizeof *dec);
    /* Room for one whole frame of the largest size plus the start of the
     * next, so a frame that fits the limits always fits the buffer. */
    dec->cap = 2 * (size_t)UWB_FRAME_MAX_BYTES;
    dec->buf = malloc(dec->cap);
    return dec->buf ? 0 : -1;
}

void uwb_frame_decoder_free(struct uwb_frame_decoder *dec)
{
    free(dec->buf);
    memset(dec, 0, sizeof *dec);
}

void uwb_frame_decoder_reset(struct uwb_frame_decoder *dec)
{
    dec->skipped_bytes += dec->len - dec->start;
    dec->start = dec->len = 0;
}

uint8_t *uwb_frame_decoder_space(struct uwb_frame_decoder *dec, size_t *room)
{
    if (dec->start > 0) {
        memmove(dec->buf, dec->buf + dec->start, dec->len - dec->start);
        dec->len -= dec->start;
        dec->start = 0;
    }
    *room = dec->cap - dec->len;
    return dec->buf + dec->len;
}

void uwb_frame_decoder_commit(struct uwb_frame_decoder *dec, size_t n)
{
    if (n > dec->cap - dec->len)
        n = dec->cap - dec->len;
    dec->len += n;
}

size_t uwb_frame_decoder_feed(struct uwb_frame_decoder *dec, const void *bytes, size_t n)
{
    size_t room;
    uint8_t *space = uwb_frame_decoder_space(dec, &room);
    if (n > room)
        n = room;
    memcpy(space, bytes, n);
    uwb_frame_decoder_commit(dec, n);
    return n;
}

int uwb_frame_decoder_next(struct uwb_frame_decoder *dec, struct uwb_frame *frame)
{
    size_t consumed;
    int status = uwb_frame_decode(dec->buf + dec->start, dec->len - dec->start, frame, &consumed);
    size_t skipped = consumed;
    if (status == UWB_FRAME_FOUND) {
        skipped = consumed - uwb_frame_size(frame->length);
        dec->frames++;
    } else if (status == UWB_FRAME_BAD_HEADER) {
        dec->bad_headers++;
    } else if (status == UWB_FRAME_BAD_CRC) {
        dec->bad_crcs++;
    }
    dec->skipped_bytes += skipped;
    dec->start += consumed;
    /* A full buffer with no frame in it cannot happen (a header that passes
     * its checks announces a frame that fits), but never stall on it. */
    if (status == UWB_FRAME_NEED_MORE && dec->start == 0 && dec->len == dec->cap) {
        dec->skipped_bytes += dec->len;
        dec->len = 0;
    }
    return status;
}

size_t uwb_trace_payload_size(uint32_t samples)
{
    return UWB_FRAME_TRACE_HEADER_BYTES + 2 * (size_t)samples;
}

size_t uwb_trace_payload_encode(const int16_t *codes, uint32_t samples, float volts_per_count, uint8_t *out,
                                size_t outlen)
{
    size_t size = uwb_trace_payload_size(samples);
    if (outlen < size)
        return 0;
    uint32_t bits;
    memcpy(&bits, &volts_per_count, sizeof bits);
    put_u32(out, samples);
    put_u32(out + 4, bits);
    for (uint32_t i = 0; i < samples; i++)
        put_u16(out + UWB_FRAME_TRACE_HEADER_BYTES + 2 * (size_t)i, (uint16_t)codes[i]);
    return size;
}

int uwb_trace_payload_parse(const struct uwb_frame *frame, struct uwb_trace_view *view, char *err,
                            size_t errlen)
{
    if (frame->length < UWB_FRAME_TRACE_HEADER_BYTES) {
        snprintf(err, errlen, "data frame %u: payload of %u bytes is shorter than its %d-byte header",
                 (unsigned)frame->sequence, (unsigned)frame->length, UWB_FRAME_TRACE_HEADER_BYTES);
        return -1;
    }
    view->samples = get_u32(frame->payload);
    uint32_t bits = get_u32(frame->payload + 4);
    memcpy(&view->volts_per_count, &bits, sizeof bits);
    view->codes = frame->payload + UWB_FRAME_TRACE_HEADER_BYTES;
    if (view->samples > UWB_FRAME_MAX_SAMPLES || uwb_trace_payload_size(view->samples) != frame->length) {
        snprintf(err, errlen, "data frame %u: says %u samples but carries %u payload bytes",
                 (unsigned)frame->sequence, (unsigned)view->samples, (unsigned)frame->length);
        return -1;
    }
    if (!(view->volts_per_count > 0) || view->volts_per_count > 1e6f) {
        snprintf(err, errlen, "data frame %u: scale of %g V per count is not usable",
                 (unsigned)frame->sequence, (double)view->volts_per_count);
        return -1;
    }
    return 0;
}

int16_t uwb_trace_code(const struct uwb_trace_view *view, uint32_t i)
{
    return (int16_t)get_u16(view->codes + 2 * (size_t)i);
}

void uwb_configure_payload_encode(uint32_t samples, double sample_interval_s,
                                  uint8_t out[UWB_FRAME_CONFIGURE_BYTES])
{
    uint64_t bits;
    memcpy(&bits, &sample_interval_s, sizeof bits);
    put_u32(out, samples);
    put_u32(out + 4, (uint32_t)bits);
    put_u32(out + 8, (uint32_t)(bits >> 32));
}

int uwb_configure_payload_parse(const struct uwb_frame *frame, uint32_t *samples, double *sample_interval_s)
{
    if (frame->length != UWB_FRAME_CONFIGURE_BYTES)
        return -1;
    *samples = get_u32(frame->payload);
    uint64_t bits = (uint64_t)get_u32(frame->payload + 4) | (uint64_t)get_u32(frame->payload + 8) << 32;
    memcpy(sample_interval_s, &bits, sizeof bits);
    return 0;
}

size_t uwb_error_payload_encode(uint16_t code, const char *text, uint8_t *out, size_t outlen)
{
    size_t n = strlen(text);
    if (outlen < 2)
        return 0;
    if (n > outlen - 2)
        n = outlen - 2;
    put_u16(out, code);
    // NOLINTNEXTLINE(bugprone-not-null-terminated-result): a frame payload, not a C string
    memcpy(out + 2, text, n);
    return 2 + n;
}

void uwb_error_payload_describe(const struct uwb_frame *frame, char *buf, size_t buflen)
{
    if (frame->length < 2) {
        snprintf(buf, buflen, "error frame without a code");
        return;
    }
    /* The text is untrusted: stop at a NUL, cap the length. */
    int n = (int)(frame->length - 2 > 200 ? 200 : frame->length - 2);
    const char *text = (const char *)frame->payload + 2;
    const char *nul = memchr(text, '\0', (size_t)n);
    if (nul)
        n = (int)(nul - text);
    snprintf(buf, buflen, "code %u: %.*s", (unsigned)get_u16(frame->payload), n, text);
}
