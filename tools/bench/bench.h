/* uwbbench: what `make bench` prints. Shared declarations of the bench's
 * files; figures, and with --assert-budget the replay budget's verdict. */
#ifndef UWBBENCH_BENCH_H
#define UWBBENCH_BENCH_H

#include <stddef.h>

#include "uwb/geometry.h"
#include "uwb/monotonic.h"
#include "uwb/scan.h"

/* ---- options ----------------------------------------------------------- */

struct bench_options {
    int quick;             /* one run of each figure, small size only (emulators) */
    int runs_small;        /* repetitions at 21 x 2048 */
    int runs_large;        /* repetitions at 64 x 4096 */
    int runs_replay;       /* repetitions of the whole replay */
    int list_calls;        /* print every timed library call of the replay */
    int replay_only;       /* the whole replay alone, no migration figures */
    const char *uwbd_path; /* the program measured as a child; NULL: next to uwbbench */
    const char *replay_current, *replay_baseline; /* recorded scans to replay; NULL: simulate a pair */
    int assert_budget;                            /* exit 1 when the replay is over its budget (make bench) */
    double budget_ms;                             /* the replay's time budget (issue 18: 100 ms) */
    double budget_mib;                            /* uwbd's peak RSS budget during it (issue 18: 16 MiB) */
};

/* ---- clock ------------------------------------------------------------- */

/* Times are taken with uwb_monotonic_s() (CLOCK_MONOTONIC in seconds). */

/* A series of timed runs: the median is what a run usually costs, the best
 * what it costs when the shared machine leaves it alone. */
struct bench_series {
    int n;
    double seconds[64];
};
void bench_series_add(struct bench_series *s, double seconds);
double bench_series_median(const struct bench_series *s);
double bench_series_best(const struct bench_series *s);

/* ---- child programs ---------------------------------------------------- */

/* uwbd runs as a child of a small launcher forked at start-up, so the peak
 * RSS the kernel reports for it (wait4) is not inflated by this bench's own
 * memory, which a child forked later would carry until its exec. */
#define BENCH_CHILD_OUTPUT 8192
struct bench_child {
    double seconds;     /* fork to wait4 */
    double cpu_seconds; /* its user + system time (wait4's rusage): what a shared machine's load does not
                           inflate */
    /* Time it was ready to run but waited for a CPU (the kernel's run_delay,
     * /proc/PID/schedstat): on a shared machine, the part of `seconds` that
     * other programs took. -1: not known (a kernel without schedstat). */
    double queue_wait_seconds;
    long maxrss_kib;                 /* wait4's ru_maxrss */
    int status;                      /* exit status, or 128 + signal */
    char output[BENCH_CHILD_OUTPUT]; /* its stdout (truncated) */
};
int bench_launcher_start(char *err, size_t errlen);
int bench_launcher_run(char *const args[], struct bench_child *out, char *err, size_t errlen);
void bench_launcher_stop(void);

/* ---- scenes ------------------------------------------------------------ */

/* A simulated scan (uwbsim: 3-D physical optics, clutter and noise on), as
 * migration sees it after conditioning. `raw` may be NULL. */
struct bench_case {
    const char *name; /* "21 x 2048" */
    int positions, samples;
    double position_step_m;
    int ny, nz; /* image grid, 1 mm */
    double y0_m, z0_m;
};
int bench_simulate(const struct bench_case *c, double displacement_m, struct uwb_scan *raw,
                   struct uwb_scan *conditioned, char *err, size_t errlen);

/* ---- the yardstick ----------------------------------------------------- */

/* The straightforward migration: double precision, the two-way path from
 * two square roots per pixel and trace, linear interpolation. `out` holds
 * ny * nz doubles, out[iy * nz + iz]. */
void yardstick_migrate(const struct uwb_scan *scan, const struct uwb_geometry *g, int ny, int nz, double y0_m,
                       double dy_m, double z0_m, double dz_m, double *out);

/* ---- figures ----------------------------------------------------------- */

struct migration_figures {
    const char *name;
    long long pixel_traces;
    double fixed_ms, portable_ms, float_ms, yardstick_ms; /* medians */
    double fixed_best_ms, portable_best_ms, float_best_ms, yardstick_best_ms;
    double snr_fixed_db, snr_portable_db, snr_float_db; /* against the yardstick */
};
int bench_migration(const struct bench_case *c, int runs, struct migration_figures *f, char *err,
                    size_t errlen);

/* Where a replay's time goes inside the library, counted by the wrappers in
 * bench_stage_timers.c (linked with -Wl,--wrap). */
enum bench_stage {
    STAGE_CONDITION,
    STAGE_DOMINANT,
    STAGE_MIGRATE,
    STAGE_ENVELOPE,
    STAGE_PNG_ENCODE,
    STAGE_COUNT
};
#define BENCH_MAX_CALLS 64
struct bench_stage_call {
    enum bench_stage stage;
    int ny, nz; /* migration, envelope: the image grid (else 0) */
    double seconds;
};
struct bench_stage_totals {
    double seconds[STAGE_COUNT];
    long calls[STAGE_COUNT];
    long long pixel_traces; /* summed over the migrations */
    int n_calls;            /* the first BENCH_MAX_CALLS calls, in order */
    struct bench_stage_call call[BENCH_MAX_CALLS];
};
void bench_stages_reset(void);
void bench_stages_read(struct bench_stage_totals *t);
const char *bench_stage_name(enum bench_stage s);

struct replay_figures {
    int child_measured; /* 0: uwbd could not be run, in-process figures only */
    double child_ms, child_best_ms;
    double child_cpu_ms, child_cpu_best_ms; /* its CPU time, median and best */
    /* Wall time less the run-queue wait: the replay on one core of its own
     * (median and best); child_own_known 0 when the kernel does not say. */
    double child_own_ms, child_own_best_ms;
    int child_own_known;
    long child_maxrss_kib;
    long idle_maxrss_kib; /* uwbd --version: the program and its libraries, no work */
    int child_status;     /* exit status of the last run */
    char verdict[160];    /* status and displacement from its JSON line */
    /* In-process, the same library calls uwbd makes (medians of each part). */
    double read_ms, evaluate_ms, images_ms, total_ms;
    struct bench_stage_totals stages; /* of the median-total run */
};
int bench_replay(const struct bench_options *opt, struct replay_figures *f, char *err, size_t errlen);

#endif
