/* The daemon's main loop and its life: start-up checks in the order an
 * installer fixes them (config, user, state directory, control socket,
 * hardware), then poll() until SIGTERM/SIGINT, then a safe shutdown. */
#include "daemon/daemon.h"

#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/signalfd.h>
#include <sys/stat.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "daemon_internal.h"
#include "control/exit_codes.h"
#include "daemon/outputs.h"
#include "util/log.h"
#include "daemon/service_notify.h"
#include "state/state_open.h"
#include "daemon/test_hang.h"
#include "state/verdict_log.h"
#include "uwb/monotonic.h"
#include "uwb/utc_time.h"
#include "uwb/verdict_json.h"

static void load_baseline_info(struct daemon *d)
{
    char why[512];
    struct uwb_scan scan = {0};
    /* The same check as before every scan: a baseline already missing or
     * damaged at start is a device fault from the start. */
    int rc = uwbd_baseline_watch(&d->store, d->cfg.evaluate.direct_coupling.window_end_s, NULL, &scan,
                                 &d->baseline, why, sizeof why);
    uwb_scan_free(&scan);
    d->has_baseline = rc == UWBD_BASELINE_LOADED;
    if (rc == UWBD_BASELINE_FAULT) {
        snprintf(d->fault, sizeof d->fault, "%s", why);
        uwbd_log(UWBD_LOG_WARNING,
                 "device fault: %s; every scan is an error until `baseline set` re-commissions "
                 "(the damaged files are kept) or the file is restored",
                 why);
    } else if (rc == UWBD_BASELINE_NONE) {
        uwbd_log(UWBD_LOG_NOTICE, "no baseline yet: send `baseline set`, then `scan`, to commission");
    }
}

/* The latest verdict's line at start (uwbd_latest_line_at_start), so
 * `verdict` still answers when latest.json was lost. */
static void load_latest_line(struct daemon *d)
{
    char note[1024];
    d->latest_verdict = uwbd_latest_line_at_start(&d->store, note, sizeof note);
    if (note[0])
        uwbd_log(UWBD_LOG_WARNING, "%s", note);
}

/* The latest verdict's record, read from its line once at start for all
 * that read it (the schedule, the site, Modbus, `status`). */
static void read_latest_record(struct daemon *d)
{
    char err[512];
    free(d->latest);
    d->latest = malloc(sizeof *d->latest);
    if (d->latest && uwb_record_from_json(d->latest_verdict, d->latest, err, sizeof err) == 0)
        return;
    uwbd_log(UWBD_LOG_WARNING,
             "the latest verdict is not read back (%s): it counts as none until the next scan",
             d->latest ? err : "out of memory");
    free(d->latest);
    d->latest = NULL;
}

/* The latest verdict at start, as a line and as a record. */
static void load_latest_verdict(struct daemon *d)
{
    load_latest_line(d);
    if (d->latest_verdict)
        read_latest_record(d);
}

static void set_rig_source(struct uwbd_config *cfg)
{
    char host[64] = "";
    gethostname(host, sizeof host - 1);
    snprintf(cfg->rig.source, sizeof cfg->rig.source, "uwbd %s%s%s", UWBD_VERSION, host[0] ? " on " : "",
             host);
    snprintf(cfg->rig.asset_id, sizeof cfg->rig.asset_id, "%s", cfg->site.asset_id);
}

static void reload(struct daemon *d)
{
    d->reload_pending = 0;
    struct uwbd_config next;
    char err[1024];
    if (uwbd_config_load(d->options->config_path, d->options->overrides, d->options->n_overrides, &next, err,
                         sizeof err) != 0) {
        uwbd_log(UWBD_LOG_ERR, "reload refused, the running configuration stays: %s", err);
        return;
    }
    set_rig_source(&next);
    /* These are fixed at start: the sandbox and the socket's owner depend on them. */
    if (strcmp(next.state_dir, d->cfg.state_dir) != 0 ||
        strcmp(next.control_socket, d->cfg.control_socket) != 0 || next.control_mode != d->cfg.control_mode ||
        strcmp(next.control_group, d->cfg.control_group) != 0 || next.allow_root != d->cfg.allow_root)
        uwbd_log(UWBD_LOG_WARNING, "reload: state_dir, control.* and allow_root change only with a restart");
    snprintf(next.state_dir, sizeof next.state_dir, "%s", d->cfg.state_dir);
    snprintf(next.control_socket, sizeof next.control_socket, "%s", d->cfg.control_socket);
    snprintf(next.control_mode_text, sizeof next.control_mode_text, "%s", d->cfg.control_mode_text);
    snprintf(next.control_group, sizeof next.control_group, "%s", d->cfg.control_group);
    next.control_mode = d->cfg.control_mode;
    next.allow_root = d->cfg.allow_root;

    /* Byte comparisons on purpose: a member list would miss a field added
     * later. Both sides are exact byte images of a configuration that
     * apply_defaults() zeroed (padding included) before filling, as they
     * are copied with memcpy below, never by assignment. */
    // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): padding zeroed, see above
    int rig_changed = memcmp(&next.rig, &d->cfg.rig, sizeof next.rig) != 0;
    int console_changed = strcmp(next.console_endpoint, d->cfg.console_endpoint) != 0;
    static struct uwbd_config previous; /* static: a configuration is large */
    memcpy(&previous, &d->cfg, sizeof previous);
    memcpy(&d->cfg, &next, sizeof d->cfg);
    if (rig_changed) {
        if (d->rig)
            uwb_rig_close(d->rig);
        d->rig = NULL;
        int detail = 0;
        if (uwbd_rig_open_logged(d, &detail, err, sizeof err) != UWB_RIG_OK) {
            /* A reload is whole or not at all: the log never says both that
             * the new rig cannot be reached and that the reload happened. */
            memcpy(&d->cfg, &previous, sizeof d->cfg);
            char old_err[512];
            if (uwbd_rig_open_logged(d, &detail, old_err, sizeof old_err) != UWB_RIG_OK)
                uwbd_log(UWBD_LOG_WARNING, "rig: %s (tried again at the next scan)", old_err);
            uwbd_log(UWBD_LOG_ERR, "reload refused, the running configuration stays: the new rig: %s", err);
            return;
        }
    }
    if (console_changed) {
        uwbd_peer_close(&d->console);
        struct itimerspec off = {0};
        timerfd_settime(d->console_retry_fd, 0, &off, NULL);
        uwbd_console_open(d);
    }
    uwbd_outputs_reload(&d->port, &previous); /* each output by its own rule (site.*, modbus.*) */
    uwbd_schedule_arm(d, &d->last_cycle_start);
    uwbd_log(UWBD_LOG_NOTICE, "configuration reloaded from %s%s%s", d->options->config_path,
             rig_changed ? " (rig reopened)" : "", console_changed ? " (console reopened)" : "");
}

static void handle_signals(struct daemon *d)
{
    struct signalfd_siginfo si;
    while (read(d->signal_fd, &si, sizeof si) == sizeof si) {
        if (si.ssi_signo == SIGHUP) {
            d->reload_pending = 1;
            if (!d->scanning)
                reload(d);
            else
                uwbd_log(UWBD_LOG_INFO, "SIGHUP: the configuration is reloaded when the running scan ends");
            continue;
        }
        if (d->stopping)
            continue;
        d->stopping = 1;
        if (d->scanning) {
            uwbd_log(UWBD_LOG_NOTICE, "%s: stopping the running scan safely, then exiting",
                     si.ssi_signo == SIGTERM ? "SIGTERM" : "SIGINT");
            uwbd_worker_request_stop(d);
        } else {
            uwbd_log(UWBD_LOG_NOTICE, "%s: exiting", si.ssi_signo == SIGTERM ? "SIGTERM" : "SIGINT");
        }
    }
}

static void cycle_finished(struct daemon *d)
{
    enum uwbd_collected collected = uwbd_worker_collect(d);
    if (collected == UWBD_COLLECTED_STOPPED)
        uwbd_peers_send_verdict(d, d->job.cycle, NULL,
                                "the scan was stopped (the daemon is shutting down); nothing recorded");
    if (collected == UWBD_COLLECTED_CYCLE) {
        const char *json = d->job.result.verdict_json;
        /* the one place the outputs hear of a verdict; the peers after them */
        uwbd_outputs_verdict(&d->port, json, uwb_monotonic_s() - d->job.started_s);
        uwbd_peers_send_verdict(d, d->job.cycle, json, "out of memory for the verdict");
        uwbd_cycle_result_free(&d->job.result);
    }
    if (d->scanning)
        return;
    uwbd_report_status(d);
    if (d->reload_pending)
        reload(d);
    if (d->stopping) {
        uwbd_peers_send_verdict(d, d->cycles_started + 1, NULL,
                                "the daemon is stopping; the queued scan will not run");
        return;
    }
    if (d->scan_queued) {
        d->scan_queued = 0;
        uwbd_peers_request_scan(d, TRIGGER_NONE);
    } else {
        uwbd_schedule_arm(d, &d->last_cycle_start);
    }
}

static void drain(int fd)
{
    uint64_t count;
    if (read(fd, &count, sizeof count) < 0) {
        /* nothing to do: the timer will fire again */
    }
}

/* How long a healthy scan worker may go without a sign of life (a rig
 * message: at least one a position): homing at its slowest, one position
 * with every frame retried to its timeout, and the analysis and writes
 * after the last position. UWBD_TEST_SCAN_STALL_S (tests only) shortens it. */
#define ANALYSIS_ALLOWANCE_S 120.0
static double worker_stall_limit_s(const struct uwbd_config *cfg)
{
    const char *test = getenv("UWBD_TEST_SCAN_STALL_S");
    if (test) {
        char *end;
        double test_s = strtod(test, &end);
        if (end != test && *end == '\0' && test_s > 0)
            return test_s;
    }
    const struct uwb_rig_config *r = &cfg->rig;
    double position_s =
        r->digitiser.stack * (r->digitiser.frame_retries + 1.0) * r->digitiser.frame_timeout_ms / 1e3 +
        r->carriage.settle_ms / 1e3 + 60.0;
    return r->carriage.home_timeout_s + position_s + ANALYSIS_ALLOWANCE_S;
}

/* A watchdog tick: ping systemd if the main loop (here) and the scan
 * worker, when one runs, are alive; otherwise stay silent so that systemd
 * restarts the daemon after WatchdogSec. */
static void watchdog_tick(struct daemon *d)
{
    drain(d->watchdog_fd);
    double silent_s = uwb_monotonic_s() - (double)atomic_load(&d->worker_beat_ms) / 1000.0;
    double limit_s = worker_stall_limit_s(&d->cfg);
    if (d->scanning && silent_s > limit_s) {
        if (!d->watchdog_withheld)
            uwbd_log(UWBD_LOG_ERR,
                     "the scan worker has been silent for %.0f s (limit %.0f s): no more watchdog "
                     "pings, so systemd restarts uwbd",
                     silent_s, limit_s);
        d->watchdog_withheld = 1;
        return;
    }
    d->watchdog_withheld = 0;
    uwbd_service_notify("WATCHDOG=1");
}

static void watchdog_start(struct daemon *d)
{
    long ping_ms = uwbd_service_watchdog_ping_ms();
    if (ping_ms <= 0)
        return;
    d->watchdog_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
    if (d->watchdog_fd < 0) {
        uwbd_log(UWBD_LOG_ERR, "watchdog: timerfd: %s; systemd will not be pinged", strerror(errno));
        return;
    }
    struct timespec every = {.tv_sec = ping_ms / 1000, .tv_nsec = (ping_ms % 1000) * 1000000L};
    struct itimerspec its = {.it_value = every, .it_interval = every};
    timerfd_settime(d->watchdog_fd, 0, &its, NULL);
    uwbd_log(UWBD_LOG_INFO,
             "systemd watchdog: a ping every %ld ms while the main loop and scan worker are alive", ping_ms);
}

static void on_signal(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    handle_signals(ctx);
}

static void on_lock_watch(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    uwbd_lock_watch_check(ctx);
}

static void on_done(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    cycle_finished(ctx);
}

static void on_schedule(void *ctx, int fd, short revents)
{
    (void)revents;
    struct daemon *d = ctx;
    drain(fd);
    d->has_next_scan = 0;
    if (!d->stopping && !d->scanning) {
        uwbd_log(UWBD_LOG_INFO, "scheduled scan");
        uwbd_peers_request_scan(d, TRIGGER_SCHEDULE);
    }
}

static void on_console_retry(void *ctx, int fd, short revents)
{
    (void)revents;
    drain(fd);
    uwbd_console_open(ctx);
}

static void on_watchdog(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    watchdog_tick(ctx);
}

static void on_progress(void *ctx, int fd, short revents)
{
    (void)revents;
    drain(fd);
    uwbd_peers_send_progress(ctx);
}

/* The daemon's own sources, then the outputs': the order they are served in a round. */
static int register_sources(struct daemon *d)
{
    struct uwbd_event_loop *loop = &d->events;
    uwbd_event_loop_init(loop);
    const struct {
        int fd;
        uwbd_event_fn fn;
    } own[] = {
        {d->signal_fd, on_signal},     {d->lock_watch_fd, on_lock_watch},       {d->done_fd, on_done},
        {d->schedule_fd, on_schedule}, {d->console_retry_fd, on_console_retry}, {d->watchdog_fd, on_watchdog},
        {d->progress_fd, on_progress},
    };
    for (size_t i = 0; i < sizeof own / sizeof own[0]; i++)
        if (uwbd_event_loop_add(loop, own[i].fd, POLLIN, own[i].fn, d) < 0)
            return -1;
    return uwbd_outputs_watch(&d->port, loop) != 0 || uwbd_peers_watch(d, loop) != 0 ? -1 : 0;
}

static void loop(struct daemon *d)
{
    if (register_sources(d) != 0) {
        uwbd_log(UWBD_LOG_ERR, "the event loop is full (%d entries); stopping", UWBD_EVENT_LOOP_MAX);
        return;
    }
    while (!(d->stopping && !d->scanning)) {
        if (uwbd_event_loop_once(&d->events, -1) >= 0 || errno == EINTR)
            continue;
        uwbd_log(UWBD_LOG_ERR, "poll: %s; stopping", strerror(errno));
        d->stopping = 1;
        uwbd_worker_request_stop(d);
    }
}

static int setup_event_fds(struct daemon *d, char *err, size_t errlen)
{
    sigset_t mask;
    sigemptyset(&mask);
    sigaddset(&mask, SIGTERM);
    sigaddset(&mask, SIGINT);
    sigaddset(&mask, SIGHUP);
    sigaddset(&mask, SIGUSR1); /* only the scan thread takes it */
    /* Blocked before any thread exists, so every thread inherits the mask. */
    if (pthread_sigmask(SIG_BLOCK, &mask, NULL) != 0) {
        snprintf(err, errlen, "cannot block signals");
        return -1;
    }
    sigdelset(&mask, SIGUSR1);
    uwbd_worker_install_stop_handler();
    signal(SIGPIPE, SIG_IGN);
    d->signal_fd = signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
    d->schedule_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
    d->console_retry_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
    d->done_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    d->progress_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (d->signal_fd < 0 || d->schedule_fd < 0 || d->console_retry_fd < 0 || d->done_fd < 0 ||
        d->progress_fd < 0) {
        snprintf(err, errlen, "signalfd/timerfd/eventfd: %s", strerror(errno));
        return -1;
    }
    return 0;
}

static void close_fd(int *fd)
{
    if (*fd >= 0)
        close(*fd);
    *fd = -1;
}

static void teardown(struct daemon *d)
{
    uwbd_outputs_close(&d->port); /* the site's first: contacts de-energised, the fault contact opens */
    uwbd_peers_close_all(d);
    if (d->rig) {
        uwb_rig_close(d->rig); /* outputs low: pulser idle, motor disabled */
        d->rig = NULL;
    }
    close_fd(&d->signal_fd);
    close_fd(&d->schedule_fd);
    close_fd(&d->console_retry_fd);
    close_fd(&d->done_fd);
    close_fd(&d->progress_fd);
    close_fd(&d->watchdog_fd);
    close_fd(&d->lock_watch_fd);
    close_fd(&d->lock_fd);
    free(d->latest_verdict);
    d->latest_verdict = NULL;
    free(d->latest);
    d->latest = NULL;
}

/* The outermost directory of `path` that does not exist yet (what mkdir -p
 * would create first), or "" when the path exists. A start that fails
 * removes what it made there, so that trying the emulated sample by hand
 * leaves no run/state behind in the working directory. */
static void first_missing_directory(const char *path, char *out, size_t n)
{
    out[0] = '\0';
    char walk[UWBD_PATH_MAX];
    if (snprintf(walk, sizeof walk, "%s", path) >= (int)sizeof walk)
        return;
    struct stat st;
    while (walk[0] && stat(walk, &st) != 0 && errno == ENOENT) {
        snprintf(out, n, "%s", walk);
        char *slash = strrchr(walk, '/');
        if (!slash || slash == walk)
            break;
        *slash = '\0';
    }
}

/* Undo a failed start's fresh state directory: only the empty skeleton
 * uwbd_store_open and the lock made; rmdir leaves anything else alone. */
static void remove_fresh_state_dir(const struct daemon *d, const char *created)
{
    static const char *const inner[] = {"baseline/history", "baseline", "archive"};
    char path[UWBD_PATH_MAX + 32];
    if (uwbd_path_join(path, sizeof path, d->cfg.state_dir, "uwbd.lock") == 0)
        unlink(path);
    for (size_t i = 0; i < sizeof inner / sizeof inner[0]; i++)
        if (uwbd_path_join(path, sizeof path, d->cfg.state_dir, inner[i]) == 0)
            rmdir(path);
    snprintf(path, sizeof path, "%s", d->cfg.state_dir);
    size_t stop = strlen(created);
    while (strlen(path) >= stop && rmdir(path) == 0) {
        char *slash = strrchr(path, '/');
        if (!slash)
            break;
        *slash = '\0';
    }
}

/* The emulated board is a separate program; say how to start it. */
static void hint_emulated_board(const struct daemon *d, int rc)
{
    if (strcmp(d->cfg.rig.gpio.backend, "emulated") != 0 ||
        (rc != UWB_RIG_ERR_GPIO && rc != UWB_RIG_ERR_LINK))
        return;
    char cwd[UWBD_PATH_MAX] = "";
    if (!getcwd(cwd, sizeof cwd))
        snprintf(cwd, sizeof cwd, "the working directory");
    uwbd_log(UWBD_LOG_ERR,
             "the emulated board (uwbemu) is not running there: start it first, in %s: "
             "uwbemu --gpio %s --digitiser %s &  (build/uwbemu in the source tree; see uwbemu --help)",
             cwd, d->cfg.rig.gpio.endpoint, d->cfg.rig.digitiser.endpoint);
}

/* The port the output modules see the daemon through (output_module.h). */
static const struct uwb_verdict_record *port_latest(void *daemon)
{
    const struct daemon *d = daemon;
    return d->latest;
}

static int port_stopping(void *daemon)
{
    const struct daemon *d = daemon;
    return d->stopping;
}

static void port_request_event_scan(void *daemon)
{
    uwbd_peers_request_scan(daemon, TRIGGER_EVENT);
}

static int port_acknowledge(void *daemon, char *err, size_t errlen)
{
    struct daemon *d = daemon;
    return uwbd_outputs_acknowledge(&d->port, err, errlen);
}

static char *port_site_command(void *daemon, const char *text)
{
    return uwbd_site_command(daemon, text);
}

static void port_modbus_status(void *daemon, struct uwbd_modbus_status *out)
{
    const struct daemon *d = daemon;
    *out = (struct uwbd_modbus_status){
        .scan_count = (unsigned long)d->scans_this_run,
        .scanning = d->scanning,
        .device_fault = d->fault[0] != '\0',
        /* d->rig belongs to the worker while a scan runs: only read it when none does. */
        .rig_down = !d->scanning && !d->rig,
        .has_baseline = d->has_baseline,
    };
}

static void port_fill(struct daemon *d)
{
    d->port = (struct uwbd_daemon_port){
        .daemon = d,
        .cfg = &d->cfg,
        .store = &d->store,
        .events = &d->events,
        .latest = port_latest,
        .stopping = port_stopping,
        .request_event_scan = port_request_event_scan,
        .acknowledge = port_acknowledge,
        .site_command = port_site_command,
        .modbus_status = port_modbus_status,
    };
}

static int start(struct daemon *d, char *created_dir, size_t created_len)
{
    char err[1024];
    if (uwbd_config_load(d->options->config_path, d->options->overrides, d->options->n_overrides, &d->cfg,
                         err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_ERR, "%s", err);
        return UWBD_EXIT_CONFIG;
    }
    set_rig_source(&d->cfg);
    if (geteuid() == 0 && !d->cfg.allow_root) {
        uwbd_log(UWBD_LOG_ERR, "refusing to run as root: run as the uwbd user (see board/uwbd.service), "
                               "or set allow_root / pass --allow-root");
        return UWBD_EXIT_NO_PERM;
    }
    first_missing_directory(d->cfg.state_dir, created_dir, created_len);
    d->lock_fd = uwbd_store_lock(d->cfg.state_dir, err, sizeof err);
    if (d->lock_fd < 0) {
        uwbd_log(UWBD_LOG_ERR, "state directory: %s", err);
        return UWBD_EXIT_CANT_CREATE;
    }
    int repairs = 0;
    if (uwbd_state_open(&d->store, d->cfg.state_dir, &repairs, err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_ERR, "state directory: %s", err);
        return UWBD_EXIT_CANT_CREATE;
    }
    if (repairs)
        uwbd_log(UWBD_LOG_WARNING, "state directory: removed %d leftover(s) of an interrupted write",
                 repairs);
    uwbd_lock_watch_open(d);
    if (setup_event_fds(d, err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_ERR, "%s", err);
        return UWBD_EXIT_OS;
    }
    /* The socket before the hardware: a second uwbd stops here, before it touches a line. */
    int rc = uwbd_control_listen(&d->control, d->cfg.control_socket, d->cfg.control_mode,
                                 d->cfg.control_group, err, sizeof err);
    if (rc != UWBD_CONTROL_OK) {
        uwbd_log(UWBD_LOG_ERR, "%s", err);
        return rc == UWBD_CONTROL_ERR_CONFIG ? UWBD_EXIT_CONFIG : UWBD_EXIT_CANT_CREATE;
    }
    int detail = 0;
    rc = uwbd_rig_open_logged(d, &detail, err, sizeof err);
    if (rc != UWB_RIG_OK) {
        int code = uwbd_exit_for_rig_open(rc, detail);
        uwbd_log(UWBD_LOG_ERR, "%s (exit %d)", err, code);
        hint_emulated_board(d, rc);
        return code;
    }
    load_baseline_info(d);
    uwbd_baseline_requests_restore(d);
    load_latest_verdict(d);
    rc = uwbd_outputs_open(&d->port); /* the site's lines, Modbus */
    if (rc != UWBD_EXIT_OK)
        return rc;
    uwbd_console_open(d);
    uwbd_schedule_first(d);
    if (d->cfg.interval_s > 0)
        uwbd_log(UWBD_LOG_NOTICE, "uwbd %s running: state %s, control %s, a scan every %.0f s", UWBD_VERSION,
                 d->store.root, d->control.path, d->cfg.interval_s);
    else
        uwbd_log(UWBD_LOG_NOTICE, "uwbd %s running: state %s, control %s, scans on request only",
                 UWBD_VERSION, d->store.root, d->control.path);
    return UWBD_EXIT_OK;
}

int uwbd_daemon_run(const struct uwbd_options *opt)
{
    static struct daemon d; /* one per process; large */
    memset(&d, 0, sizeof d);
    d.options = opt;
    d.started = time(NULL);
    d.lock_fd = d.lock_watch_fd = d.signal_fd = d.schedule_fd = d.console_retry_fd = d.done_fd =
        d.watchdog_fd = d.progress_fd = -1;
    d.control.fd = -1;
    port_fill(&d);
    uwbd_peers_init(&d);
    clock_gettime(CLOCK_MONOTONIC, &d.last_cycle_start);
    uwbd_log_setup(opt->log_level, opt->use_syslog);
    static char created_dir[UWBD_PATH_MAX];
    int rc = start(&d, created_dir, sizeof created_dir);
    if (rc == UWBD_EXIT_OK) {
        watchdog_start(&d);
        uwbd_report_status(&d);
        uwbd_service_notify("READY=1");
        loop(&d);
        uwbd_service_notify("STOPPING=1");
    }
    teardown(&d);
    if (rc != UWBD_EXIT_OK && created_dir[0])
        remove_fresh_state_dir(&d, created_dir);
    if (rc == UWBD_EXIT_OK && d.exit_code) {
        uwbd_log(UWBD_LOG_ERR, "stopped: the state directory is no longer ours (exit %d); hardware left safe",
                 d.exit_code);
        return d.exit_code;
    }
    if (rc == UWBD_EXIT_OK)
        uwbd_log(UWBD_LOG_NOTICE, "stopped; hardware left safe");
    return rc;
}
