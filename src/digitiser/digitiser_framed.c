/* The framed protocol's digitiser backend (board/digitiser-protocol.md)
 * over a uwb_link: the first row of src/digitiser/digitiser.c's table.
 * Commands are answered by a reply carrying the command's sequence number; after ARM every trigger is
 * answered by one DATA frame whose sequence counts the triggers since ARM, so the host can tell the frame of
 * its own trigger from a late one of an earlier trigger. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "digitiser/digitiser_backend.h"
#include "uwb/digitiser.h"
#include "uwb/frame.h"
#include "uwb/link.h"
#include "uwb/monotonic.h"

/* Commands may make a digitiser (or the emulated board) rebuild its
 * acquisition set-up; give them longer than one frame. */
#define MIN_COMMAND_TIMEOUT_MS 5000
#define WRITE_TIMEOUT_MS 2000

struct framed {
    struct uwb_digitiser_config cfg;
    struct uwb_link *link; /* NULL after a failure until reconnected */
    struct uwb_frame_decoder dec;
    uint32_t command_sequence;
    uint32_t next_trigger; /* sequence the next trigger's frame should carry */
    char identity[128];
    struct uwb_digitiser_stats stats;
};

/* Internal outcomes of waiting for a frame, beside enum uwb_frame_status. */
enum { WAIT_TIMEOUT = -10, WAIT_LINK = -11 };

enum uwb_sequence_check uwb_digitiser_check_sequence(uint32_t expected, uint32_t got)
{
    int32_t ahead = (int32_t)(got - expected);
    if (ahead == 0)
        return UWB_SEQUENCE_EXPECTED;
    return ahead < 0 ? UWB_SEQUENCE_STALE : UWB_SEQUENCE_AHEAD;
}

/* The next frame, a BAD_* status (already skipped), WAIT_TIMEOUT or WAIT_LINK. */
static int next_frame(struct framed *d, struct uwb_frame *frame, long long deadline, char *err, size_t errlen)
{
    for (;;) {
        int status = uwb_frame_decoder_next(&d->dec, frame);
        if (status != UWB_FRAME_NEED_MORE)
            return status;
        long long left = deadline - uwb_monotonic_ms();
        if (left <= 0) {
            snprintf(err, errlen, "%s: no complete frame in time", d->cfg.endpoint);
            return WAIT_TIMEOUT;
        }
        size_t room;
        uint8_t *space = uwb_frame_decoder_space(&d->dec, &room);
        ssize_t n = uwb_link_read(d->link, space, room, (int)left, err, errlen);
        if (n == UWB_LINK_ERR_TIMEOUT)
            return WAIT_TIMEOUT;
        if (n < 0)
            return WAIT_LINK;
        uwb_frame_decoder_commit(&d->dec, (size_t)n);
    }
}

static int command_timeout_ms(const struct framed *d)
{
    return d->cfg.frame_timeout_ms > MIN_COMMAND_TIMEOUT_MS ? d->cfg.frame_timeout_ms
                                                            : MIN_COMMAND_TIMEOUT_MS;
}

static const char *command_name(uint8_t type)
{
    switch (type) {
    case UWB_FRAME_PING: return "PING";
    case UWB_FRAME_CONFIGURE: return "CONFIGURE";
    case UWB_FRAME_ARM: return "ARM";
    case UWB_FRAME_DISARM: return "DISARM";
    default: return "command"; /* unreachable on purpose: command() sends only the four above */
    }
}

/* Send a command and wait for its reply (type | 0x80 with the same
 * sequence); DATA and unrelated frames met on the way are dropped. */
static int command(struct framed *d, uint8_t type, const void *payload, size_t len, struct uwb_frame *reply,
                   char *err, size_t errlen)
{
    uint8_t out[64];
    uint32_t sequence = d->command_sequence++;
    size_t n = uwb_frame_encode(type, sequence, payload, len, out, sizeof out);
    char why[512];
    if (uwb_link_write_all(d->link, out, n, WRITE_TIMEOUT_MS, why, sizeof why) != UWB_LINK_OK) {
        snprintf(err, errlen, "digitiser %s: %s", command_name(type), why);
        return UWB_DIGITISER_ERR_LINK;
    }
    long long deadline = uwb_monotonic_ms() + command_timeout_ms(d);
    for (;;) {
        int status = next_frame(d, reply, deadline, why, sizeof why);
        if (status == WAIT_TIMEOUT) {
            snprintf(err, errlen,
                     "digitiser at %s: no reply to %s within %d ms (is it a digitiser speaking "
                     "board/digitiser-protocol.md?)",
                     d->cfg.endpoint, command_name(type), command_timeout_ms(d));
            return UWB_DIGITISER_ERR_PROTOCOL;
        }
        if (status == WAIT_LINK) {
            snprintf(err, errlen, "digitiser %s: %s", command_name(type), why);
            return UWB_DIGITISER_ERR_LINK;
        }
        if (status != UWB_FRAME_FOUND || reply->sequence != sequence)
            continue;
        if (reply->type == UWB_FRAME_ERROR) {
            uwb_error_payload_describe(reply, why, sizeof why);
            snprintf(err, errlen, "digitiser at %s refused %s: %s", d->cfg.endpoint, command_name(type), why);
            return UWB_DIGITISER_ERR_PROTOCOL;
        }
        if (reply->type == (type | 0x80))
            return UWB_DIGITISER_OK;
    }
}

/* Open the link and bring the digitiser to "armed" with our record length. */
static int connect_and_arm(struct framed *d, int *link_detail, char *err, size_t errlen)
{
    int rc = uwb_link_open(d->cfg.endpoint, &d->link, err, errlen);
    if (link_detail)
        *link_detail = rc;
    if (rc != UWB_LINK_OK)
        return UWB_DIGITISER_ERR_LINK;
    uwb_frame_decoder_reset(&d->dec);
    struct uwb_frame reply;
    rc = command(d, UWB_FRAME_PING, NULL, 0, &reply, err, errlen);
    if (rc == UWB_DIGITISER_OK) {
        size_t n = reply.length < sizeof d->identity ? reply.length : sizeof d->identity - 1;
        memcpy(d->identity, reply.payload, n);
        d->identity[n] = '\0';
        for (size_t i = 0; i < n; i++) /* it ends up in file headers: printable only */
            if (d->identity[i] < 0x20 || d->identity[i] > 0x7e)
                d->identity[i] = '?';
        uint8_t payload[UWB_FRAME_CONFIGURE_BYTES];
        uwb_configure_payload_encode((uint32_t)d->cfg.samples, d->cfg.sample_interval_s, payload);
        rc = command(d, UWB_FRAME_CONFIGURE, payload, sizeof payload, &reply, err, errlen);
    }
    if (rc == UWB_DIGITISER_OK) {
        uint32_t samples;
        double interval;
        if (uwb_configure_payload_parse(&reply, &samples, &interval) != 0) {
            snprintf(err, errlen, "digitiser at %s: malformed CONFIGURED reply", d->cfg.endpoint);
            rc = UWB_DIGITISER_ERR_PROTOCOL;
        } else if ((int)samples != d->cfg.samples ||
                   fabs(interval - d->cfg.sample_interval_s) > 1e-6 * d->cfg.sample_interval_s) {
            snprintf(err, errlen, "digitiser at %s runs %u samples at %g s, the config asks for %d at %g s",
                     d->cfg.endpoint, (unsigned)samples, interval, d->cfg.samples, d->cfg.sample_interval_s);
            rc = UWB_DIGITISER_ERR_PROTOCOL;
        }
    }
    if (rc == UWB_DIGITISER_OK)
        rc = command(d, UWB_FRAME_ARM, NULL, 0, &reply, err, errlen);
    if (rc != UWB_DIGITISER_OK) {
        uwb_link_close(d->link);
        d->link = NULL;
        return rc;
    }
    d->next_trigger = 0;
    return UWB_DIGITISER_OK;
}

static int framed_open(struct uwb_digitiser *dig, const struct uwb_digitiser_config *cfg, int *link_detail,
                       char *err, size_t errlen)
{
    if (cfg->samples < 1 || cfg->samples > UWB_FRAME_MAX_SAMPLES || !(cfg->sample_interval_s > 0) ||
        cfg->frame_timeout_ms < 1 || cfg->frame_retries < 0) {
        snprintf(err, errlen,
                 "digitiser config: samples must be 1..%d, sample_interval_s > 0, "
                 "frame_timeout_ms >= 1 and frame_retries >= 0",
                 UWB_FRAME_MAX_SAMPLES);
        return UWB_DIGITISER_ERR_PROTOCOL;
    }
    struct framed *d = calloc(1, sizeof *d);
    if (!d || uwb_frame_decoder_init(&d->dec) != 0) {
        free(d);
        snprintf(err, errlen, "digitiser: out of memory");
        return UWB_DIGITISER_ERR_LINK;
    }
    d->cfg = *cfg;
    int rc = connect_and_arm(d, link_detail, err, errlen);
    if (rc != UWB_DIGITISER_OK) {
        uwb_frame_decoder_free(&d->dec);
        free(d);
        return rc;
    }
    dig->state = d;
    return UWB_DIGITISER_OK;
}

static const char *framed_identity(const struct uwb_digitiser *dig)
{
    const struct framed *d = dig->state;
    return d->identity;
}

/* Waits for the frame answering the trigger just fired (sequence
 * `expected`). 1: got it in out; 0: bad or missing, fire again; <0: fatal. */
static int await_trace(struct framed *d, uint32_t expected, float *out, char *why, size_t whylen)
{
    long long deadline = uwb_monotonic_ms() + d->cfg.frame_timeout_ms;
    for (;;) {
        struct uwb_frame frame;
        int status = next_frame(d, &frame, deadline, why, whylen);
        if (status == WAIT_TIMEOUT) {
            d->stats.timeouts++;
            snprintf(why, whylen, "no frame within %d ms", d->cfg.frame_timeout_ms);
            /* A partial frame left in the buffer will never complete. */
            uwb_frame_decoder_reset(&d->dec);
            return 0;
        }
        if (status == WAIT_LINK) {
            uwb_link_close(d->link);
            d->link = NULL;
            return 0;
        }
        if (status == UWB_FRAME_BAD_HEADER || status == UWB_FRAME_BAD_CRC) {
            d->stats.bad_frames++;
            snprintf(why, whylen, "frame failed its %s CRC",
                     status == UWB_FRAME_BAD_HEADER ? "header" : "frame");
            return 0;
        }
        if (frame.type != UWB_FRAME_DATA)
            continue;
        enum uwb_sequence_check check = uwb_digitiser_check_sequence(expected, frame.sequence);
        if (check == UWB_SEQUENCE_STALE) {
            d->stats.stale++;
            continue;
        }
        if (check == UWB_SEQUENCE_AHEAD) {
            /* The digitiser saw triggers we did not fire (a glitch on the
             * line): the frame still follows our trigger, so it is taken,
             * and our count follows the digitiser's. */
            d->stats.ahead++;
            d->next_trigger = frame.sequence + 1;
        }
        struct uwb_trace_view view;
        if (uwb_trace_payload_parse(&frame, &view, why, whylen) != 0) {
            d->stats.bad_payloads++;
            return 0;
        }
        if ((int)view.samples != d->cfg.samples) {
            d->stats.bad_payloads++;
            snprintf(why, whylen, "data frame %u has %u samples, configured %d", (unsigned)frame.sequence,
                     (unsigned)view.samples, d->cfg.samples);
            return 0;
        }
        for (uint32_t i = 0; i < view.samples; i++)
            out[i] = (float)uwb_trace_code(&view, i) * view.volts_per_count;
        return 1;
    }
}

static int framed_acquire(struct uwb_digitiser *dig, uwb_fire_fn fire, void *ctx, float *out, char *err,
                          size_t errlen)
{
    struct framed *d = dig->state;
    char why[512] = "";
    for (int attempt = 0; attempt <= d->cfg.frame_retries; attempt++) {
        if (!d->link) {
            d->stats.reconnects++;
            if (connect_and_arm(d, NULL, why, sizeof why) != UWB_DIGITISER_OK)
                continue;
        }
        if (attempt > 0)
            d->stats.retries++;
        uint32_t expected = d->next_trigger++;
        d->stats.fired++;
        int rc = fire(ctx, err, errlen);
        if (rc != 0)
            return UWB_DIGITISER_ERR_FIRE;
        int got = await_trace(d, expected, out, why, sizeof why);
        if (got > 0) {
            d->stats.traces++;
            return UWB_DIGITISER_OK;
        }
    }
    snprintf(err, errlen, "digitiser at %s: no good frame after %d trigger%s; last problem: %s",
             d->cfg.endpoint, d->cfg.frame_retries + 1, d->cfg.frame_retries ? "s" : "", why);
    return UWB_DIGITISER_ERR_FRAMES;
}

static void framed_get_stats(const struct uwb_digitiser *dig, struct uwb_digitiser_stats *stats)
{
    const struct framed *d = dig->state;
    *stats = d->stats;
}

static void framed_close(struct uwb_digitiser *dig)
{
    struct framed *d = dig->state;
    if (d->link) {
        uint8_t out[64];
        char ignored[256];
        size_t n = uwb_frame_encode(UWB_FRAME_DISARM, d->command_sequence++, NULL, 0, out, sizeof out);
        uwb_link_write_all(d->link, out, n, 200, ignored, sizeof ignored);
        uwb_link_close(d->link);
    }
    uwb_frame_decoder_free(&d->dec);
    free(d);
}

const struct uwb_digitiser_backend uwb_digitiser_framed_backend = {
    .name = "framed",
    .open = framed_open,
    .identity = framed_identity,
    .acquire = framed_acquire,
    .get_stats = framed_get_stats,
    .close = framed_close,
};
