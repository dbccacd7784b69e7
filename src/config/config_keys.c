/* Every configuration key: where it lands, its unit, range and default, and
 * what it means. The loader applies defaults and checks ranges from here and
 * `uwbd --config-keys` prints it, so the documentation is this table. */
#include "config/config_keys.h"

#include <float.h>
#include <limits.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "config/config.h"
#include "rig/rig_keys.h"
#include "util/value_range.h"

/* The table macros take member names and designated-initializer values: a member name
 * cannot be parenthesized, and every value lands alone after "= ", so none needs it. */
// NOLINTBEGIN(bugprone-macro-parentheses)
#define AT(member) offsetof(struct uwbd_config, member)
#define SIZE(member) sizeof(((struct uwbd_config *)0)->member)

#define STRING(p, m, def, text) \
    { \
        .path = p, .type = KEY_STRING, .offset = AT(m), .size = SIZE(m), .scale = 1, .default_text = def, \
        .unit = "", .doc = text \
    }
#define REQUIRED_STRING(p, m, text) \
    { \
        .path = p, .type = KEY_STRING, .offset = AT(m), .size = SIZE(m), .scale = 1, .required = 1, \
        .unit = "", .doc = text \
    }
/* A number in [lo, hi] (ABOVE: in (lo, hi]), written in `u`, stored times `sc`. */
#define NUMBER(p, m, u, sc, lo, hi, def, text) \
    { \
        .path = p, .type = KEY_NUMBER, .offset = AT(m), .scale = sc, .min = lo, .max = hi, \
        .default_number = def, .unit = u, .doc = text \
    }
#define NUMBER_ABOVE(p, m, u, sc, lo, hi, def, text) \
    { \
        .path = p, .type = KEY_NUMBER, .offset = AT(m), .scale = sc, .min = lo, .max = hi, \
        .min_exclusive = 1, .default_number = def, .unit = u, .doc = text \
    }
#define INTEGER(p, m, u, lo, hi, def, text) \
    { \
        .path = p, .type = KEY_INT, .offset = AT(m), .scale = 1, .min = lo, .max = hi, \
        .default_number = def, .unit = u, .doc = text \
    }
#define BOOLEAN(p, m, def, text) \
    { \
        .path = p, .type = KEY_BOOL, .offset = AT(m), .scale = 1, .max = 1, .default_number = def, \
        .unit = "", .doc = text \
    }
/* Required with the libgpiod backend (config.c checks); the emulated board ignores them. */
#define GPIO_LINE(p, line, text) \
    { \
        .path = p, .type = KEY_GPIO_LINE, .offset = AT(rig.gpio), .size = line, .scale = 1, .max = INT_MAX, \
        .unit = "", .doc = text \
    }
/* A line of the site's own GPIO handle (alarm contacts, event input). */
#define SITE_LINE(p, line, when, text) \
    { \
        .path = p, .type = KEY_GPIO_LINE, .offset = AT(site.io), .size = line, .scale = 1, .max = INT_MAX, \
        .default_text = when, .unit = "", .doc = text \
    }
/* A key of the rig's: its name, unit, range and default are the rig's spec
 * (src/rig/rig_keys.h); here where it lands and what it means. */
#define RIG_KEY(t, m, spec, text) \
    { \
        .type = t, .offset = AT(rig.m), spec, .doc = text \
    }
#define RIG_OPTIONAL_PAIR(m, flag, spec, text) \
    { \
        .type = KEY_PAIR, .offset = AT(rig.m), .flag_offset = AT(rig.flag), spec, .doc = text \
    }
// NOLINTEND(bugprone-macro-parentheses)

static const char *const gpio_backends[] = {"libgpiod", "emulated", NULL};

const struct config_key uwbd_config_keys[] = {
    STRING("site.asset_id", site.asset_id, "",
           "the transformer's name in the utility's asset register (letters, digits, . _ - ; at most 63); in "
           "every verdict as asset_id when set; required once any integration (contacts, event, prometheus, "
           "mqtt) is on"),
    STRING("state_dir", state_dir, "/var/lib/uwbd",
           "directory of the archive, verdicts.jsonl, latest.json and the baseline (board/state-dir.md); "
           "created if missing; a relative path is taken from the daemon's working directory; a directory of "
           "its "
           "own: / and system directories (/etc, /home, /usr, /var, /var/lib, ...) are refused"),
    BOOLEAN("allow_root", allow_root, 0,
            "let the daemon run as root; without it uwbd refuses to start as root (exit 77)"),

    NUMBER("schedule.interval_s", interval_s, "s", 1, 0, 366.0 * 86400, 86400,
           "time between scheduled scans, from the start of one to the start of the next; "
           "0 = scan only on request"),

    INTEGER("retention.max_scans", retention_max_scans, "", 0, INT_MAX, 1000,
            "keep at most this many scans in the archive, and as many lines in verdicts.jsonl, deleting "
            "the oldest first; 0 = no limit. Baselines are never deleted"),
    NUMBER("retention.max_age_days", retention_max_age_days, "days", 1, 0, 36500, 0,
           "delete archived scans and verdicts.jsonl lines older than this, only while the system clock is "
           "synchronised (NTP), and never the newest scan; 0 = no limit"),

    STRING("control.socket", control_socket, UWBD_DEFAULT_CONTROL_SOCKET,
           "path of the local control socket that `uwbd ctl` talks to (at most 107 bytes)"),
    {.path = "control.mode",
     .type = KEY_FILE_MODE,
     .offset = AT(control_mode),
     .scale = 1,
     .default_text = "0660",
     .unit = "",
     .doc = "permissions of the control socket, octal; the owner "
            "needs read and write, others may have nothing"},
    STRING("control.group", control_group, "",
           "group owning the control socket (engineers in it may use `uwbd ctl`); "
           "empty = the daemon's own group"),
    INTEGER("control.max_clients_per_user", control_max_clients_per_user, "", 1, 15, 8,
            "control connections one user other than root and the daemon's user may hold at once (of the 15 "
            "such users share); one more is refused, or takes the place of that user's own idle one"),
    NUMBER("control.scan_min_interval_s", control_scan_min_interval_s, "s", 1, 0, 86400, 60,
           "a user other than root and the daemon's user may start a scan (`scan`, `event`) at most once per "
           "this long; sooner is refused, naming when the next is allowed; 0 = no limit"),

    STRING("console.endpoint", console_endpoint, "",
           "serial console for line commands: serial:/dev/ttyS0?baud=115200, or tcp:HOST:PORT / "
           "unix:PATH, which uwbd connects to; empty = no console"),

    {.path = "gpio.backend",
     .type = KEY_CHOICE,
     .offset = AT(rig.gpio.backend),
     .size = SIZE(rig.gpio.backend),
     .scale = 1,
     .required = 1,
     .unit = "",
     .choices = gpio_backends,
     .doc = "libgpiod (a /dev/gpiochip*) or emulated (the emulated board's GPIO socket)"},
    STRING("gpio.chip", rig.gpio.chip, "",
           "libgpiod: the chip's label, name (gpiochip0) or path; required with that backend"),
    STRING("gpio.endpoint", rig.gpio.endpoint, "",
           "emulated: unix:PATH or tcp:HOST:PORT of the emulated board; required with that backend"),
    GPIO_LINE(
        "gpio.lines.trigger", UWB_LINE_TRIGGER,
        "pulser trigger output: line offset (integer) or line name (string); libgpiod only, required there"),
    GPIO_LINE("gpio.lines.step", UWB_LINE_STEP, "stepper driver STEP output: offset or name"),
    GPIO_LINE("gpio.lines.dir", UWB_LINE_DIR, "stepper driver DIR output (high = up): offset or name"),
    GPIO_LINE("gpio.lines.enable", UWB_LINE_ENABLE,
              "stepper driver ENABLE output (high = energised): offset or name"),
    GPIO_LINE("gpio.lines.home", UWB_LINE_HOME, "home switch input: offset or name"),
    RIG_KEY(KEY_BOOL, gpio.home_active_low, UWB_RIG_HOME_ACTIVE_LOW,
            "the home switch pulls its line low when the carriage is home"),
    RIG_KEY(KEY_BOOL, gpio.home_pull_up, UWB_RIG_HOME_PULL_UP,
            "request the internal pull-up bias on the home line"),
    RIG_KEY(KEY_BOOL, gpio.enable_active_low, UWB_RIG_ENABLE_ACTIVE_LOW,
            "the stepper driver's EN input energises the motor when low (A4988, DRV8825, TMC2209); "
            "uwbd still keeps the motor off between scans"),

    STRING("gpio.site_endpoint", site.io.endpoint, "",
           "emulated: unix:PATH or tcp:HOST:PORT of the emulated board's site lines (uwbemu --site-io: alarm "
           "contacts and event input); required there when contacts.enabled or event.enabled"),

    REQUIRED_STRING("digitiser.endpoint", rig.digitiser.endpoint,
                    "the digitiser link: serial:/dev/uwb-digitiser?baud=921600, tcp:HOST:PORT or unix:PATH"),
    RIG_KEY(KEY_INT, digitiser.samples, UWB_RIG_SAMPLES, "record length: samples per trace"),
    RIG_KEY(KEY_NUMBER, digitiser.sample_interval_s, UWB_RIG_SAMPLE_INTERVAL_PS, "time between samples"),
    RIG_KEY(KEY_NUMBER, digitiser.t0_s, UWB_RIG_T0_PS,
            "time of sample 0 after the pulse leaves the transmitter (negative: before it), "
            "from commissioning"),
    RIG_KEY(KEY_INT, digitiser.stack, UWB_RIG_STACK, "pulses fired and averaged per antenna position"),
    RIG_KEY(KEY_INT, digitiser.frame_timeout_ms, UWB_RIG_FRAME_TIMEOUT_MS,
            "wait this long for a frame after a trigger"),
    RIG_KEY(KEY_INT, digitiser.frame_retries, UWB_RIG_FRAME_RETRIES,
            "a bad or missing frame is retried (with a fresh trigger) this many times per pulse"),

    RIG_KEY(KEY_NUMBER, carriage.steps_per_mm, UWB_RIG_STEPS_PER_MM,
            "microsteps per millimetre of carriage travel; at least 1, as a coarser step could not "
            "place the antennas to the millimetre"),
    RIG_KEY(KEY_NUMBER, carriage.max_rate_hz, UWB_RIG_MAX_RATE_HZ, "top step rate"),
    RIG_KEY(KEY_NUMBER, carriage.accel_hz_per_s, UWB_RIG_ACCEL_HZ_PER_S,
            "linear ramp of the step rate at the start and end of a move"),
    RIG_KEY(KEY_NUMBER, carriage.travel_mm, UWB_RIG_TRAVEL_MM,
            "usable travel above the home switch; every position must lie inside it"),
    RIG_KEY(KEY_NUMBER, carriage.park_mm, UWB_RIG_PARK_MM,
            "where the carriage rests between scans, above home"),
    RIG_KEY(KEY_NUMBER, carriage.backlash_mm, UWB_RIG_BACKLASH_MM,
            "every position is approached from below, after going this much lower first"),
    RIG_KEY(KEY_NUMBER, carriage.settle_ms, UWB_RIG_SETTLE_MS, "wait after a move before firing"),
    RIG_KEY(KEY_NUMBER, carriage.home_timeout_s, UWB_RIG_HOME_TIMEOUT_S,
            "give up homing (an error verdict) when the switch is not seen within this"),
    RIG_KEY(KEY_NUMBER, carriage.home_debounce_ms, UWB_RIG_HOME_DEBOUNCE_MS,
            "the home switch must read the same for this long"),
    RIG_KEY(KEY_NUMBER, carriage.home_offset_mm, UWB_RIG_HOME_OFFSET_MM,
            "height of the home switch's position in scan coordinates (y of the antenna reference "
            "point when the carriage is home), measured at installation"),
    RIG_KEY(KEY_NUMBER, carriage.home_rate_hz, UWB_RIG_HOME_RATE_HZ,
            "step rate while seeking the home switch (the final approach runs at a quarter of it); "
            "at most max_rate_hz"),
    RIG_KEY(KEY_NUMBER, carriage.home_backoff_mm, UWB_RIG_HOME_BACKOFF_MM,
            "after homing the carriage backs off this far; a switch still closed then is stuck"),

    RIG_KEY(KEY_INT, positions, UWB_RIG_POSITIONS, "antenna positions per scan (K)"),
    RIG_KEY(KEY_NUMBER, first_position_mm, UWB_RIG_FIRST_POSITION_MM,
            "height of position 0 in scan coordinates"),
    RIG_KEY(KEY_NUMBER, step_mm, UWB_RIG_STEP_MM,
            "spacing between positions; at least 1 mm, and (positions - 1) x step at most 5000 mm (what a "
            "scan file may hold)"),
    RIG_KEY(KEY_NUMBER, trigger_pulse_us, UWB_RIG_TRIGGER_PULSE_US, "how long the trigger line is held high"),
    RIG_KEY(KEY_NUMBER, time_scale, UWB_RIG_TIME_SCALE,
            "multiplies every wait of a scan (step timing, settle, debounce, trigger pulse): 1 on real "
            "hardware; below 1 runs scans of the emulated board faster, 0 = no waiting"),

    RIG_KEY(KEY_PAIR, tx_m, UWB_RIG_TX_MM,
            "transmit antenna phase centre [dy, dz] from the carriage's reference point"),
    RIG_KEY(KEY_PAIR, rx_m, UWB_RIG_RX_MM,
            "receive antenna phase centre [dy, dz] from the carriage's reference point"),
    RIG_KEY(KEY_NUMBER, eps_r, UWB_RIG_EPS_R,
            "relative permittivity between antennas and winding (transformer oil about 2.2)"),
    RIG_OPTIONAL_PAIR(target_z_m, has_target_z, UWB_RIG_TARGET_Z_MM,
                      "[near, far] range where the drawings put the winding's face; it is searched only "
                      "there. Absent: searched from 150 to 1600 mm"),

    {.path = "analysis.winding_span_mm",
     .type = KEY_PAIR,
     .offset = AT(evaluate.analysis.winding_span_m),
     .flag_offset = AT(evaluate.analysis.has_winding_span),
     .scale = 1e-3,
     .min = -1e5,
     .max = 1e5,
     .unit = "mm",
     .doc = "[lower, upper] height where the transformer's drawings put the winding's ends, in the scans' "
            "own y (commissioning): the baseline's face must have both ends within a quarter of that height "
            "of them, else it is another reflector's (a clamp plate level with the face) and the baseline is "
            "not established. Absent: not checked"},
    NUMBER_ABOVE("analysis.watch_mm", evaluate.compare.thresholds.watch_m, "mm", 1e-3, 0, 1000, 2,
                 "a displacement (up or down) from this size on gives the status watch"),
    NUMBER_ABOVE("analysis.alarm_mm", evaluate.compare.thresholds.alarm_m, "mm", 1e-3, 0, 1000, 5,
                 "a displacement (up or down) from this size on gives the status alarm (not below watch_mm)"),
    NUMBER_ABOVE("analysis.max_uncertainty_mm", evaluate.compare.max_uncertainty_m, "mm", 1e-3, 0, 1000, 1,
                 "above this 1-sigma uncertainty a displacement is given only when its whole 95 % interval "
                 "lies in one "
                 "status band (ok, watch, alarm); otherwise the verdict is inconclusive"),
    NUMBER_ABOVE("radial.watch_mm", evaluate.compare.radial_thresholds.watch_m, "mm", 1e-3, 0, 1000, 2,
                 "a radial change of the winding's face (toward the antenna or away) from this size on gives "
                 "the status watch"),
    NUMBER_ABOVE("radial.alarm_mm", evaluate.compare.radial_thresholds.alarm_m, "mm", 1e-3, 0, 1000, 5,
                 "a radial change from this size on gives the status alarm (not below radial.watch_mm)"),
    {.path = "analysis.migration",
     .type = KEY_MIGRATION,
     .offset = AT(evaluate.analysis.migration),
     .scale = 1,
     .default_text = "fixed",
     .unit = "",
     .doc = "migration arithmetic: fixed (int16 samples, Q15 weights) or float"},
    NUMBER("analysis.time_zero_offset_ps", evaluate.analysis.time_zero_offset_s, "ps", 1e-12, -1e6, 1e6, 0,
           "calibration added to each scan's t0"),
    NUMBER_ABOVE("analysis.edge_fraction", evaluate.analysis.edge_fraction, "", 1, 0.05, 0.95, 0.5,
                 "an edge is where the face profile crosses this fraction of its peak"),
    NUMBER_ABOVE("analysis.display_half_range_mm", evaluate.analysis.display_half_range_m, "mm", 1e-3, 10,
                 2000, 250,
                 "the migrated image (PNG) shows ranges this far either side of the winding's face"),

    NUMBER("direct_coupling.window_end_ns", evaluate.direct_coupling.window_end_s, "ns", 1e-9, -1e3, 1e3, 2,
           "the direct Tx-to-Rx arrival is looked for from the first sample up to this time after "
           "the pulse leaves the transmitter"),
    NUMBER_ABOVE("direct_coupling.tolerance_ps", evaluate.direct_coupling.tolerance_s, "ps", 1e-12, 0, 1e6,
                 20,
                 "a scan whose direct-coupling arrival moved more than this from the baseline's is "
                 "inconclusive (cable or antenna changed?) instead of compared"),

    INTEGER(
        "baseline.scans", baseline_scans, "", 1, 16, 4,
        "`baseline set` without N commissions the baseline from this many scans acquired back to back and "
        "averaged; their spread is recorded as the baseline's repeatability and enters every verdict's "
        "uncertainty"),
    NUMBER(
        "analysis.reacquire_budget_s", reacquire_budget_s, "s", 1, 0, 86400, 600,
        "when a scan's uncertainty is over analysis.max_uncertainty_mm and more pulses would bring it under "
        "(its noise part falls as 1/sqrt(pulses)), acquire again and average, for at most this long per "
        "scan cycle, before the verdict says inconclusive; 0 = never"),
    STRING(
        "site.phase", site_phase, "",
        "the phase (or winding) this unit watches, as the site names it (e.g. B, L2, HV-B; at most 7 bytes); "
        "shown in `status` and the trend image"),
    STRING(
        "site.label", site_label, "",
        "a free label for people (e.g. Hillside GT2, north window; at most 63 bytes); shown in `status` and "
        "the trend image"),

    BOOLEAN("contacts.enabled", site.contacts_enabled, 0,
            "drive the alarm contacts (uwbd-contacts(7)): watch and alarm energised by those verdicts, "
            "fault energised while the appliance is healthy (fail-safe)"),
    STRING(
        "contacts.test_group", contacts_test_group, "",
        "a group whose members may run `contacts test` (the RTU sees every contact rise and fall); root and "
        "the daemon's own user always may; empty = only they"),
    NUMBER("contacts.test_min_interval_s", contacts_test_min_interval_s, "s", 1, 0, 86400, 60,
           "at most one `contacts test` per this long, counted from the start of the last, whoever asks; "
           "sooner is refused, naming when the next is allowed; 0 = no limit"),
    SITE_LINE("contacts.watch.line", UWB_LINE_WATCH, "required with libgpiod when contacts.enabled",
              "the watch contact's output: line offset (integer) or line name (string)"),
    BOOLEAN("contacts.watch.active_low", site.io.active_low[UWB_LINE_WATCH], 0,
            "the watch relay is energised by a low pin (libgpiod)"),
    BOOLEAN("contacts.watch.latch", site.watch_latch, 1,
            "the watch contact stays energised after a verdict that no longer calls for it, until `ack`"),
    SITE_LINE("contacts.alarm.line", UWB_LINE_ALARM, "required with libgpiod when contacts.enabled",
              "the alarm contact's output: offset or name"),
    BOOLEAN("contacts.alarm.active_low", site.io.active_low[UWB_LINE_ALARM], 0,
            "the alarm relay is energised by a low pin (libgpiod)"),
    BOOLEAN("contacts.alarm.latch", site.alarm_latch, 1,
            "the alarm contact stays energised after a verdict that no longer calls for it, until `ack`"),
    SITE_LINE("contacts.fault.line", UWB_LINE_FAULT, "required with libgpiod when contacts.enabled",
              "the device-fault contact's output: offset or name; energised while healthy, so a dead board, "
              "a stopped daemon or an `error` verdict opens it"),
    BOOLEAN("contacts.fault.active_low", site.io.active_low[UWB_LINE_FAULT], 0,
            "the fault relay is energised by a low pin (libgpiod)"),

    BOOLEAN(
        "event.enabled", site.event_enabled, 0,
        "scan after an event: the event input (a protection relay's trip contact) starts a scan as soon as "
        "the running one ends; the verdict says \"trigger\": \"event\""),
    SITE_LINE("event.line", UWB_LINE_EVENT, "required with libgpiod when event.enabled",
              "the event input: offset or name"),
    BOOLEAN("event.active_low", site.io.active_low[UWB_LINE_EVENT], 0,
            "the event input is active when its pin is low (a contact to ground on a pulled-up input)"),
    NUMBER("event.debounce_ms", site.event_debounce_s, "ms", 1e-3, 0, 10000, 50,
           "the input must read active for this long to count (contact bounce, induced spikes)"),
    NUMBER("event.min_interval_s", site.event_min_interval_s, "s", 1, 0, 366.0 * 86400, 600,
           "at most one event scan per this long: a relay that chatters or recloses does not keep the "
           "carriage running; events inside it are logged and dropped"),
    NUMBER_ABOVE("event.poll_ms", site.event_poll_s, "ms", 1e-3, 0, 10000, 10,
                 "how often the event input is read; at most event.debounce_ms where that is above 0"),

    BOOLEAN("prometheus.enabled", site.prometheus_enabled, 0,
            "write the Prometheus textfile (uwbd-prometheus(7)) after every verdict"),
    STRING("prometheus.textfile", site.prometheus_textfile, "",
           "where: a NAME.prom in node_exporter's --collector.textfile.directory (Debian: "
           "/var/lib/prometheus/node-exporter/uwbd.prom); replaced atomically; required when "
           "prometheus.enabled"),

    BOOLEAN("mqtt.enabled", site.mqtt_enabled, 0,
            "publish verdicts and status to an MQTT broker (uwbd-mqtt(7)); needs mqtt.endpoint and "
            "site.asset_id"),
    STRING("mqtt.endpoint", site.mqtt_endpoint, "",
           "the broker: tcp:HOST:PORT (8883 with TLS); required when mqtt.enabled"),
    STRING("mqtt.username", site.mqtt_username, "", "user name at the broker; empty = anonymous"),
    STRING("mqtt.password_file", site.mqtt_password_file, "",
           "file whose first line is the password, readable by the service only (mode 0600 or 0400); "
           "required with mqtt.username"),
    STRING("mqtt.ca_file", site.mqtt_ca_file, "",
           "CA certificate (PEM) the broker's is checked against; set = TLS, empty = plain TCP"),
    STRING("mqtt.cert_file", site.mqtt_cert_file, "", "client certificate (PEM) for TLS, with mqtt.key_file"),
    STRING("mqtt.key_file", site.mqtt_key_file, "",
           "the client certificate's key (PEM), readable by the service only"),
    STRING(
        "mqtt.topic_prefix", site.mqtt_topic_prefix, "uwbd",
        "topics are PREFIX/ASSET_ID/verdict (each verdict, retained), PREFIX/ASSET_ID/status (online or "
        "offline), PREFIX/ASSET_ID/health (the appliance's health, retained) and, with mqtt.commands, "
        "PREFIX/ASSET_ID/cmd (commands taken) and PREFIX/ASSET_ID/reply (their answers); see uwbd-mqtt(7)"),
    INTEGER("mqtt.queue_max", site.mqtt_queue_max, "", 1, 100000, 1000,
            "verdicts kept in STATE_DIR/mqtt-queue while the broker is away, sent in order when it is back; "
            "beyond this the oldest is dropped (logged)"),
    NUMBER_ABOVE("mqtt.reconnect_max_s", site.mqtt_reconnect_max_s, "s", 1, 0, 3600, 60,
                 "reconnecting backs off from 1 s, doubling, up to this"),
    BOOLEAN(
        "mqtt.commands", site.mqtt_commands, 0,
        "take the commands scan, event, ack and baseline set [N|force] from PREFIX/ASSET_ID/cmd (one a "
        "message) and answer each on PREFIX/ASSET_ID/reply; the broker's ACL decides who may publish there"),
    BOOLEAN(
        "modbus.enabled", modbus.enabled, 0,
        "serve the latest verdict, health and contact states as Modbus registers and take `ack` and `event` "
        "as coils (uwbd-modbus(7) has the map); off: nothing is opened"),
    STRING("modbus.endpoint", modbus.endpoint, "",
           "serial:/dev/ttyX?baud=N[&parity=P][&stopbits=S]: Modbus RTU on that line (RS-485; 8 data bits, "
           "parity P none, even or odd, S 1 or 2 stop bits; without them no parity and 1 stop bit, as "
           "before, though the Modbus serial line standard's default, and many RTUs', is parity=even); "
           "unix:PATH: RTU over a local socket uwbd connects to (the tests); tcp:HOST:PORT: Modbus TCP, "
           "listening on that address (the substation LAN's, e.g. tcp:192.0.2.10:502; a port under 1024 "
           "needs CAP_NET_BIND_SERVICE); "
           "required when modbus.enabled"),
    INTEGER("modbus.unit_id", modbus.unit_id, "", 1, 247, 1,
            "the RTU unit (slave) address this appliance answers on the bus; Modbus TCP answers any"),
    NUMBER_ABOVE("modbus.idle_timeout_s", modbus.idle_timeout_s, "s", 1, 0, 86400, 60,
                 "Modbus TCP: a master that sends nothing for this long is disconnected (it may connect "
                 "again); of the 4 connections at once, a fifth master takes the slot of the one idle "
                 "longest (2 s or more), and keepalive finds a vanished master within 2 minutes"),
    BOOLEAN("csv.enabled", csv.enabled, 0,
            "keep the verdict history as a CSV file for spreadsheets (the columns of `uwbd ctl --csv "
            "history`): a row per verdict, rotated with the archive (the newest retention.max_scans rows), "
            "replaced atomically"),
    STRING("csv.path", csv.path, "", "the CSV file; empty = STATE_DIR/verdicts.csv"),
};

const size_t uwbd_config_key_total = sizeof uwbd_config_keys / sizeof uwbd_config_keys[0];

const struct config_key *uwbd_config_key_find(const char *path)
{
    for (size_t i = 0; i < uwbd_config_key_total; i++)
        if (strcmp(uwbd_config_keys[i].path, path) == 0)
            return &uwbd_config_keys[i];
    return NULL;
}

static struct uwb_value_range key_range(const struct config_key *k)
{
    return (struct uwb_value_range){k->min, k->max, k->min_exclusive, k->unit, k->below_min_why};
}

void uwbd_config_key_describe_range(const struct config_key *k, char *buf, size_t n)
{
    const struct uwb_value_range range = key_range(k);
    uwb_value_range_describe(&range, buf, n);
}

int uwbd_config_key_check_range(const struct config_key *k, double written, char *problem, size_t n)
{
    const struct uwb_value_range range = key_range(k);
    return uwb_value_range_check(&range, written, problem, n);
}

int uwbd_config_key_in_rig(const struct config_key *k, size_t *offset, size_t *flag_offset)
{
    size_t rig = offsetof(struct uwbd_config, rig);
    /* A GPIO line row has no offset: its `size` is the line's index. */
    if (k->type == KEY_GPIO_LINE || k->offset < rig || k->offset >= rig + sizeof(struct uwb_rig_config))
        return 0;
    *offset = k->offset - rig;
    *flag_offset = k->flag_offset ? k->flag_offset - rig : 0;
    return 1;
}
