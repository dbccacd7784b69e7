/* uwbemu, the emulated board: pulser, digitiser and carriage in one
 * process. The daemon's emulated-GPIO backend moves the carriage and fires
 * the pulser over one endpoint (board/emulated-gpio.md); the digitiser
 * answers over another (board/digitiser-protocol.md) with traces the
 * simulator computes where the carriage really is; a control endpoint
 * changes the scene and injects faults. */
#ifndef EMUBOARD_EMU_H
#define EMUBOARD_EMU_H

#include <stddef.h>
#include <stdint.h>

#include "uwb/frame.h"
#include "uwb/gpio.h"
#include "uwb/link.h"
#include "uwbsim/uwbsim.h"

#define EMU_VERSION "1.0"
#define EMU_GPIO_PROTOCOL "uwb-gpio/1"
/* The carriage's hard stop, this far below the home switch (mm). */
#define EMU_END_STOP_BELOW_HOME_MM 3.0
/* Its hard stop at the top, this far above the home switch (mm): the
 * emulated rig's travel (board/emulated/uwbd.json, carriage.travel_mm 650)
 * and 20 mm of clearance, so a daemon that steps too far stalls there. */
#define EMU_END_STOP_ABOVE_HOME_MM 670.0

enum emu_fault_id {
    EMU_FAULT_CRC,        /* corrupt one payload byte after the CRC is computed */
    EMU_FAULT_TRUNCATE,   /* send only the first half of the frame */
    EMU_FAULT_DROP,       /* count the trigger, send nothing */
    EMU_FAULT_SILENT,     /* ignore triggers altogether */
    EMU_FAULT_DISCONNECT, /* close the digitiser connection instead of answering */
    EMU_FAULT_HOME_NEVER, /* home switch never closes */
    EMU_FAULT_HOME_STUCK, /* home switch always closed */
    EMU_FAULT_LOSE_STEPS, /* an upward STEP pulse that strikes does not move the carriage (a slipping belt) */
    EMU_FAULT_COUNT
};

enum emu_fault_mode { EMU_FAULT_OFF, EMU_FAULT_ON, EMU_FAULT_EVERY, EMU_FAULT_NEXT };

struct emu_fault {
    enum emu_fault_mode mode;
    unsigned n;         /* EVERY: period; NEXT: how many are left */
    unsigned long seen; /* events counted for EVERY */
    unsigned long hits; /* times it struck */
};

/* One answered (or not) trigger, for the control `log`. */
struct emu_log_entry {
    unsigned long trigger; /* rising edges of TRIGGER since start */
    long sequence;         /* DATA sequence, -1 when no frame was due */
    double y_m;            /* carriage y the trace was (or would have been) computed for */
    long steps;            /* carriage microsteps above home */
    const char *result;    /* "sent", "crc", "truncate", "drop", "silent", "disconnect", "unarmed", "error" */
};

struct emu_board {
    /* the scene and its engine */
    struct sim_scene scene;
    struct sim_engine *engine;
    struct sim_acq acq;
    float *trace; /* scene.samples */
    int16_t *codes;
    uint8_t *payload; /* one DATA payload */
    uint8_t *frame;   /* the frame carrying it */

    /* the carriage, as the board's mechanics see it */
    double steps_per_mm;
    double home_y_mm; /* y of the home switch, scene coordinates, mm */
    int invert_dir;   /* wiring fault: DIR 1 moves down */
    long steps;       /* microsteps above home (0 = switch closes) */
    int line[UWB_LINE_COUNT];
    unsigned long steps_counted, steps_while_disabled;
    unsigned long steps_stalled; /* counted, but against an end stop */
    unsigned long steps_lost;    /* counted, but lost to the lose-steps fault */

    /* the digitiser */
    struct uwb_link *digitiser;
    struct uwb_frame_decoder decoder;
    int armed;
    uint32_t sequence;
    unsigned long triggers, frames_sent, frames_failed;
    double last_trace_y_m;

    struct emu_fault fault[EMU_FAULT_COUNT];
    struct emu_log_entry *log;
    size_t log_len, log_cap;
    int verbose;
    int quit;
};

/* board.c: scene and engine */
int emu_board_init(struct emu_board *b, const struct sim_scene *scene, uint64_t seed, char *err,
                   size_t errlen);
void emu_board_free(struct emu_board *b);
/* Build the engine for a changed scene; the old one stays on failure. */
int emu_board_set_scene(struct emu_board *b, const struct sim_scene *scene, char *err, size_t errlen);
double emu_board_y_m(const struct emu_board *b);
int emu_board_home_active(const struct emu_board *b);
void emu_board_log(struct emu_board *b, long sequence, const char *result);

/* gpio_server.c: one line of the GPIO protocol; writes the reply (if
 * any, with its '\n') into reply, else reply[0] = 0. */
void emu_gpio_line(struct emu_board *b, const char *line, char *reply, size_t replylen);
/* A GPIO peer went away: the outputs among `lines` (UWB_GPIO_LINE_BIT
 * mask) fall low, as released lines and unpowered relays do. */
void emu_gpio_released(struct emu_board *b, unsigned lines);
/* The site's input (`event`, the protection relay's trip contact) as the
 * control endpoint drives it; -1 for another line or value. */
int emu_gpio_set_input(struct emu_board *b, const char *name, int value);
/* The site's lines (alarm contacts, event input): what --site-io serves. */
#define EMU_SITE_LINES \
    (UWB_GPIO_LINE_BIT(UWB_LINE_WATCH) | UWB_GPIO_LINE_BIT(UWB_LINE_ALARM) | \
     UWB_GPIO_LINE_BIT(UWB_LINE_FAULT) | UWB_GPIO_LINE_BIT(UWB_LINE_EVENT))

/* digitiser_server.c */
void emu_digitiser_attach(struct emu_board *b, struct uwb_link *link);
void emu_digitiser_detach(struct emu_board *b);
/* Bytes arrived on the digitiser link: answer the commands in them.
 * Returns -1 if the link failed (it is detached then). */
int emu_digitiser_readable(struct emu_board *b);
/* A rising edge on TRIGGER. */
void emu_digitiser_trigger(struct emu_board *b);

/* faults.c */
const char *emu_fault_name(enum emu_fault_id id);
int emu_fault_find(const char *name);
/* Whether the fault strikes this time (advances EVERY/NEXT counters). */
int emu_fault_strikes(struct emu_fault *fault);
int emu_fault_active(const struct emu_fault *fault);
void emu_fault_describe(const struct emu_fault *fault, char *buf, size_t buflen);

/* control.c: one control command; the reply is one JSON line (malloc'd). */
char *emu_control_command(struct emu_board *b, const char *line);

#endif
