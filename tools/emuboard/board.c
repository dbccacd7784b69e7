/* The emulated board's state: the scene's engine, where the carriage is,
 * what the home switch reads, and the log of answered triggers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emu.h"

/* Enough for long test runs; older entries are dropped beyond it. */
#define LOG_MAX 100000
/* Positions whose noiseless response the engine keeps: every pulse of a
 * stack, and every later scan over the same positions, then only adds its
 * own jitter, drift and noise (64 KiB each at 2,048 samples). A scene
 * change builds a new engine, so nothing stale is kept. */
#define RESPONSES_KEPT 256

static int alloc_buffers(struct emu_board *b, int samples, char *err, size_t errlen)
{
    float *trace = realloc(b->trace, (size_t)samples * sizeof *trace);
    if (trace)
        b->trace = trace;
    int16_t *codes = realloc(b->codes, (size_t)samples * sizeof *codes);
    if (codes)
        b->codes = codes;
    uint8_t *payload = realloc(b->payload, uwb_trace_payload_size((uint32_t)samples));
    if (payload)
        b->payload = payload;
    uint8_t *frame = realloc(b->frame, uwb_frame_size(uwb_trace_payload_size((uint32_t)samples)));
    if (frame)
        b->frame = frame;
    if (!trace || !codes || !payload || !frame) {
        snprintf(err, errlen, "out of memory for %d samples", samples);
        return -1;
    }
    return 0;
}

int emu_board_set_scene(struct emu_board *b, const struct sim_scene *scene, char *err, size_t errlen)
{
    if (scene->samples > UWB_FRAME_MAX_SAMPLES) {
        snprintf(err, errlen, "samples: %d is more than a frame carries (%d)", scene->samples,
                 UWB_FRAME_MAX_SAMPLES);
        return -1;
    }
    if (sim_scene_validate(scene, err, errlen) != 0)
        return -1;
    struct sim_engine *engine;
    if (sim_engine_create(scene, &engine, err, errlen) != 0)
        return -1;
    /* The noise reference costs a pass over the scene's positions: pay it
     * now, not on the first trigger. */
    if (scene->noise && !(sim_engine_peak_echo(engine) > 0)) {
        snprintf(err, errlen,
                 "snr_db: the winding returns nothing inside the record, so noise has no reference");
        sim_engine_free(engine);
        return -1;
    }
    if (sim_engine_cache_responses(engine, RESPONSES_KEPT) != 0) {
        snprintf(err, errlen, "out of memory for %d kept responses", RESPONSES_KEPT);
        sim_engine_free(engine);
        return -1;
    }
    if (alloc_buffers(b, scene->samples, err, errlen) != 0) {
        sim_engine_free(engine);
        return -1;
    }
    sim_engine_free(b->engine);
    b->engine = engine;
    b->scene = *scene;
    return 0;
}

int emu_board_init(struct emu_board *b, const struct sim_scene *scene, uint64_t seed, char *err,
                   size_t errlen)
{
    memset(b, 0, sizeof *b);
    b->steps_per_mm = 100;
    b->home_y_mm = -20;
    sim_acq_init(&b->acq, seed);
    if (uwb_frame_decoder_init(&b->decoder) != 0) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    return emu_board_set_scene(b, scene, err, errlen);
}

void emu_board_free(struct emu_board *b)
{
    emu_digitiser_detach(b);
    uwb_frame_decoder_free(&b->decoder);
    sim_engine_free(b->engine);
    free(b->trace);
    free(b->codes);
    free(b->payload);
    free(b->frame);
    free(b->log);
    memset(b, 0, sizeof *b);
}

double emu_board_y_m(const struct emu_board *b)
{
    return (b->home_y_mm + b->steps / b->steps_per_mm) / 1000.0;
}

int emu_board_home_active(const struct emu_board *b)
{
    if (emu_fault_active(&b->fault[EMU_FAULT_HOME_STUCK]))
        return 1;
    if (emu_fault_active(&b->fault[EMU_FAULT_HOME_NEVER]))
        return 0;
    return b->steps <= 0;
}

void emu_board_log(struct emu_board *b, long sequence, const char *result)
{
    if (b->log_len == LOG_MAX) {
        memmove(b->log, b->log + 1, (LOG_MAX - 1) * sizeof *b->log);
        b->log_len--;
    }
    if (b->log_len == b->log_cap) {
        size_t cap = b->log_cap ? 2 * b->log_cap : 256;
        struct emu_log_entry *log = realloc(b->log, cap * sizeof *log);
        if (!log)
            return;
        b->log = log;
        b->log_cap = cap;
    }
    b->log[b->log_len++] = (struct emu_log_entry){
        .trigger = b->triggers - 1,
        .sequence = sequence,
        .y_m = emu_board_y_m(b),
        .steps = b->steps,
        .result = result,
    };
    if (b->verbose)
        fprintf(stderr, "uwbemu: trigger %lu at y = %.4f m (%ld steps): %s\n", b->triggers - 1,
                emu_board_y_m(b), b->steps, result);
}
