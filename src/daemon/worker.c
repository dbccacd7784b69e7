/* The scan worker: one thread per scan cycle, so the main loop keeps
 * answering commands while the carriage moves. Stopping it is a signal
 * (SIGUSR1) sent to that thread alone: its handler raises the flag the
 * rig polls, so the flag is only ever touched by the thread that reads it. */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "daemon_internal.h"
#include "util/log.h"
#include "daemon/test_hang.h"
#include "daemon/trend.h"
#include "uwb/monotonic.h"

static volatile sig_atomic_t scan_stop;

static void on_stop_signal(int sig)
{
    (void)sig;
    scan_stop = 1;
}

void uwbd_worker_install_stop_handler(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    /* Restart file writes; poll() and sleeps in the rig still return EINTR
     * and look at the flag. */
    sa.sa_flags = SA_RESTART;
    sigaction(SIGUSR1, &sa, NULL);
}

static void rig_log(void *ctx, int priority, const char *message)
{
    struct daemon *d = ctx;
    /* Every rig message (one a position at least) shows the worker alive. */
    atomic_store(&d->worker_beat_ms, (long long)(uwb_monotonic_s() * 1000.0));
    uwbd_log(priority, "rig: %s", message);
}

static void progress_signal(struct daemon *d)
{
    uint64_t one = 1;
    if (write(d->progress_fd, &one, sizeof one) != sizeof one) {
        /* the counter is full: the loop has a wake-up pending anyway */
    }
}

/* The rig's position hook: record where the scan is, wake the loop. */
static void rig_progress(void *ctx, int done, int total)
{
    struct daemon *d = ctx;
    long long now_ms = (long long)(uwb_monotonic_s() * 1000.0);
    atomic_store(&d->worker_beat_ms, now_ms);
    int pass = atomic_load(&d->progress_pass);
    if (done == 0) { /* a new acquisition of this cycle begins */
        pass++;
        atomic_store(&d->progress_pass, pass);
        if (pass > atomic_load(&d->progress_passes))
            atomic_store(&d->progress_passes, pass);
    }
    /* The times run over the whole cycle: its first pass's start and first position. */
    if (done == 0 && pass <= 1)
        atomic_store(&d->progress_start_ms, now_ms);
    if (done == 1 && pass <= 1)
        atomic_store(&d->progress_first_ms, now_ms);
    atomic_store(&d->progress_last_ms, now_ms);
    atomic_store(&d->progress_total, total);
    atomic_store(&d->progress_done, done);
    progress_signal(d);
}

int uwbd_scan_progress_now(struct daemon *d, struct uwbd_scan_progress *out)
{
    if (!d->scanning)
        return 0;
    int done = atomic_load(&d->progress_done);
    uwbd_scan_progress_estimate_passes(atomic_load(&d->progress_pass), atomic_load(&d->progress_passes), done,
                                       atomic_load(&d->progress_total),
                                       atomic_load(&d->progress_start_ms) / 1000.0,
                                       atomic_load(&d->progress_first_ms) / 1000.0,
                                       atomic_load(&d->progress_last_ms) / 1000.0, uwb_monotonic_s(), out);
    return 1;
}

int uwbd_rig_open_logged(struct daemon *d, int *detail, char *err, size_t errlen)
{
    int rc = uwb_rig_open(&d->cfg.rig, &d->rig, detail, err, errlen);
    if (rc != UWB_RIG_OK) {
        d->rig = NULL;
        snprintf(d->rig_state, sizeof d->rig_state, "unavailable: %.400s", err);
        return rc;
    }
    uwb_rig_set_log(d->rig, rig_log, d);
    uwb_rig_set_progress(d->rig, rig_progress, d);
    snprintf(d->rig_state, sizeof d->rig_state, "ready");
    return rc;
}

/* uwbd_acquire_fn over the rig: reopen it when an earlier failure closed
 * it, and close it after a failure so that a link that went away is opened
 * afresh next time. */
static int acquire_from_rig(void *ctx, const volatile sig_atomic_t *stop, struct uwb_scan *out, char *err,
                            size_t errlen)
{
    struct daemon *d = ctx;
    uwbd_test_hang_point("worker");
    if (!d->rig) {
        int detail = 0;
        if (uwbd_rig_open_logged(d, &detail, err, errlen) != UWB_RIG_OK)
            return *stop ? UWBD_ACQUIRE_STOPPED : UWBD_ACQUIRE_FAILED;
        uwbd_log(UWBD_LOG_NOTICE, "rig opened again");
    }
    int rc = uwb_rig_scan(d->rig, stop, out, err, errlen);
    if (rc == UWB_RIG_OK)
        return UWBD_ACQUIRE_OK;
    uwb_rig_make_safe(d->rig);
    if (rc == UWB_RIG_ERR_STOPPED || *stop)
        return UWBD_ACQUIRE_STOPPED;
    uwb_rig_close(d->rig);
    d->rig = NULL;
    snprintf(d->rig_state, sizeof d->rig_state, "closed after an error, reopened at the next scan: %.300s",
             err);
    return UWBD_ACQUIRE_FAILED;
}

static void *worker_main(void *arg)
{
    struct daemon *d = arg;
    sigset_t usr1;
    sigemptyset(&usr1);
    sigaddset(&usr1, SIGUSR1);
    pthread_sigmask(SIG_UNBLOCK, &usr1, NULL);
    uwbd_cycle_run(&d->cfg, &d->store, acquire_from_rig, d, &scan_stop, &d->job.request, &d->job.result);
    if (d->job.result.outcome == UWBD_CYCLE_RECORDED) {
        /* trend.png follows every verdict; here, off the main loop. */
        char err[512], site[256];
        uwbd_trend_site_text(&d->cfg, site, sizeof site);
        if (uwbd_trend_png_update(&d->cfg, &d->store, site, err, sizeof err) != 0)
            uwbd_log(UWBD_LOG_WARNING, "trend image not updated: %s", err);
    }
    /* No signal may land after this thread stops looking. */
    pthread_sigmask(SIG_BLOCK, &usr1, NULL);
    uint64_t one = 1;
    if (write(d->done_fd, &one, sizeof one) != sizeof one)
        uwbd_log(UWBD_LOG_ERR, "worker: cannot signal the end of the scan: %s", strerror(errno));
    return NULL;
}

static const char *trigger_name(enum scan_trigger why)
{
    switch (why) {
    case TRIGGER_EVENT: return "event";
    case TRIGGER_COMMAND: return "command";
    case TRIGGER_SCHEDULE:
    case TRIGGER_NONE: break;
    }
    return "schedule";
}

int uwbd_worker_start(struct daemon *d)
{
    memset(&d->job, 0, sizeof d->job);
    d->job.cycle = ++d->cycles_started;
    struct timespec wall;
    clock_gettime(CLOCK_REALTIME, &wall);
    d->job.request.now = wall.tv_sec;
    d->job.request.now_ms = wall.tv_nsec / 1000000;
    d->job.started_s = uwb_monotonic_s();
    d->job.request.trigger = trigger_name(d->pending_trigger);
    d->pending_trigger = TRIGGER_NONE;
    uwbd_baseline_request_fill(d, &d->job.request);
    int pending = d->job.request.make_baseline;
    d->job.baseline_request = pending ? d->baseline_requests : 0;
    long long now_ms = (long long)(uwb_monotonic_s() * 1000.0);
    atomic_store(&d->progress_done, 0);
    atomic_store(&d->progress_total, d->cfg.rig.positions);
    int passes = d->job.request.make_baseline ? d->job.request.baseline_scans : 1;
    atomic_store(&d->progress_pass, 0);
    atomic_store(&d->progress_passes, passes < 1                        ? 1
                                      : passes > UWB_BASELINE_SCANS_MAX ? UWB_BASELINE_SCANS_MAX
                                                                        : passes);
    atomic_store(&d->progress_start_ms, now_ms);
    scan_stop = 0; /* before the thread exists: pthread_create orders it */
    int rc = pthread_create(&d->job.thread, NULL, worker_main, d);
    if (rc != 0) {
        uwbd_log(UWBD_LOG_ERR, "cannot start the scan thread: %s", strerror(rc));
        d->cycles_started--;
        return -1;
    }
    d->scanning = 1;
    uwbd_log(UWBD_LOG_INFO, "scan cycle %lu started%s", d->job.cycle,
             pending ? " (it becomes the baseline if good)" : "");
    return 0;
}

void uwbd_worker_request_stop(struct daemon *d)
{
    if (d->scanning)
        pthread_kill(d->job.thread, SIGUSR1);
}

enum uwbd_collected uwbd_worker_collect(struct daemon *d)
{
    uint64_t count;
    if (read(d->done_fd, &count, sizeof count) != sizeof count)
        return UWBD_COLLECTED_NOTHING;
    if (!d->scanning)
        return UWBD_COLLECTED_NOTHING;
    pthread_join(d->job.thread, NULL);
    d->scanning = 0;
    struct uwbd_cycle_result *res = &d->job.result;
    if (res->outcome == UWBD_CYCLE_STOPPED) {
        uwbd_log(UWBD_LOG_NOTICE, "scan cycle %lu stopped before its end; nothing recorded, hardware safe",
                 d->job.cycle);
        uwbd_cycle_result_free(res);
        return UWBD_COLLECTED_STOPPED;
    }
    d->scans_this_run++;
    uwbd_state_writes_after_cycle(&d->writes, res->write_error, time(NULL));
    if (res->verdict_json && res->verdict) {
        free(d->latest_verdict);
        d->latest_verdict = strdup(res->verdict_json);
        free(d->latest);
        d->latest = res->verdict;
        res->verdict = NULL;
    }
    uwbd_baseline_request_finished(d, d->job.baseline_request, res);
    return UWBD_COLLECTED_CYCLE;
}
