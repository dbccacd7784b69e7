/* Fuzzing the digitiser client (src/digitiser/digitiser_framed.c) on the frames
 * it reads: the input is everything a digitiser says on the link, from
 * the replies to PING, CONFIGURE and ARM to the DATA frames of three
 * triggers (scripted_link.c plays it back; the link then ends, and
 * reconnections find nobody). The pure frame decoder has its own target
 * (fuzz_frame.c); this one covers what the client does with the frames:
 * reply matching by sequence, the identity text, the CONFIGURED check,
 * sequence tracking of DATA frames, retries and reconnects.
 *
 * Contract: open and acquire return one of their documented codes and
 * fill err when they fail; the identity is printable; a trace is finite
 * and within the frame format's range; the statistics add up. */
#include <math.h>
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/digitiser.h"

#define SAMPLES 16
#define SAMPLE_INTERVAL_S 1e-11
#define TRIGGERS 3

static int fire_nothing(void *ctx, char *err, size_t errlen)
{
    (void)err;
    (void)errlen;
    ++*(unsigned *)ctx;
    return 0;
}

static int check_trace(const float *trace, char *why, size_t whylen)
{
    /* int16 codes times a scale of at most 1e6 V per count. */
    for (int i = 0; i < SAMPLES; i++)
        if (!isfinite(trace[i]) || fabsf(trace[i]) > 32768.0f * 1e6f)
            return fuzz_broken(why, whylen, "trace sample %d is %g", i, (double)trace[i]);
    return FUZZ_ACCEPTED;
}

static int check_identity(const char *identity, char *why, size_t whylen)
{
    for (const char *c = identity; *c; c++)
        if (*c < 0x20 || *c > 0x7e)
            return fuzz_broken(why, whylen, "identity holds byte 0x%02x", (unsigned char)*c);
    return FUZZ_ACCEPTED;
}

static int run_session(struct uwb_digitiser_config *cfg, char *why, size_t whylen)
{
    struct uwb_digitiser *dig = NULL;
    int link_detail = 0;
    why[0] = '\0';
    int rc = uwb_digitiser_open(cfg, &dig, &link_detail, why, whylen);
    if (rc != UWB_DIGITISER_OK) {
        if (dig)
            return fuzz_broken(why, whylen, "open failed (%d) but returned a digitiser", rc);
        if (rc != UWB_DIGITISER_ERR_LINK && rc != UWB_DIGITISER_ERR_PROTOCOL)
            return fuzz_broken(why, whylen, "open returned %d", rc);
        if (!why[0])
            return fuzz_broken(why, whylen, "open failed (%d) without a message", rc);
        return FUZZ_REJECTED;
    }
    int outcome = check_identity(uwb_digitiser_identity(dig), why, whylen);
    unsigned fired = 0, traces = 0;
    float trace[SAMPLES];
    for (int t = 0; outcome != FUZZ_BROKEN && t < TRIGGERS; t++) {
        char err[1024] = "";
        memset(trace, 0xff, sizeof trace); /* NaN until written */
        rc = uwb_digitiser_acquire(dig, fire_nothing, &fired, trace, err, sizeof err);
        if (rc == UWB_DIGITISER_OK) {
            traces++;
            outcome = check_trace(trace, why, whylen);
        } else if (rc != UWB_DIGITISER_ERR_FRAMES) {
            outcome = fuzz_broken(why, whylen, "acquire returned %d (%s)", rc, err);
        } else if (!err[0]) {
            outcome = fuzz_broken(why, whylen, "acquire failed without a message");
        }
    }
    if (outcome != FUZZ_BROKEN) {
        struct uwb_digitiser_stats st;
        uwb_digitiser_get_stats(dig, &st);
        if (st.traces != traces || st.fired != fired || st.retries > st.fired ||
            st.fired > (unsigned long)TRIGGERS * (unsigned long)(cfg->frame_retries + 1))
            outcome =
                fuzz_broken(why, whylen, "stats: %lu traces (%u returned), %lu fired (%u fired), %lu retries",
                            st.traces, traces, st.fired, fired, st.retries);
        else if (traces == 0) {
            snprintf(why, whylen, "no trace in %lu triggers", st.fired);
            outcome = FUZZ_REJECTED;
        }
    }
    uwb_digitiser_close(dig);
    return outcome;
}

int fuzz_digitiser_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    struct uwb_digitiser_config cfg = {
        .endpoint = "unix:fuzz-digitiser.sock",
        .samples = SAMPLES,
        .sample_interval_s = SAMPLE_INTERVAL_S,
        .stack = 1,
        /* Never reached: the scripted link ends instead of going silent. */
        .frame_timeout_ms = 1000,
        .frame_retries = 2,
    };
    fuzz_link_script(data, size);
    int rc = run_session(&cfg, why, whylen);
    fuzz_link_script(NULL, 0);
    return rc;
}

UWB_FUZZ_TARGET(fuzz_digitiser_input)
UWB_FUZZ_FRAME_MUTATOR
