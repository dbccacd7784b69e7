/* The daemon's configuration: one JSON file, every key listed in a table
 * (src/daemon/config_keys.c) with its unit, range and default, so that the
 * loader, `uwbd --config-keys` and board/config.md cannot disagree.
 * Unknown keys, wrong types, out-of-range values and missing required keys
 * are errors that name the key: "FILE: key `x.y`: problem". */
#ifndef UWB_DAEMON_CONFIG_H
#define UWB_DAEMON_CONFIG_H

#include <stdio.h>
#include <stddef.h>

#include "uwb/evaluate.h"
#include "uwb/rig.h"
#include "integrations/site_config.h"

#define UWBD_PATH_MAX 1024
/* sun_path holds 108 bytes including the terminator. */
#define UWBD_SOCKET_PATH_MAX 108
#define UWBD_GROUP_MAX 64
#define UWBD_DEFAULT_CONFIG "/etc/uwbd/uwbd.json"
#define UWBD_DEFAULT_CONTROL_SOCKET "/run/uwbd/control.sock"

/* Modbus (src/integrations/modbus_server.c): off by default. */
struct uwbd_modbus_config {
    int enabled;
    char endpoint[UWB_ENDPOINT_MAX]; /* serial:|unix: RTU, tcp: listening; required when enabled */
    int unit_id;                     /* RTU address, 1-247 */
    double idle_timeout_s;           /* TCP: a master with nothing pending this long is closed */
};

struct uwbd_config {
    struct uwb_rig_config rig;
    struct uwb_evaluate_options evaluate;
    char state_dir[UWBD_PATH_MAX];
    int allow_root;
    double interval_s;                       /* 0: scan only on request */
    int retention_max_scans;                 /* 0: no limit by count */
    double retention_max_age_days;           /* 0: no limit by age */
    char console_endpoint[UWB_ENDPOINT_MAX]; /* "": no console */
    char control_socket[UWBD_SOCKET_PATH_MAX];
    char control_mode_text[8]; /* as written, e.g. "0660" */
    unsigned control_mode;
    char control_group[UWBD_GROUP_MAX]; /* "": the daemon's own group */
    int control_max_clients_per_user;   /* control slots one ordinary user may hold */
    double control_scan_min_interval_s; /* an ordinary user's scans at most once per this; 0: no limit */
    int baseline_scans;                 /* `baseline set` without N averages this many scans */
    double reacquire_budget_s;          /* time a cycle may spend acquiring again to be decisive; 0: never */
    char site_phase[8];                 /* site.phase: the phase as the site names it ("B", "L2"); "": none */
    char site_label[64];                /* site.label: free text for people; "": none */
    struct uwbd_site_config site; /* the site's integrations: asset id, alarm contacts, event input, ... */
    struct uwbd_modbus_config modbus;
};

/* A command-line override: KEY=VALUE, VALUE as JSON (a bare word is taken
 * as a string); KEY may also be a section, replaced by an object. Applied
 * to the file's JSON before validation, so it is checked exactly like the
 * file. */
struct uwbd_override {
    const char *key;
    const char *value;
};

/* Parse config text. `name` prefixes messages. Returns 0, or -1 with err
 * holding "NAME: key `x.y`: problem" (or "NAME: line L column C: ..."). */
int uwbd_config_parse(const char *text, size_t len, const char *name, const struct uwbd_override *overrides,
                      size_t n_overrides, struct uwbd_config *cfg, char *err, size_t errlen);
/* Read and parse a file; an unreadable file is an error too. */
/* What only the running system can say (e.g. that control.group exists):
 * --check-config asks it after loading; "name" prefixes the message. */
int uwbd_config_check_system(const struct uwbd_config *cfg, const char *name, char *err, size_t errlen);

int uwbd_config_load(const char *path, const struct uwbd_override *overrides, size_t n_overrides,
                     struct uwbd_config *cfg, char *err, size_t errlen);

/* Every key as a Markdown table (key, type, unit, default, meaning). */
void uwbd_config_print_keys_markdown(FILE *out);
/* Number of keys in the table and the i-th key's dotted path (for tests). */
size_t uwbd_config_key_count(void);
const char *uwbd_config_key_path(size_t i);

#endif
