/* What the configuration file says, section by section: struct uwbd_config
 * holds the rig's, the evaluation's, the site's and the daemon's own
 * settings. Here, below its loader (config/config_load.h), the daemon and
 * the modules that read their section, so none of them leans on the
 * daemon; every key is listed in config/config_keys.c. */
#ifndef UWB_CONFIG_CONFIG_H
#define UWB_CONFIG_CONFIG_H

#include <stddef.h>

#include "uwb/evaluate.h"
#include "uwb/rig.h"
#include "config/site_config.h"

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

/* The CSV verdict history (src/daemon/output_csv.c): off by default. */
struct uwbd_csv_config {
    int enabled;
    char path[UWBD_PATH_MAX]; /* "": STATE_DIR/verdicts.csv */
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
    char contacts_test_group[UWBD_GROUP_MAX]; /* may run `contacts test` besides root and the daemon's user */
    double contacts_test_min_interval_s;      /* at most one `contacts test` per this; 0: no limit */
    int baseline_scans;                       /* `baseline set` without N averages this many scans */
    double reacquire_budget_s;    /* time a cycle may spend acquiring again to be decisive; 0: never */
    char site_phase[8];           /* site.phase: the phase as the site names it ("B", "L2"); "": none */
    char site_label[64];          /* site.label: free text for people; "": none */
    struct uwbd_site_config site; /* the site's integrations: asset id, alarm contacts, event input, ... */
    struct uwbd_modbus_config modbus;
    struct uwbd_csv_config csv;
};

#endif
