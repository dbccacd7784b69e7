/* The daemon's state, shared by the loop (daemon.c), the command peers
 * (peers.c) and the scan worker (worker.c). Everything here belongs to the
 * main thread, except what the comments give to the worker while a scan
 * runs; pthread_create and pthread_join hand it over and back. */
#ifndef UWB_DAEMON_INTERNAL_H
#define UWB_DAEMON_INTERNAL_H

#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <signal.h>
#include <sys/types.h>
#include <time.h>

#include "state/baseline_store.h"
#include "config/config_load.h"
#include "control/control_socket.h"
#include "loop/event_loop.h"
#include "daemon/output_module.h"
#include "control/console_line.h"
#include "control/line_buffer.h"
#include "daemon/scan_cycle.h"
#include "control/scan_progress.h"
#include "state/state_writes.h"
#include "state/store.h"
#include "uwb/link.h"
#include "uwb/rig.h"

struct uwbd_options; /* daemon/daemon.h: the command line's */

#define MAX_CLIENTS 16
/* Clients other than root and the daemon's own user (control-group members)
 * fill at most this many slots: the last is kept so that an administrator
 * can always get in, as PostgreSQL keeps superuser_reserved_connections. */
#define MAX_ORDINARY_CLIENTS (MAX_CLIENTS - 1)
/* A reply that cannot be sent within this is dropped with its client (the
 * console's blocking write; a control client's queue that makes no progress). */
#define SEND_TIMEOUT_MS 2000
/* A control client must complete a command line within this of connecting
 * or of its previous line, unless it waits for a scan's verdict. */
#define CLIENT_LINE_TIMEOUT_S 5.0
/* A full table drops, for a new connection, a client whose current line
 * began at least this long ago. */
#define CLIENT_IDLE_EVICT_S 2.0
/* Replies queued for one control client that does not read: beyond this it
 * is dropped (the loop never blocks on a client). */
#define CLIENT_QUEUE_MAX ((size_t)1024 * 1024)
#define CONSOLE_RETRY_S 5

enum peer_kind { PEER_CONTROL, PEER_CONSOLE };
/* What started a scan, for its verdict; ranked, so that requests merged
 * into one scan name the strongest. */
enum scan_trigger { TRIGGER_NONE, TRIGGER_SCHEDULE, TRIGGER_COMMAND, TRIGGER_EVENT };
enum { WATCH_ALL = 1, WATCH_PROGRESS = 2 };

struct peer {
    enum peer_kind kind;
    int in_use;
    int fd;                /* control client socket */
    struct uwb_link *link; /* console */
    struct uwbd_line_buffer lines;
    struct uwbd_console_line console_line; /* the console's: echo and editing keys */
    int console_at_prompt;                 /* the console's cursor is on the prompt's line */
    int console_progress_shown; /* the line above the prompt is a PROGRESS line, redrawn in place */
    unsigned long waiting_for;  /* cycle whose verdict this peer asked for; 0 = none */
    int watching;               /* `watch`: WATCH_ALL, WATCH_PROGRESS (what `uwbd ctl scan` asks) or 0 */
    double last_active_s;       /* CLOCK_MONOTONIC of its connection or last input */
    double line_since_s;        /* CLOCK_MONOTONIC of its connection or last complete line */
    char *out;                  /* queued reply bytes not yet sent (control clients) */
    size_t out_len, out_cap;
    double out_progress_s; /* CLOCK_MONOTONIC of the queue's last progress */
    int privileged;        /* connected as root or the daemon's own user (SO_PEERCRED) */
    uid_t uid;             /* its user (SO_PEERCRED); (uid_t)-1 unknown */
};

/* When each ordinary user last started a scan (control.scan_min_interval_s). */
struct scan_start {
    uid_t uid;
    double at_s; /* CLOCK_MONOTONIC; 0: a free entry */
};

struct scan_job {
    pthread_t thread;
    unsigned long cycle;
    double started_s;               /* CLOCK_MONOTONIC when the cycle started */
    unsigned long baseline_request; /* the `baseline set` this job carries, 0 = none */
    struct uwbd_cycle_request request;
    struct uwbd_cycle_result result;
};

struct daemon {
    const struct uwbd_options *options;
    struct uwbd_config cfg; /* read by the worker while a scan runs: not changed then */
    struct uwbd_store store;
    struct uwb_rig *rig; /* the worker's while a scan runs */
    char rig_state[512]; /* the worker's while a scan runs */
    time_t started;

    int lock_fd; /* the state directory's lock, held until exit */
    int signal_fd, schedule_fd, done_fd, console_retry_fd;
    struct uwbd_control_socket control;
    struct peer clients[MAX_CLIENTS];
    struct peer console;
    struct scan_start scan_starts[MAX_CLIENTS]; /* ordinary users' latest scans */

    int scanning; /* a worker thread exists */
    struct scan_job job;
    unsigned long cycles_started;
    int scans_this_run;
    int scan_queued;                 /* a `scan` came while one was running */
    unsigned long baseline_requests; /* `baseline set` commands so far */
    unsigned long baseline_done;     /* the request the baseline last satisfied */
    int baseline_scans;              /* scans the pending request averages */
    int baseline_force;              /* ...and it is `baseline set force` */
    char fault[512];                 /* "" or the device fault the last scan found (the baseline) */
    struct uwbd_state_writes writes; /* whether the state directory takes the cycles' writes */
    int lock_watch_fd;               /* inotify on the state directory's lock file, -1 none */
    int exit_code;                   /* non-zero: stop and exit with it */
    int stopping;
    int reload_pending;
    int has_next_scan;
    struct timespec next_scan;        /* CLOCK_MONOTONIC */
    struct timespec last_cycle_start; /* CLOCK_MONOTONIC; the schedule counts from it */
    int console_failing;              /* log a console outage once, not every retry */

    /* systemd's watchdog (daemon.c): pinged from the main loop while the
     * scan worker, if one runs, has shown a sign of life recently. */
    int watchdog_fd;                  /* timerfd, -1 without a watchdog */
    int watchdog_withheld;            /* pings stopped: the worker went silent */
    _Atomic long long worker_beat_ms; /* CLOCK_MONOTONIC ms of the worker's last sign of life */

    /* The running scan's progress, written by the worker (its rig hook), read
     * by the loop; progress_fd tells the loop a position was acquired. */
    int progress_fd;
    _Atomic int progress_done, progress_total;
    /* Which acquisition of the cycle (1-based; 0 before the first), of how many:
     * `baseline set N` plans N; one re-acquired for a decisive verdict adds one. */
    _Atomic int progress_pass, progress_passes;
    _Atomic long long progress_start_ms, progress_first_ms, progress_last_ms;

    char *latest_verdict;              /* VERDICT line or NULL: what is sent and stored */
    struct uwb_verdict_record *latest; /* the same verdict as a record, or NULL: what is read */
    enum scan_trigger pending_trigger; /* what asked for the next scan */
    /* What the output modules see of the daemon (daemon.c fills it). */
    struct uwbd_daemon_port port;
    int has_baseline;
    struct uwbd_baseline_info baseline;

    /* Every fd the main loop polls (daemon.c, peer_watch.c and the output
     * modules' watch hooks: outputs.h); the ids of the peers' entries. */
    struct uwbd_event_loop events;
    int control_id, console_id, client_id[MAX_CLIENTS];
};

/* worker.c */
int uwbd_worker_start(struct daemon *d); /* 0, or -1 (logged) */
void uwbd_worker_request_stop(struct daemon *d);
/* After done_fd fired: the cycle's end taken in (d->latest, the baseline
 * request, the state directory's writes); what the caller tells whom. A
 * CYCLE leaves d->job.result for the caller to publish and free. */
enum uwbd_collected { UWBD_COLLECTED_NOTHING, UWBD_COLLECTED_STOPPED, UWBD_COLLECTED_CYCLE };
enum uwbd_collected uwbd_worker_collect(struct daemon *d);
void uwbd_worker_install_stop_handler(void);
int uwbd_rig_open_logged(struct daemon *d, int *detail, char *err, size_t errlen);

/* peers.c */
void uwbd_peers_init(struct daemon *d);
void uwbd_peer_accept(struct daemon *d);
void uwbd_peer_readable(struct daemon *d, struct peer *p);
void uwbd_peer_close(struct peer *p);
/* Send what a control client's queue holds, as far as its socket takes it. */
void uwbd_peer_writable(struct daemon *d, struct peer *p);
/* Drop control clients past their deadlines; returns the milliseconds until
 * the next deadline (-1: none), for poll(). */
int uwbd_peers_expire(struct daemon *d);
/* The verdict line to the peers waiting for `cycle`, or ERROR with `error` when line is NULL. */
void uwbd_peers_send_verdict(struct daemon *d, unsigned long cycle, const char *line, const char *error);
/* A PROGRESS line to the peers that asked to `watch`. */
void uwbd_peers_send_progress(struct daemon *d);
/* The running scan's progress now (0 when no scan runs). */
int uwbd_scan_progress_now(struct daemon *d, struct uwbd_scan_progress *out);
void uwbd_console_open(struct daemon *d);
/* uwbd_scan_start, the peers waiting for the cycle told when it cannot start. */
void uwbd_peers_request_scan(struct daemon *d, enum scan_trigger why);

/* peer_watch.c: the peers' entries in the main loop (0, or -1 when it is
 * full); every peer and the control socket closed. */
int uwbd_peers_watch(struct daemon *d, struct uwbd_event_loop *loop);
void uwbd_peers_close_all(struct daemon *d);

/* baseline_requests.c */
char *uwbd_baseline_request(struct daemon *d, int scans, int force); /* `baseline set [N|force]`: the reply */
void uwbd_baseline_requests_restore(struct daemon *d);               /* a request pending at the last stop */
void uwbd_baseline_request_fill(struct daemon *d, struct uwbd_cycle_request *req);
void uwbd_baseline_request_finished(struct daemon *d, unsigned long request,
                                    const struct uwbd_cycle_result *res);

/* lock_watch.c */
int uwbd_lock_watch_open(struct daemon *d);   /* 0, or -1 (logged; the daemon runs unwatched) */
void uwbd_lock_watch_check(struct daemon *d); /* stops the daemon when the lock is no longer ours */

/* scan_start.c: the schedule armed one interval after `from`, or at start
 * from the latest verdict's time; a cycle started now or queued behind the
 * running one (why: what asked, TRIGGER_NONE for a queued one): NULL, or
 * why it cannot start, for the peers waiting for it. */
void uwbd_schedule_arm(struct daemon *d, const struct timespec *from);
void uwbd_schedule_first(struct daemon *d);
const char *uwbd_scan_start(struct daemon *d, enum scan_trigger why);
void uwbd_worker_beat(struct daemon *d);   /* the worker shows a sign of life (the watchdog's) */
void uwbd_report_status(struct daemon *d); /* STATUS= for systemctl status */

/* contacts_test.c: `contacts test [force] [S]` (the reply) from `who`, a
 * peer already found to be allowed (the sequence runs in output_contacts.c). */
char *uwbd_contacts_test_start(struct daemon *d, int hold_s, int force, const char *who);
/* Root, the daemon's own user, the console and contacts.test_group's
 * members may test the contacts: 0, or -1 with `why` naming who may. */
int uwbd_contacts_test_permitted(const struct daemon *d, const struct peer *p, char *why, size_t n);

/* site_commands.c: a command MQTT received, run: its reply (malloc'd) */
char *uwbd_site_command(struct daemon *d, const char *text);

#endif
