/* The digitiser client against a scripted digitiser in a child process:
 * stale frames, a sequence that jumps ahead, a wrong record length, a
 * corrupted frame, refused or altered configurations. The fire callback
 * tells the child about each trigger through a pipe. */
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "scratch_support.h"
#include "unity.h"
#include "uwb/digitiser.h"
#include "uwb/frame.h"
#include "uwb/link.h"

#define SAMPLES 64
#define VOLTS_PER_COUNT 0.001f

enum action {
    ANSWER = 0,          /* the frame for this trigger; also every unscripted one (peer is zeroed) */
    STALE_THEN_ANSWER,   /* an old frame first, then this trigger's */
    JUMP_AHEAD,          /* a sequence 5 beyond (the digitiser counted extra triggers) */
    WRONG_LENGTH,        /* one sample short */
    CORRUPT_THEN_ANSWER, /* a frame failing its CRC, then this trigger's frame */
    OTHER_THEN_ANSWER,   /* a frame that is not DATA with this trigger's sequence first */
    BAD_PAYLOAD,         /* a DATA frame whose payload is shorter than its header */
    HANG_UP,             /* the digitiser goes away instead of answering */
};

/* How the scripted digitiser answers ARM. */
enum arm_reply { ARM_ANSWERED = 0, ARM_REFUSED, ARM_IGNORED, ARM_HUNG_UP };

static struct {
    enum action script[8]; /* what the n-th trigger gets */
    int refuse_configure;
    int malformed_configured; /* a CONFIGURED reply too short to hold its fields */
    int noise_before_pong;    /* a reply to another sequence and a DATA frame before PONG */
    enum arm_reply arm;
    uint32_t configured_samples;
} peer;

static char dir[64], endpoint[128];
static int trigger_pipe[2];
static pid_t child = -1;
static struct uwb_link_listener *listener;
static char err[1024];

/* corrupt: one byte in the middle flipped, so the frame fails its CRC. */
static void send_encoded(struct uwb_link *link, uint8_t type, uint32_t seq, const void *payload, size_t len,
                         int corrupt)
{
    static uint8_t buf[UWB_FRAME_HEADER_BYTES + 4096];
    size_t n = uwb_frame_encode(type, seq, payload, len, buf, sizeof buf);
    if (corrupt)
        buf[n / 2] ^= 0xFF;
    char e[256];
    if (!n || uwb_link_write_all(link, buf, n, 2000, e, sizeof e) != UWB_LINK_OK)
        _exit(3);
}

static void send_frame(struct uwb_link *link, uint8_t type, uint32_t seq, const void *payload, size_t len)
{
    send_encoded(link, type, seq, payload, len, 0);
}

/* Codes seq * 100 + i, so the parent can tell which trigger a trace answers. */
static void send_trace(struct uwb_link *link, uint32_t seq, uint32_t samples, int corrupt)
{
    int16_t codes[SAMPLES];
    uint8_t payload[UWB_FRAME_TRACE_HEADER_BYTES + 2 * SAMPLES];
    for (uint32_t i = 0; i < samples; i++)
        codes[i] = (int16_t)(seq * 100 + i);
    size_t plen = uwb_trace_payload_encode(codes, samples, VOLTS_PER_COUNT, payload, sizeof payload);
    send_encoded(link, UWB_FRAME_DATA, seq, payload, plen, corrupt);
}

static void answer_command(struct uwb_link *link, const struct uwb_frame *f, uint32_t *seq)
{
    uint8_t p[UWB_FRAME_CONFIGURE_BYTES];
    switch (f->type) {
    case UWB_FRAME_PING:
        if (peer.noise_before_pong) {
            send_frame(link, UWB_FRAME_PONG, f->sequence + 7, "someone else", 12);
            send_trace(link, 0, SAMPLES, 0);
        }
        send_frame(link, UWB_FRAME_PONG, f->sequence, "scripted\001digitiser", 18);
        break;
    case UWB_FRAME_CONFIGURE:
        if (peer.refuse_configure) {
            uint8_t e[64];
            size_t n = uwb_error_payload_encode(7, "record length not supported", e, sizeof e);
            send_frame(link, UWB_FRAME_ERROR, f->sequence, e, n);
        } else {
            uwb_configure_payload_encode(peer.configured_samples, 1e-11, p);
            send_frame(link, UWB_FRAME_CONFIGURED, f->sequence, p, peer.malformed_configured ? 3 : sizeof p);
        }
        break;
    case UWB_FRAME_ARM:
        *seq = 0;
        if (peer.arm == ARM_REFUSED) {
            uint8_t e[64];
            size_t n = uwb_error_payload_encode(9, "trigger input not wired", e, sizeof e);
            send_frame(link, UWB_FRAME_ERROR, f->sequence, e, n);
        } else if (peer.arm == ARM_HUNG_UP) {
            _exit(0);
        } else if (peer.arm == ARM_ANSWERED) {
            send_frame(link, UWB_FRAME_ARMED, f->sequence, NULL, 0);
        }
        break;
    default: send_frame(link, f->type | 0x80, f->sequence, NULL, 0);
    }
}

static void serve(void)
{
    struct uwb_link *link;
    char e[256];
    if (uwb_link_accept(listener, &link, 10000, e, sizeof e) != UWB_LINK_OK)
        _exit(2);
    struct uwb_frame_decoder dec;
    if (uwb_frame_decoder_init(&dec) != 0)
        _exit(2);
    uint32_t seq = 0;
    int step = 0;
    for (;;) {
        struct pollfd fds[2] = {{.fd = uwb_link_fd(link), .events = POLLIN},
                                {.fd = trigger_pipe[0], .events = POLLIN}};
        if (poll(fds, 2, 10000) <= 0)
            _exit(4);
        if (fds[0].revents) {
            size_t room;
            uint8_t *space = uwb_frame_decoder_space(&dec, &room);
            ssize_t n = uwb_link_read(link, space, room, 0, e, sizeof e);
            if (n < 0)
                _exit(0); /* the parent closed: done */
            uwb_frame_decoder_commit(&dec, (size_t)n);
            struct uwb_frame f;
            int status;
            while ((status = uwb_frame_decoder_next(&dec, &f)) != UWB_FRAME_NEED_MORE)
                if (status == UWB_FRAME_FOUND)
                    answer_command(link, &f, &seq);
        }
        if (fds[1].revents) {
            char byte;
            if (read(trigger_pipe[0], &byte, 1) != 1)
                _exit(0);
            enum action a =
                step < (int)(sizeof peer.script / sizeof peer.script[0]) ? peer.script[step] : ANSWER;
            step++;
            if (a == STALE_THEN_ANSWER && seq > 0)
                send_trace(link, seq - 1, SAMPLES, 0);
            if (a == JUMP_AHEAD)
                seq += 5;
            if (a == CORRUPT_THEN_ANSWER)
                send_trace(link, seq, SAMPLES, 1);
            if (a == OTHER_THEN_ANSWER)
                send_frame(link, UWB_FRAME_PONG, seq, "not data", 8);
            if (a == HANG_UP)
                _exit(0);
            if (a == BAD_PAYLOAD) {
                send_frame(link, UWB_FRAME_DATA, seq, "abc", 3);
                seq++;
                continue;
            }
            send_trace(link, seq, a == WRONG_LENGTH ? SAMPLES - 1 : SAMPLES, 0);
            seq++;
        }
    }
}

static void start_peer(void)
{
    TEST_ASSERT_EQUAL_INT(0, pipe(trigger_pipe));
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, uwb_link_listen(endpoint, &listener, err, sizeof err), err);
    fflush(stdout);
    child = fork();
    TEST_ASSERT_TRUE(child >= 0);
    if (child == 0) {
        close(trigger_pipe[1]);
        serve();
        _exit(0);
    }
    close(trigger_pipe[0]);
}

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "dig");
    snprintf(endpoint, sizeof endpoint, "unix:%s/digitiser", dir);
    memset(&peer, 0, sizeof peer);
    peer.configured_samples = SAMPLES;
    child = -1;
    listener = NULL;
}

void tearDown(void)
{
    if (child > 0) {
        close(trigger_pipe[1]);
        int status;
        kill(child, SIGTERM);
        waitpid(child, &status, 0);
    }
    uwb_link_listener_close(listener);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, scratch_remove_tree(dir), dir);
}

static int fire(void *ctx, char *e, size_t elen)
{
    (void)ctx;
    (void)e;
    (void)elen;
    return write(trigger_pipe[1], "t", 1) == 1 ? 0 : -1;
}

/* Start the scripted digitiser as `peer` says and open the client on it;
 * returns what uwb_digitiser_open says. */
static int start_and_open(int frame_timeout_ms, int frame_retries, struct uwb_digitiser **dig)
{
    start_peer();
    struct uwb_digitiser_config cfg = {.samples = SAMPLES,
                                       .sample_interval_s = 1e-11,
                                       .stack = 1,
                                       .frame_timeout_ms = frame_timeout_ms,
                                       .frame_retries = frame_retries};
    snprintf(cfg.endpoint, sizeof cfg.endpoint, "%s", endpoint);
    int detail;
    return uwb_digitiser_open(&cfg, dig, &detail, err, sizeof err);
}

static struct uwb_digitiser *open_client(void)
{
    struct uwb_digitiser *dig;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_DIGITISER_OK, start_and_open(3000, 2, &dig), err);
    /* it ends up in file headers: a control byte becomes '?' */
    TEST_ASSERT_EQUAL_STRING("scripted?digitiser", uwb_digitiser_identity(dig));
    return dig;
}

/* The trace answers trigger `seq`: code seq * 100 + i at every sample. */
static void acquire_expecting(struct uwb_digitiser *dig, uint32_t seq)
{
    float out[SAMPLES];
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_DIGITISER_OK,
                                  uwb_digitiser_acquire(dig, fire, NULL, out, err, sizeof err), err);
    for (int i = 0; i < SAMPLES; i++)
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, (float)(seq * 100 + (uint32_t)i) * VOLTS_PER_COUNT, out[i]);
}

/* Open a client, take one trace per entry of `seqs` (each answering that
 * trigger), and return the client's counters at the end. */
static struct uwb_digitiser_stats stats_after_traces(const uint32_t *seqs, int n)
{
    struct uwb_digitiser *dig = open_client();
    for (int i = 0; i < n; i++)
        acquire_expecting(dig, seqs[i]);
    struct uwb_digitiser_stats st;
    uwb_digitiser_get_stats(dig, &st);
    uwb_digitiser_close(dig);
    return st;
}

static void test_stale_frames_are_skipped(void)
{
    peer.script[1] = STALE_THEN_ANSWER;
    struct uwb_digitiser_stats st = stats_after_traces((const uint32_t[]){0, 1}, 2);
    TEST_ASSERT_EQUAL_UINT32(1, st.stale);
    TEST_ASSERT_EQUAL_UINT32(0, st.retries);
    TEST_ASSERT_EQUAL_UINT32(2, st.traces);
}

static void test_a_sequence_jump_is_followed(void)
{
    peer.script[0] = JUMP_AHEAD;
    /* the count follows the digitiser's: 5, then 6 */
    struct uwb_digitiser_stats st = stats_after_traces((const uint32_t[]){5, 6}, 2);
    TEST_ASSERT_EQUAL_UINT32(1, st.ahead);
    TEST_ASSERT_EQUAL_UINT32(0, st.stale);
}

static void test_a_wrong_record_length_is_fired_again(void)
{
    peer.script[0] = WRONG_LENGTH;
    struct uwb_digitiser_stats st = stats_after_traces((const uint32_t[]){1}, 1);
    TEST_ASSERT_EQUAL_UINT32(1, st.bad_payloads);
    TEST_ASSERT_EQUAL_UINT32(1, st.retries);
    TEST_ASSERT_EQUAL_UINT32(2, st.fired);
}

/* The corrupt frame costs a retry; the good frame that followed it then
 * answers an earlier trigger and is dropped as stale. */
static void test_a_corrupt_frame_is_fired_again(void)
{
    peer.script[0] = CORRUPT_THEN_ANSWER;
    struct uwb_digitiser_stats st = stats_after_traces((const uint32_t[]){1}, 1);
    TEST_ASSERT_EQUAL_UINT32(1, st.bad_frames);
    TEST_ASSERT_EQUAL_UINT32(1, st.retries);
    TEST_ASSERT_EQUAL_UINT32(1, st.stale);
}

static void test_bad_frames_beyond_the_retries_fail(void)
{
    for (int i = 0; i < 3; i++)
        peer.script[i] = WRONG_LENGTH;
    struct uwb_digitiser *dig = open_client();
    float out[SAMPLES];
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_FRAMES,
                          uwb_digitiser_acquire(dig, fire, NULL, out, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "after 3 triggers"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "63 samples"), err);
    uwb_digitiser_close(dig);
}

static void test_a_refused_configuration_is_reported_with_the_reason(void)
{
    peer.refuse_configure = 1;
    struct uwb_digitiser *dig;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL, start_and_open(1000, 0, &dig));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "refused CONFIGURE"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "record length not supported"), err);
}

static void test_a_different_record_length_in_force_is_refused(void)
{
    peer.configured_samples = 1024;
    struct uwb_digitiser *dig;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL, start_and_open(1000, 0, &dig));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "runs 1024 samples"), err);
}

/* Frames that are not the reply sought are passed over: a reply to
 * another sequence and a DATA frame before PONG, a frame that is not DATA
 * before the trace. */
static void test_frames_that_answer_something_else_are_passed_over(void)
{
    peer.noise_before_pong = 1;
    peer.script[0] = OTHER_THEN_ANSWER;
    struct uwb_digitiser_stats st = stats_after_traces((const uint32_t[]){0}, 1);
    TEST_ASSERT_EQUAL_UINT32(1, st.fired);
    TEST_ASSERT_EQUAL_UINT32(0, st.bad_frames);
}

/* A DATA frame whose payload cannot be a trace costs a retry, counted. */
static void test_a_data_frame_too_short_for_its_header_is_fired_again(void)
{
    peer.script[0] = BAD_PAYLOAD;
    struct uwb_digitiser_stats st = stats_after_traces((const uint32_t[]){1}, 1);
    TEST_ASSERT_EQUAL_UINT32(1, st.bad_payloads);
    TEST_ASSERT_EQUAL_UINT32(1, st.retries);
}

/* A digitiser that goes away mid-scan: with no retries left the error
 * names it and says the link closed. */
static void test_a_digitiser_that_hangs_up_fails_the_trace_by_name(void)
{
    peer.script[0] = HANG_UP;
    struct uwb_digitiser *dig;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_DIGITISER_OK, start_and_open(3000, 0, &dig), err);
    float out[SAMPLES];
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_FRAMES,
                          uwb_digitiser_acquire(dig, fire, NULL, out, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, endpoint), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no good frame after 1 trigger;"), err);
    uwb_digitiser_close(dig);
}

static void test_a_malformed_configured_reply_is_refused(void)
{
    peer.malformed_configured = 1;
    struct uwb_digitiser *dig = (struct uwb_digitiser *)(void *)&peer;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL, start_and_open(1000, 0, &dig));
    TEST_ASSERT_NULL(dig);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "malformed CONFIGURED reply"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, endpoint), err);
}

/* ARM refused, hung up on and never answered: each is its own error,
 * naming the command (and, unanswered, the time waited). */
static void test_arm_refused_hung_up_or_unanswered_is_reported(void)
{
    struct uwb_digitiser *dig;
    peer.arm = ARM_REFUSED;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL, start_and_open(1000, 0, &dig));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "refused ARM: "), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "trigger input not wired"), err);
    tearDown();
    setUp();
    peer.arm = ARM_HUNG_UP;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_LINK, start_and_open(1000, 0, &dig));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "digitiser ARM: "), err);
    tearDown();
    setUp();
    peer.arm = ARM_IGNORED; /* the shortest wait for a command is 5 s */
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL, start_and_open(1000, 0, &dig));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no reply to ARM within 5000 ms"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, endpoint), err);
}

/* A configuration the protocol cannot carry is refused before any link. */
static void test_an_impossible_configuration_is_refused_before_connecting(void)
{
    const struct uwb_digitiser_config good = {.samples = SAMPLES,
                                              .sample_interval_s = 1e-11,
                                              .stack = 1,
                                              .frame_timeout_ms = 100,
                                              .frame_retries = 0};
    struct uwb_digitiser_config bad[5];
    for (int i = 0; i < 5; i++) {
        bad[i] = good;
        snprintf(bad[i].endpoint, sizeof bad[i].endpoint, "%s", endpoint);
    }
    bad[0].samples = 0;
    bad[1].samples = UWB_FRAME_MAX_SAMPLES + 1;
    bad[2].sample_interval_s = NAN;
    bad[3].frame_timeout_ms = 0;
    bad[4].frame_retries = -1;
    for (int i = 0; i < 5; i++) {
        struct uwb_digitiser *dig = (struct uwb_digitiser *)(void *)&peer;
        int detail = -1;
        TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL,
                              uwb_digitiser_open(&bad[i], &dig, &detail, err, sizeof err));
        TEST_ASSERT_NULL(dig);
        TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, detail);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "digitiser config: samples must be 1.."), err);
    }
    uwb_digitiser_close(NULL);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    UNITY_BEGIN();
    RUN_TEST(test_stale_frames_are_skipped);
    RUN_TEST(test_a_sequence_jump_is_followed);
    RUN_TEST(test_a_wrong_record_length_is_fired_again);
    RUN_TEST(test_a_corrupt_frame_is_fired_again);
    RUN_TEST(test_bad_frames_beyond_the_retries_fail);
    RUN_TEST(test_a_refused_configuration_is_reported_with_the_reason);
    RUN_TEST(test_a_different_record_length_in_force_is_refused);
    RUN_TEST(test_frames_that_answer_something_else_are_passed_over);
    RUN_TEST(test_a_data_frame_too_short_for_its_header_is_fired_again);
    RUN_TEST(test_a_digitiser_that_hangs_up_fails_the_trace_by_name);
    RUN_TEST(test_a_malformed_configured_reply_is_refused);
    RUN_TEST(test_arm_refused_hung_up_or_unanswered_is_reported);
    RUN_TEST(test_an_impossible_configuration_is_refused_before_connecting);
    return UNITY_END();
}
