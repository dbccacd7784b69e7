/* Replies to line commands: one JSON object per line, each with a "class"
 * (gpsd style): STATUS, VERDICT, HISTORY, BASELINE, HELP, ERROR. The same
 * text goes to the control socket and to the serial console. Every
 * function returns a malloc'd line without its newline, or NULL when out of
 * memory. */
#ifndef UWB_CONTROL_REPLY_H
#define UWB_CONTROL_REPLY_H

#include <time.h>

#include "control/scan_progress.h"

#include "state/baseline_store.h"

#define UWBD_PROTOCOL_MAJOR 1
#define UWBD_PROTOCOL_MINOR 0

struct uwbd_mqtt_link;
struct uwbd_contact_states;
struct uwbd_state_writes;

struct uwbd_status {
    const char *version;
    const char *state; /* "idle", "scanning", "stopping" */
    long uptime_s;
    double interval_s; /* 0: on request only */
    int has_next_scan;
    long next_scan_in_s;
    int scans_this_run;
    int scan_queued; /* a requested scan waits for the running one */
    int baseline_pending;
    int has_baseline;
    struct uwbd_baseline_info baseline;
    const struct uwb_verdict_record *latest; /* the latest verdict, or NULL */
    const char *state_dir;
    const char *rig;                            /* "ready" or why not */
    const char *console;                        /* endpoint, or NULL when none */
    const char *fault;                          /* a device fault (the baseline failed its check), or NULL */
    const struct uwbd_scan_progress *progress;  /* while scanning, or NULL */
    const char *site_phase, *site_label;        /* site.phase, site.label; "" or NULL: not set */
    const struct uwbd_mqtt_link *mqtt;          /* the MQTT link and queue, or NULL when MQTT is off */
    const char *asset_id;                       /* site.asset_id; "" or NULL: not set */
    const char *modbus_endpoint;                /* modbus.endpoint, or NULL when Modbus is off */
    int modbus_listening;                       /* its server is open */
    const struct uwbd_contact_states *contacts; /* energised (1) or not, or NULL when there are none */
    time_t now;                                 /* for the baseline's age; 0: not given */
    int has_state_dir_free;
    unsigned long long state_dir_free_bytes; /* statvfs: what an unprivileged writer may still use */
    const struct uwbd_state_writes *writes;  /* the state directory refusing writes, or NULL: it takes them */
};

char *uwbd_reply_error(const char *message);
char *uwbd_reply_help(void);
char *uwbd_reply_status(const struct uwbd_status *status);
/* verdict_lines: lines from verdicts.jsonl, oldest first; each VERDICT
 * becomes a summary (scan_id, created, status, reason, displacement), any
 * other line counts with skipped in unreadable_lines. */
char *uwbd_reply_history(char *const *verdict_lines, int count, int requested, int skipped);
char *uwbd_reply_baseline(int pending, int has_current, const struct uwbd_baseline_info *current);
/* The answer to `watch`: what this connection will now be sent. */
char *uwbd_reply_watch(int watch);
/* The answer to `ack`: the contacts energised (1) or not after it, and the
 * latest verdict (NULL: none) they now follow. */
char *uwbd_reply_ack(const struct uwbd_contact_states *st, const struct uwb_verdict_record *latest);
/* The answer to `event`: the scan it asked for started, or queued behind the running one. */
char *uwbd_reply_event(int queued);
/* The answer to `scan` where no one waits for its verdict (MQTT): it started, or queued. */
char *uwbd_reply_scan_requested(int queued);

#endif
