/* The digitiser link's frames (board/digitiser-protocol.md): encoding, and
 * a decoder that finds whole, checked frames in any byte stream and
 * resynchronises after garbage, corruption or a truncated frame. Pure: no
 * I/O, so it can be fed anything (tests, fuzzers). */
#ifndef UWB_FRAME_H
#define UWB_FRAME_H

#include <stddef.h>
#include <stdint.h>

#define UWB_FRAME_SYNC_BYTES 4
extern const uint8_t uwb_frame_sync[UWB_FRAME_SYNC_BYTES]; /* A5 55 57 42: 0xA5 "UWB" */
#define UWB_FRAME_VERSION 1
#define UWB_FRAME_HEADER_BYTES 20   /* sync, type, version, flags, sequence, length, header CRC */
#define UWB_FRAME_TRAILER_BYTES 4   /* CRC-32 of header and payload */
#define UWB_FRAME_MAX_SAMPLES 65536 /* record length limit per trace */
#define UWB_FRAME_TRACE_HEADER_BYTES 8
#define UWB_FRAME_MAX_PAYLOAD (UWB_FRAME_TRACE_HEADER_BYTES + 2 * UWB_FRAME_MAX_SAMPLES)
#define UWB_FRAME_MAX_BYTES (UWB_FRAME_HEADER_BYTES + UWB_FRAME_MAX_PAYLOAD + UWB_FRAME_TRAILER_BYTES)

enum uwb_frame_type {
    /* host -> digitiser */
    UWB_FRAME_PING = 0x01,
    UWB_FRAME_CONFIGURE = 0x02, /* payload: u32 samples, f64 sample_interval_s */
    UWB_FRAME_ARM = 0x03,       /* answer every trigger from now on; data sequence restarts at 0 */
    UWB_FRAME_DISARM = 0x04,
    /* digitiser -> host */
    UWB_FRAME_PONG = 0x81,       /* payload: identity text */
    UWB_FRAME_CONFIGURED = 0x82, /* payload as CONFIGURE: what is now in force */
    UWB_FRAME_ARMED = 0x83,
    UWB_FRAME_DISARMED = 0x84,
    UWB_FRAME_ERROR = 0x8F, /* payload: u16 code, text */
    UWB_FRAME_DATA = 0x90,  /* one trace answering one trigger */
};

struct uwb_frame {
    uint8_t type;
    uint8_t version;
    uint16_t flags;
    uint32_t sequence; /* commands: chosen by the host, echoed in the reply; DATA: trigger count since ARM */
    uint32_t length;   /* payload bytes */
    const uint8_t *payload; /* points into the decoded buffer */
};

/* Bytes a frame with `payload_len` bytes of payload occupies. */
size_t uwb_frame_size(size_t payload_len);
/* Encode into out; returns the bytes written, 0 if outlen is too small or
 * the payload too long. */
size_t uwb_frame_encode(uint8_t type, uint32_t sequence, const void *payload, size_t payload_len,
                        uint8_t *out, size_t outlen);

enum uwb_frame_status {
    UWB_FRAME_FOUND = 1,
    UWB_FRAME_NEED_MORE = 0,
    UWB_FRAME_BAD_HEADER = -1, /* a sync marker whose header fails its CRC, version or length limit */
    UWB_FRAME_BAD_CRC = -2,    /* a good header whose frame CRC fails (corrupt, or truncated and overrun) */
};

/* Look for one frame at the start of buf[0..len). Always sets *consumed to
 * the bytes the caller may drop before calling again: FOUND: up to the end
 * of the frame (garbage before it included); NEED_MORE: garbage that
 * cannot begin a frame; BAD_*: the garbage and the false sync's first byte.
 * On FOUND, frame->payload points into buf. */
int uwb_frame_decode(const uint8_t *buf, size_t len, struct uwb_frame *frame, size_t *consumed);

/* An incremental decoder over a byte stream, with counts of what it threw
 * away. */
struct uwb_frame_decoder {
    uint8_t *buf;
    size_t start, len, cap; /* undecoded bytes are buf[start..len) */
    unsigned long frames, bad_headers, bad_crcs;
    unsigned long long skipped_bytes;
};

int uwb_frame_decoder_init(struct uwb_frame_decoder *dec);
void uwb_frame_decoder_free(struct uwb_frame_decoder *dec);
/* Forget buffered bytes (after a timeout or a reconnection); counts stay. */
void uwb_frame_decoder_reset(struct uwb_frame_decoder *dec);
/* Where to put new bytes and how many fit; then commit what was put there.
 * Frames returned earlier are invalid after space(). */
uint8_t *uwb_frame_decoder_space(struct uwb_frame_decoder *dec, size_t *room);
void uwb_frame_decoder_commit(struct uwb_frame_decoder *dec, size_t n);
/* Copying convenience over space/commit; returns the bytes taken. */
size_t uwb_frame_decoder_feed(struct uwb_frame_decoder *dec, const void *bytes, size_t n);
/* The next frame from what was fed: FOUND, NEED_MORE, or a BAD_* status
 * (the bad bytes are already skipped; call again to go on). */
int uwb_frame_decoder_next(struct uwb_frame_decoder *dec, struct uwb_frame *frame);

/* DATA payload: u32 samples, f32 volts per count, then samples x int16 LE. */
struct uwb_trace_view {
    uint32_t samples;
    float volts_per_count;
    const uint8_t *codes;
};
size_t uwb_trace_payload_size(uint32_t samples);
/* Returns the payload bytes written, 0 if out is too small. */
size_t uwb_trace_payload_encode(const int16_t *codes, uint32_t samples, float volts_per_count, uint8_t *out,
                                size_t outlen);
/* Checks that the length matches the sample count; 0 or -1 with err. */
int uwb_trace_payload_parse(const struct uwb_frame *frame, struct uwb_trace_view *view, char *err,
                            size_t errlen);
int16_t uwb_trace_code(const struct uwb_trace_view *view, uint32_t i);

/* CONFIGURE / CONFIGURED payload. */
#define UWB_FRAME_CONFIGURE_BYTES 12
void uwb_configure_payload_encode(uint32_t samples, double sample_interval_s,
                                  uint8_t out[UWB_FRAME_CONFIGURE_BYTES]);
int uwb_configure_payload_parse(const struct uwb_frame *frame, uint32_t *samples, double *sample_interval_s);

/* ERROR payload: u16 code, text (not NUL-terminated on the wire). */
size_t uwb_error_payload_encode(uint16_t code, const char *text, uint8_t *out, size_t outlen);
/* "code N: text" into buf. */
void uwb_error_payload_describe(const struct uwb_frame *frame, char *buf, size_t buflen);

#endif
