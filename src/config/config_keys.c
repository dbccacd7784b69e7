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
#include "uwb/frame.h"
#include "uwb/scan.h"

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
#define REQUIRED_NUMBER(p, m, u, sc, lo, hi, text) \
    { \
        .path = p, .type = KEY_NUMBER, .offset = AT(m), .scale = sc, .min = lo, .max = hi, .required = 1, \
        .unit = u, .doc = text \
    }
#define REQUIRED_NUMBER_ABOVE(p, m, u, sc, lo, hi, text) \
    { \
        .path = p, .type = KEY_NUMBER, .offset = AT(m), .scale = sc, .min = lo, .max = hi, \
        .min_exclusive = 1, .required = 1, .unit = u, .doc = text \
    }
#define INTEGER(p, m, u, lo, hi, def, text) \
    { \
        .path = p, .type = KEY_INT, .offset = AT(m), .scale = 1, .min = lo, .max = hi, \
        .default_number = def, .unit = u, .doc = text \
    }
#define REQUIRED_INTEGER(p, m, lo, hi, text) \
    { \
        .path = p, .type = KEY_INT, .offset = AT(m), .scale = 1, .min = lo, .max = hi, .required = 1, \
        .unit = "", .doc = text \
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
#define REQUIRED_PAIR(p, m, u, sc, lo, hi, text) \
    { \
        .path = p, .type = KEY_PAIR, .offset = AT(m), .scale = sc, .min = lo, .max = hi, .required = 1, \
        .unit = u, .doc = text \
    }
#define OPTIONAL_PAIR(p, m, flag, u, sc, lo, hi, text) \
    { \
        .path = p, .type = KEY_PAIR, .offset = AT(m), .flag_offset = AT(flag), .scale = sc, .min = lo, \
        .max = hi, .unit = u, .doc = text \
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
    BOOLEAN("gpio.home_active_low", rig.gpio.home_active_low, 1,
            "the home switch pulls its line low when the carriage is home"),
    BOOLEAN("gpio.home_pull_up", rig.gpio.home_pull_up, 1,
            "request the internal pull-up bias on the home line"),
    BOOLEAN("gpio.enable_active_low", rig.gpio.enable_active_low, 1,
            "the stepper driver's EN input energises the motor when low (A4988, DRV8825, TMC2209); "
            "uwbd still keeps the motor off between scans"),

    STRING("gpio.site_endpoint", site.io.endpoint, "",
           "emulated: unix:PATH or tcp:HOST:PORT of the emulated board's site lines (uwbemu --site-io: alarm "
           "contacts and event input); required there when contacts.enabled or event.enabled"),

    REQUIRED_STRING("digitiser.endpoint", rig.digitiser.endpoint,
                    "the digitiser link: serial:/dev/uwb-digitiser?baud=921600, tcp:HOST:PORT or unix:PATH"),
    REQUIRED_INTEGER("digitiser.samples", rig.digitiser.samples, 16, UWB_FRAME_MAX_SAMPLES,
                     "record length: samples per trace"),
    REQUIRED_NUMBER_ABOVE("digitiser.sample_interval_ps", rig.digitiser.sample_interval_s, "ps", 1e-12, 0,
                          1e6, "time between samples"),
    NUMBER("digitiser.t0_ps", rig.digitiser.t0_s, "ps", 1e-12, -1e6, 1e6, 0,
           "time of sample 0 after the pulse leaves the transmitter (negative: before it), "
           "from commissioning"),
    INTEGER("digitiser.stack", rig.digitiser.stack, "", 1, 65536, UWB_DEFAULT_STACK,
            "pulses fired and averaged per antenna position"),
    INTEGER("digitiser.frame_timeout_ms", rig.digitiser.frame_timeout_ms, "ms", 1, 600000, 1000,
            "wait this long for a frame after a trigger"),
    INTEGER("digitiser.frame_retries", rig.digitiser.frame_retries, "", 0, 100, 3,
            "a bad or missing frame is retried (with a fresh trigger) this many times per pulse"),

    REQUIRED_NUMBER("carriage.steps_per_mm", rig.carriage.steps_per_mm, "steps/mm", 1, 1, 1e6,
                    "microsteps per millimetre of carriage travel; at least 1, as a coarser step could not "
                    "place the antennas to the millimetre"),
    /* At most 1e5 Hz: the STEP pulse (UWB_STEP_PULSE_S, 5 us) and the gap after it fit one period. */
    NUMBER_ABOVE("carriage.max_rate_hz", rig.carriage.max_rate_hz, "Hz", 1, 0, 1e5, 4000, "top step rate"),
    NUMBER_ABOVE("carriage.accel_hz_per_s", rig.carriage.accel_hz_per_s, "Hz/s", 1, 0, 1e9, 8000,
                 "linear ramp of the step rate at the start and end of a move"),
    REQUIRED_NUMBER_ABOVE("carriage.travel_mm", rig.carriage.travel_mm, "mm", 1, 0, 1e5,
                          "usable travel above the home switch; every position must lie inside it"),
    NUMBER("carriage.park_mm", rig.carriage.park_mm, "mm", 1, 0, 1e5, 5,
           "where the carriage rests between scans, above home"),
    NUMBER("carriage.backlash_mm", rig.carriage.backlash_mm, "mm", 1, 0, 100, 0.5,
           "every position is approached from below, after going this much lower first"),
    NUMBER("carriage.settle_ms", rig.carriage.settle_ms, "ms", 1, 0, 60000, 50,
           "wait after a move before firing"),
    NUMBER_ABOVE("carriage.home_timeout_s", rig.carriage.home_timeout_s, "s", 1, 0, 3600, 60,
                 "give up homing (an error verdict) when the switch is not seen within this"),
    NUMBER("carriage.home_debounce_ms", rig.carriage.home_debounce_ms, "ms", 1, 0, 1000, 5,
           "the home switch must read the same for this long"),
    REQUIRED_NUMBER("carriage.home_offset_mm", rig.carriage.home_offset_mm, "mm", 1, -1e5, 1e5,
                    "height of the home switch's position in scan coordinates (y of the antenna reference "
                    "point when the carriage is home), measured at installation"),
    NUMBER_ABOVE("carriage.home_rate_hz", rig.carriage.home_rate_hz, "Hz", 1, 0, 1e5, 1500,
                 "step rate while seeking the home switch (the final approach runs at a quarter of it); "
                 "at most max_rate_hz"),
    NUMBER_ABOVE("carriage.home_backoff_mm", rig.carriage.home_backoff_mm, "mm", 1, 0, 1e5, 5,
                 "after homing the carriage backs off this far; a switch still closed then is stuck"),

    REQUIRED_INTEGER("scan.positions", rig.positions, 2, UWBSCAN_MAX_POSITIONS,
                     "antenna positions per scan (K)"),
    REQUIRED_NUMBER("scan.first_position_mm", rig.first_position_mm, "mm", 1, -1e5, 1e5,
                    "height of position 0 in scan coordinates"),
    {.path = "scan.step_mm",
     .type = KEY_NUMBER,
     .offset = AT(rig.step_mm),
     .scale = 1,
     .min = UWBSCAN_MIN_STEP_M * 1e3,
     .max = UWBSCAN_MAX_TRAVEL_M * 1e3,
     .required = 1,
     .unit = "mm",
     .below_min_why = "under the smallest step a scan file may hold (1 mm, uwb/scan.h)",
     .doc = "spacing between positions; at least 1 mm, and (positions - 1) x step at most 5000 mm (what a "
            "scan file may hold)"},
    NUMBER_ABOVE("scan.trigger_pulse_us", rig.trigger_pulse_us, "us", 1, 0, 1e6, 10,
                 "how long the trigger line is held high"),
    NUMBER("scan.time_scale", rig.time_scale, "", 1, 0, 100, 1,
           "multiplies every wait of a scan (step timing, settle, debounce, trigger pulse): 1 on real "
           "hardware; below 1 runs scans of the emulated board faster, 0 = no waiting"),

    REQUIRED_PAIR("geometry.tx_mm", rig.tx_m, "mm", 1e-3, -1e4, 1e4,
                  "transmit antenna phase centre [dy, dz] from the carriage's reference point"),
    REQUIRED_PAIR("geometry.rx_mm", rig.rx_m, "mm", 1e-3, -1e4, 1e4,
                  "receive antenna phase centre [dy, dz] from the carriage's reference point"),
    REQUIRED_NUMBER("geometry.eps_r", rig.eps_r, "", 1, 1, 100,
                    "relative permittivity between antennas and winding (transformer oil about 2.2)"),
    OPTIONAL_PAIR("geometry.target_z_mm", rig.target_z_m, rig.has_target_z, "mm", 1e-3, 0, 1e5,
                  "[near, far] range where the drawings put the winding's face; it is searched only "
                  "there. Absent: searched from 150 to 1600 mm"),

    NUMBER_ABOVE("analysis.watch_mm", evaluate.compare.thresholds.watch_m, "mm", 1e-3, 0, 1000, 2,
                 "a displacement (up or down) from this size on gives the status watch"),
    NUMBER_ABOVE("analysis.alarm_mm", evaluate.compare.thresholds.alarm_m, "mm", 1e-3, 0, 1000, 5,
                 "a displacement (up or down) from this size on gives the status alarm (not below watch_mm)"),
    NUMBER_ABOVE("analysis.max_uncertainty_mm", evaluate.compare.max_uncertainty_m, "mm", 1e-3, 0, 1000, 1,
                 "above this 1-sigma uncertainty of the displacement the verdict is inconclusive"),
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
            "drive the alarm contacts (README: Alarm contacts): watch and alarm energised by those verdicts, "
            "fault energised while the appliance is healthy (fail-safe)"),
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
            "write the Prometheus textfile (README: Prometheus textfile) after every verdict"),
    STRING("prometheus.textfile", site.prometheus_textfile, "",
           "where: a NAME.prom in node_exporter's --collector.textfile.directory (Debian: "
           "/var/lib/prometheus/node-exporter/uwbd.prom); replaced atomically; required when "
           "prometheus.enabled"),

    BOOLEAN("mqtt.enabled", site.mqtt_enabled, 0,
            "publish verdicts and status to an MQTT broker (README: MQTT); needs mqtt.endpoint and "
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
    STRING("mqtt.topic_prefix", site.mqtt_topic_prefix, "uwbd",
           "topics are PREFIX/ASSET_ID/verdict and PREFIX/ASSET_ID/status"),
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
        "as coils (README \"Modbus\" has the map); off: nothing is opened"),
    STRING("modbus.endpoint", modbus.endpoint, "",
           "serial:/dev/ttyX?baud=N: Modbus RTU on that line (RS-485; 8 data bits, no parity, 1 stop bit); "
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
};

const size_t uwbd_config_key_total = sizeof uwbd_config_keys / sizeof uwbd_config_keys[0];

const struct config_key *uwbd_config_key_find(const char *path)
{
    for (size_t i = 0; i < uwbd_config_key_total; i++)
        if (strcmp(uwbd_config_keys[i].path, path) == 0)
            return &uwbd_config_keys[i];
    return NULL;
}

void uwbd_config_key_describe_range(const struct config_key *k, char *buf, size_t n)
{
    snprintf(buf, n, "%s%.10g, %.10g]%s%s", k->min_exclusive ? "(" : "[", k->min, k->max,
             k->unit[0] ? " " : "", k->unit);
}

int uwbd_config_key_check_range(const struct config_key *k, double written, char *problem, size_t n)
{
    int low = k->min_exclusive ? !(written > k->min) : !(written >= k->min);
    if (!low && written <= k->max)
        return 0;
    char range[96];
    uwbd_config_key_describe_range(k, range, sizeof range);
    if (low && k->below_min_why)
        snprintf(problem, n, "%g is out of range %s: %s", written, range, k->below_min_why);
    else
        snprintf(problem, n, "%g is out of range %s", written, range);
    return -1;
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
