/* The digitiser client: opens the link, checks who answers, configures
 * the record length, arms, and then turns each trigger into one checked
 * trace (CRC, sequence, length), firing again a bounded number of times
 * when a frame is bad or missing. Protocol: board/digitiser-protocol.md. */
#ifndef UWB_DIGITISER_H
#define UWB_DIGITISER_H

#include <stddef.h>
#include <stdint.h>

#include "uwb/link.h"

struct uwb_digitiser_config {
    char endpoint[UWB_ENDPOINT_MAX];
    int samples; /* record length per trace */
    double sample_interval_s;
    double t0_s; /* time of sample 0 after the trigger (from commissioning) */
    int stack;   /* pulses fired and averaged per position */
    int frame_timeout_ms;
    int frame_retries; /* bad or missing frames retried this many times per pulse */
};

enum uwb_digitiser_error {
    UWB_DIGITISER_OK = 0,
    UWB_DIGITISER_ERR_LINK = -1,     /* endpoint could not be opened (or reopened) */
    UWB_DIGITISER_ERR_PROTOCOL = -2, /* peer does not answer as a digitiser, or refused the configuration */
    UWB_DIGITISER_ERR_FRAMES = -3,   /* no good frame for a trigger within the retries */
    UWB_DIGITISER_ERR_FIRE = -4,     /* the fire callback failed (GPIO) */
    UWB_DIGITISER_ERR_CONFIG = -5,   /* the digitiser model is unknown (no backend in the table) */
};

struct uwb_digitiser_stats {
    unsigned long traces;       /* good traces returned */
    unsigned long fired;        /* triggers fired, retries included */
    unsigned long retries;      /* triggers fired again after a bad or missing frame */
    unsigned long timeouts;     /* triggers whose frame never came */
    unsigned long bad_frames;   /* frames failing a CRC (header or whole frame) */
    unsigned long bad_payloads; /* frames whose length or sample count is wrong */
    unsigned long stale;        /* frames answering an earlier trigger, dropped */
    unsigned long ahead;        /* frames whose sequence skipped triggers (digitiser counted more) */
    unsigned long reconnects;   /* link reopened after it failed */
};

struct uwb_digitiser;

/* `link_detail` (may be NULL) receives the uwb_link error when the link
 * itself could not be opened. */
int uwb_digitiser_open(const struct uwb_digitiser_config *cfg, struct uwb_digitiser **dig, int *link_detail,
                       char *err, size_t errlen);
/* What the digitiser said it is (PONG), e.g. "uwbemu 1.0". */
const char *uwb_digitiser_identity(const struct uwb_digitiser *dig);

/* Fires the pulser once (the rig's GPIO trigger pulse). */
typedef int (*uwb_fire_fn)(void *ctx, char *err, size_t errlen);

/* One trace of cfg->samples values, in volts, answering one trigger:
 * fire, wait frame_timeout_ms for its frame, check it; on a bad or missing
 * frame or a dropped link, fire again, up to frame_retries times. */
int uwb_digitiser_acquire(struct uwb_digitiser *dig, uwb_fire_fn fire, void *ctx, float *out, char *err,
                          size_t errlen);
void uwb_digitiser_get_stats(const struct uwb_digitiser *dig, struct uwb_digitiser_stats *stats);
/* Disarms (best effort) and closes. NULL is a no-op. */
void uwb_digitiser_close(struct uwb_digitiser *dig);

/* How a DATA frame's sequence relates to the one the next trigger should
 * get (wrap-around safe). */
enum uwb_sequence_check { UWB_SEQUENCE_EXPECTED, UWB_SEQUENCE_STALE, UWB_SEQUENCE_AHEAD };
enum uwb_sequence_check uwb_digitiser_check_sequence(uint32_t expected, uint32_t got);

#endif
