/* The board's digitiser (board/digitiser-protocol.md): answers PING,
 * CONFIGURE, ARM and DISARM, and, while armed, every TRIGGER rising edge
 * with one DATA frame whose trace the simulator computes, with fresh
 * noise, for the y where the carriage really is. Fault knobs spoil frames
 * on purpose. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "emu.h"

#define WRITE_TIMEOUT_MS 2000

void emu_digitiser_attach(struct emu_board *b, struct uwb_link *link)
{
    emu_digitiser_detach(b);
    b->digitiser = link;
    b->armed = 0; /* a new connection starts as a digitiser just powered */
    uwb_frame_decoder_reset(&b->decoder);
}

void emu_digitiser_detach(struct emu_board *b)
{
    if (b->digitiser)
        uwb_link_close(b->digitiser);
    b->digitiser = NULL;
    b->armed = 0;
}

static int send_bytes(struct emu_board *b, const uint8_t *bytes, size_t n)
{
    char err[512];
    if (uwb_link_write_all(b->digitiser, bytes, n, WRITE_TIMEOUT_MS, err, sizeof err) != UWB_LINK_OK) {
        fprintf(stderr, "uwbemu: digitiser: %s; dropping the connection\n", err);
        emu_digitiser_detach(b);
        return -1;
    }
    return 0;
}

static int reply(struct emu_board *b, uint8_t type, uint32_t sequence, const void *payload, size_t len)
{
    uint8_t out[UWB_FRAME_HEADER_BYTES + 256 + UWB_FRAME_TRAILER_BYTES];
    size_t n = uwb_frame_encode(type, sequence, payload, len, out, sizeof out);
    return n ? send_bytes(b, out, n) : -1;
}

static int reply_error(struct emu_board *b, uint32_t sequence, uint16_t code, const char *text)
{
    uint8_t payload[240];
    size_t n = uwb_error_payload_encode(code, text, payload, sizeof payload);
    return reply(b, UWB_FRAME_ERROR, sequence, payload, n);
}

static int configure(struct emu_board *b, const struct uwb_frame *f)
{
    uint32_t samples;
    double interval;
    if (uwb_configure_payload_parse(f, &samples, &interval) != 0)
        return reply_error(b, f->sequence, 2, "CONFIGURE payload must be 12 bytes");
    if (samples != (uint32_t)b->scene.samples || interval != b->scene.sample_interval_s) {
        struct sim_scene scene = b->scene;
        char text[64], err[512];
        snprintf(text, sizeof text, "%u", (unsigned)samples);
        int rc = sim_scene_set(&scene, "samples", text, err, sizeof err);
        snprintf(text, sizeof text, "%.17g", interval);
        if (rc == 0)
            rc = sim_scene_set(&scene, "sample_interval_s", text, err, sizeof err);
        if (rc == 0)
            rc = emu_board_set_scene(b, &scene, err, sizeof err);
        if (rc != 0)
            return reply_error(b, f->sequence, 3, err);
        fprintf(stderr, "uwbemu: digitiser configured: %u samples at %g s\n", (unsigned)samples, interval);
    }
    uint8_t payload[UWB_FRAME_CONFIGURE_BYTES];
    uwb_configure_payload_encode((uint32_t)b->scene.samples, b->scene.sample_interval_s, payload);
    return reply(b, UWB_FRAME_CONFIGURED, f->sequence, payload, sizeof payload);
}

static int command(struct emu_board *b, const struct uwb_frame *f)
{
    switch (f->type) {
    case UWB_FRAME_PING: {
        char identity[64];
        snprintf(identity, sizeof identity, "uwbemu %s (emulated digitiser)", EMU_VERSION);
        return reply(b, UWB_FRAME_PONG, f->sequence, identity, strlen(identity));
    }
    case UWB_FRAME_CONFIGURE: return configure(b, f);
    case UWB_FRAME_ARM:
        b->armed = 1;
        b->sequence = 0;
        return reply(b, UWB_FRAME_ARMED, f->sequence, NULL, 0);
    case UWB_FRAME_DISARM: b->armed = 0; return reply(b, UWB_FRAME_DISARMED, f->sequence, NULL, 0);
    default: {
        char text[64];
        snprintf(text, sizeof text, "unknown command type 0x%02x", f->type);
        return reply_error(b, f->sequence, 1, text);
    }
    }
}

int emu_digitiser_readable(struct emu_board *b)
{
    size_t room;
    uint8_t *space = uwb_frame_decoder_space(&b->decoder, &room);
    char err[512];
    ssize_t n = uwb_link_read(b->digitiser, space, room, 0, err, sizeof err);
    if (n == UWB_LINK_ERR_TIMEOUT)
        return 0;
    if (n < 0) {
        fprintf(stderr, "uwbemu: digitiser: %s\n", err);
        emu_digitiser_detach(b);
        return -1;
    }
    uwb_frame_decoder_commit(&b->decoder, (size_t)n);
    struct uwb_frame f;
    int status;
    while (b->digitiser && (status = uwb_frame_decoder_next(&b->decoder, &f)) != UWB_FRAME_NEED_MORE)
        if (status == UWB_FRAME_FOUND && command(b, &f) != 0)
            return -1;
    return 0;
}

/* Volts to ADC codes: the scene's own ADC when it has one that fits int16
 * (its values are already whole codes), else full scale over 32767. */
static float to_codes(struct emu_board *b)
{
    const struct sim_scene *s = &b->scene;
    double lsb = s->adc_bits > 0 && s->adc_bits <= 16 ? 2.0 * s->adc_full_scale_v / ldexp(1.0, s->adc_bits)
                                                      : s->adc_full_scale_v / 32767.0;
    for (int i = 0; i < s->samples; i++) {
        double code = nearbyint(b->trace[i] / lsb);
        b->codes[i] = (int16_t)(code > 32767 ? 32767 : code < -32768 ? -32768 : code);
    }
    return (float)lsb;
}

void emu_digitiser_trigger(struct emu_board *b)
{
    b->triggers++;
    if (emu_fault_strikes(&b->fault[EMU_FAULT_SILENT])) {
        emu_board_log(b, -1, "silent");
        return;
    }
    if (!b->digitiser || !b->armed) {
        emu_board_log(b, -1, "unarmed");
        return;
    }
    if (emu_fault_strikes(&b->fault[EMU_FAULT_DISCONNECT])) {
        emu_board_log(b, -1, "disconnect");
        emu_digitiser_detach(b);
        return;
    }
    uint32_t sequence = b->sequence++;
    if (emu_fault_strikes(&b->fault[EMU_FAULT_DROP])) {
        emu_board_log(b, sequence, "drop");
        return;
    }
    double y = emu_board_y_m(b);
    char err[512];
    if (sim_engine_acquire(b->engine, y, 1, &b->acq, b->trace, err, sizeof err) != 0) {
        fprintf(stderr, "uwbemu: trace at y = %g m: %s\n", y, err);
        b->frames_failed++;
        emu_board_log(b, sequence, "error");
        return;
    }
    b->last_trace_y_m = y;
    float lsb = to_codes(b);
    uint32_t samples = (uint32_t)b->scene.samples;
    size_t payload_len =
        uwb_trace_payload_encode(b->codes, samples, lsb, b->payload, uwb_trace_payload_size(samples));
    size_t n = uwb_frame_encode(UWB_FRAME_DATA, sequence, b->payload, payload_len, b->frame,
                                uwb_frame_size(payload_len));
    const char *result = "sent";
    if (emu_fault_strikes(&b->fault[EMU_FAULT_TRUNCATE])) {
        n /= 2;
        result = "truncate";
    } else if (emu_fault_strikes(&b->fault[EMU_FAULT_CRC])) {
        b->frame[UWB_FRAME_HEADER_BYTES + payload_len / 2] ^= 0x5A;
        result = "crc";
    }
    emu_board_log(b, sequence, result);
    if (send_bytes(b, b->frame, n) == 0)
        b->frames_sent++;
}
