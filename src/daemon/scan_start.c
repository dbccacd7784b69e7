/* When scans start: the schedule's timer, and a scan started now or queued
 * behind the running one, whoever asks (the schedule, a command, the event
 * input). What starts it tells no one: the caller answers whoever waits
 * (uwbd_peers_request_scan in peers.c), so this file sits below the peers. */
#include <stdatomic.h>
#include <sys/timerfd.h>
#include <time.h>

#include "daemon/service_notify.h"
#include "daemon/test_hang.h"
#include "daemon_internal.h"
#include "util/log.h"
#include "uwb/monotonic.h"
#include "uwb/utc_time.h"

static struct timespec monotonic_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t;
}

static struct timespec add_seconds(struct timespec t, double s)
{
    long whole = (long)s;
    t.tv_sec += whole;
    t.tv_nsec += (long)((s - (double)whole) * 1e9);
    if (t.tv_nsec >= 1000000000L) {
        t.tv_sec++;
        t.tv_nsec -= 1000000000L;
    }
    return t;
}

static void schedule_off(struct daemon *d)
{
    struct itimerspec off = {0};
    timerfd_settime(d->schedule_fd, 0, &off, NULL);
    d->has_next_scan = 0;
}

static void arm_at(struct daemon *d, struct timespec when)
{
    if (when.tv_sec == 0 && when.tv_nsec == 0)
        when.tv_nsec = 1; /* an all-zero time would disarm the timer */
    d->next_scan = when;
    struct itimerspec its = {.it_value = when};
    timerfd_settime(d->schedule_fd, TFD_TIMER_ABSTIME, &its, NULL);
    d->has_next_scan = 1;
}

/* The next scheduled scan one interval after `from` (a past time fires at once). */
void uwbd_schedule_arm(struct daemon *d, const struct timespec *from)
{
    if (d->cfg.interval_s <= 0)
        schedule_off(d);
    else
        arm_at(d, add_seconds(*from, d->cfg.interval_s));
}

const char *uwbd_scan_start(struct daemon *d, enum scan_trigger why)
{
    if (why > d->pending_trigger)
        d->pending_trigger = why;
    if (d->scanning) {
        d->scan_queued = 1;
        return NULL;
    }
    uwbd_lock_watch_check(d); /* also when inotify is unavailable */
    if (d->exit_code)
        return "the state directory was deleted or replaced; uwbd is stopping";
    schedule_off(d);
    d->last_cycle_start = monotonic_now();
    uwbd_worker_beat(d);
    if (uwbd_worker_start(d) != 0) {
        uwbd_schedule_arm(d, &d->last_cycle_start);
        return "cannot start a scan (see the daemon's log)";
    }
    uwbd_report_status(d);
    uwbd_test_hang_point("loop");
    return NULL;
}

/* After a restart the schedule carries on from the latest verdict's time. */
void uwbd_schedule_first(struct daemon *d)
{
    if (d->cfg.interval_s <= 0) {
        schedule_off(d);
        return;
    }
    double wait = d->cfg.interval_s;
    time_t created_s;
    if (d->latest && uwb_utc_parse(d->latest->created, &created_s) == 0) {
        double elapsed = difftime(time(NULL), created_s);
        if (elapsed >= 0) /* a clock set back says nothing about the schedule */
            wait = elapsed >= wait ? 0 : wait - elapsed;
    }
    arm_at(d, add_seconds(monotonic_now(), wait));
    if (wait < d->cfg.interval_s)
        uwbd_log(UWBD_LOG_INFO,
                 "next scheduled scan in %.0f s (the schedule carries on from the latest verdict)", wait);
}

void uwbd_worker_beat(struct daemon *d)
{
    atomic_store(&d->worker_beat_ms, (long long)(uwb_monotonic_s() * 1000.0));
}

/* STATUS= for systemctl status: what the daemon does and the latest verdict. */
void uwbd_report_status(struct daemon *d)
{
    if (d->stopping) {
        uwbd_service_status("stopping");
        return;
    }
    if (d->scanning) {
        uwbd_service_status("scanning (cycle %lu)", d->job.cycle);
        return;
    }
    if (d->latest)
        uwbd_service_status("idle; latest verdict %s%s%s", uwb_status_name(d->latest->status),
                            d->latest->created[0] ? " at " : "", d->latest->created);
    else
        uwbd_service_status("idle; no verdict yet");
}
