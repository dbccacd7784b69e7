/* The whole replay of a 21 x 2048 scan against its baseline: what
 * `uwbd --replay CUR --baseline BASE --out DIR` does, read to PNGs.
 *
 * Measured twice. As uwbd itself, started as a child (bench_launcher.c):
 * wall time around fork..wait4 and the peak RSS the kernel accounted to it
 * (wait4's rusage), so the memory figure is the real program's. And
 * in-process through the same library calls uwbd makes, with the stage
 * timers (bench_stage_timers.c) saying where the time goes. */
#include "bench.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "uwb/evaluate.h"
#include "uwb/render.h"

#define MAX_RUNS 64
#define MAX_PREFIX_WORDS 8

static const struct bench_case replay_case = {
    .name = "21 x 2048",
    .positions = 21,
    .samples = 2048,
    .position_step_m = 0.03,
};

struct replay_files {
    char dir[64];
    char current[PATH_MAX], baseline[PATH_MAX], out_child[128], out_inproc[128];
};

static void remove_files_in(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        unlink(path);
    }
    closedir(d);
}

static void remove_replay_files(const struct replay_files *f)
{
    remove_files_in(f->out_child);
    remove_files_in(f->out_inproc);
    rmdir(f->out_child);
    rmdir(f->out_inproc);
    remove_files_in(f->dir);
    rmdir(f->dir);
}

/* The recorded scans the options name, or two simulated scans, intact and
 * moved up 20 mm, written as uwbscan files. */
static int make_replay_files(const struct bench_options *opt, struct replay_files *f, char *err,
                             size_t errlen)
{
    snprintf(f->dir, sizeof f->dir, "/tmp/uwbbench-XXXXXX");
    if (!mkdtemp(f->dir)) {
        snprintf(err, errlen, "bench: cannot create a directory under /tmp: %s", strerror(errno));
        return -1;
    }
    snprintf(f->current, sizeof f->current, "%s/up20mm.uwbscan", f->dir);
    snprintf(f->baseline, sizeof f->baseline, "%s/intact.uwbscan", f->dir);
    snprintf(f->out_child, sizeof f->out_child, "%s/out-uwbd", f->dir);
    snprintf(f->out_inproc, sizeof f->out_inproc, "%s/out-library", f->dir);
    const char *paths[2] = {f->baseline, f->current};
    if (opt->replay_current) {
        int a = snprintf(f->current, sizeof f->current, "%s", opt->replay_current);
        int b = snprintf(f->baseline, sizeof f->baseline, "%s", opt->replay_baseline);
        if (a < 0 || (size_t)a >= sizeof f->current || b < 0 || (size_t)b >= sizeof f->baseline) {
            snprintf(err, errlen, "bench: --replay: path too long");
            return -1;
        }
    }
    for (int i = 0; i < 2 && !opt->replay_current; i++) {
        struct uwb_scan raw;
        if (bench_simulate(&replay_case, i ? 0.020 : 0.0, &raw, NULL, err, errlen) != 0)
            return -1;
        int rc = uwbscan_write_file(paths[i], &raw, err, errlen);
        uwb_scan_free(&raw);
        if (rc != 0)
            return -1;
    }
    if (mkdir(f->out_child, 0755) != 0 || mkdir(f->out_inproc, 0755) != 0) {
        snprintf(err, errlen, "bench: cannot create output directories in %s: %s", f->dir, strerror(errno));
        return -1;
    }
    return 0;
}

/* uwbd next to this program, unless the options name one. */
static int find_uwbd(const struct bench_options *opt, char *path, size_t n)
{
    if (opt->uwbd_path) {
        snprintf(path, n, "%s", opt->uwbd_path);
    } else {
        char self[PATH_MAX];
        ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
        if (len <= 0)
            return -1;
        self[len] = '\0';
        char *slash = strrchr(self, '/');
        if (!slash)
            return -1;
        *slash = '\0';
        int len_path = snprintf(path, n, "%s/uwbd", self);
        if (len_path < 0 || (size_t)len_path >= n)
            return -1;
    }
    return access(path, X_OK) == 0 ? 0 : -1;
}

/* "status alarm, displacement +20.03 mm" from the verdict line. */
static void summarise_verdict(const char *line, char *out, size_t n)
{
    cJSON *v = cJSON_Parse(line);
    const cJSON *status = cJSON_GetObjectItemCaseSensitive(v, "status");
    const cJSON *disp = cJSON_GetObjectItemCaseSensitive(v, "axial_displacement_mm");
    if (cJSON_IsString(status) && cJSON_IsNumber(disp))
        snprintf(out, n, "status %s, displacement %+.2f mm", status->valuestring, disp->valuedouble);
    else if (cJSON_IsString(status))
        snprintf(out, n, "status %s", status->valuestring);
    else
        snprintf(out, n, "no verdict line");
    cJSON_Delete(v);
}

/* Run uwbd with `args` (NULL-terminated) through the launcher, with
 * UWB_EXEC_PREFIX (e.g. "qemu-aarch64 -L /") in front as in the tests. */
static int run_uwbd(char *const args[], struct bench_child *child, char *err, size_t errlen)
{
    char *argv[MAX_PREFIX_WORDS + 16];
    int argc = 0;
    char prefix[256] = "";
    const char *env = getenv("UWB_EXEC_PREFIX");
    if (env)
        snprintf(prefix, sizeof prefix, "%s", env);
    for (char *save = NULL, *w = strtok_r(prefix, " \t", &save); w && argc < MAX_PREFIX_WORDS;
         w = strtok_r(NULL, " \t", &save))
        argv[argc++] = w;
    for (int i = 0; args[i] && argc < MAX_PREFIX_WORDS + 15; i++)
        argv[argc++] = args[i];
    argv[argc] = NULL;
    if (bench_launcher_run(argv, child, err, errlen) != 0)
        return -1;
    if (child->status != 0) {
        snprintf(err, errlen, "bench: %s exited with status %d", args[0], child->status);
        return -1;
    }
    return 0;
}

/* One in-process run: the calls src/cli/replay_cli.c makes for --replay/--baseline/--out. */
static int run_in_process(const struct replay_files *f, double part[3], char *err, size_t errlen)
{
    struct uwb_scan cur = {0}, base = {0};
    struct uwb_analysis cur_a, base_a;
    struct uwb_verdict v;
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    int rc = -1;
    double t0 = uwb_monotonic_s();
    if (uwbscan_read_file(f->current, &cur, err, errlen) != 0 ||
        uwbscan_read_file(f->baseline, &base, err, errlen) != 0)
        goto done;
    double t1 = uwb_monotonic_s();
    struct uwb_baseline_record rec = {.scan = &base};
    if (uwb_evaluate(&cur, &rec, &opt, &v, &cur_a, &base_a, err, errlen) != 0)
        goto done;
    double t2 = uwb_monotonic_s();
    rc = uwb_write_images(f->out_inproc, "current", NULL, &cur, &cur_a, &base_a, &v, err, errlen);
    double t3 = uwb_monotonic_s();
    uwb_analysis_free(&cur_a);
    uwb_analysis_free(&base_a);
    part[0] = t1 - t0;
    part[1] = t2 - t1;
    part[2] = t3 - t2;
done:
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    return rc;
}

int bench_replay(const struct bench_options *opt, struct replay_figures *fig, char *err, size_t errlen)
{
    memset(fig, 0, sizeof *fig);
    struct replay_files f;
    memset(&f, 0, sizeof f);
    if (make_replay_files(opt, &f, err, errlen) != 0) {
        if (f.dir[0] && strcmp(f.dir, "/tmp/uwbbench-XXXXXX") != 0)
            remove_replay_files(&f);
        return -1;
    }
    int runs = opt->runs_replay < 1 ? 1 : opt->runs_replay > MAX_RUNS ? MAX_RUNS : opt->runs_replay;
    int rc = -1;

    char uwbd[PATH_MAX];
    if (find_uwbd(opt, uwbd, sizeof uwbd) == 0) {
        struct bench_series wall = {0}, cpu = {0}, own = {0};
        static struct bench_child child;
        char *version[] = {uwbd, "--version", NULL};
        if (run_uwbd(version, &child, err, errlen) != 0)
            goto done;
        fig->idle_maxrss_kib = child.maxrss_kib;
        char *replay[] = {uwbd, "--replay", f.current, "--baseline", f.baseline, "--out", f.out_child, NULL};
        for (int r = 0; r < runs; r++) {
            if (run_uwbd(replay, &child, err, errlen) != 0)
                goto done;
            bench_series_add(&wall, child.seconds);
            bench_series_add(&cpu, child.cpu_seconds);
            if (child.queue_wait_seconds >= 0.0)
                bench_series_add(&own, child.seconds - child.queue_wait_seconds);
            if (child.maxrss_kib > fig->child_maxrss_kib)
                fig->child_maxrss_kib = child.maxrss_kib;
        }
        fig->child_status = child.status;
        summarise_verdict(child.output, fig->verdict, sizeof fig->verdict);
        fig->child_measured = 1;
        fig->child_ms = 1e3 * bench_series_median(&wall);
        fig->child_best_ms = 1e3 * bench_series_best(&wall);
        fig->child_cpu_ms = 1e3 * bench_series_median(&cpu);
        fig->child_cpu_best_ms = 1e3 * bench_series_best(&cpu);
        fig->child_own_known = own.n == wall.n;
        fig->child_own_ms = 1e3 * bench_series_median(&own);
        fig->child_own_best_ms = 1e3 * bench_series_best(&own);
    }

    struct bench_series parts[3] = {{0}}, total = {0};
    static struct bench_stage_totals stages[MAX_RUNS];
    for (int r = 0; r < runs; r++) {
        double part[3];
        bench_stages_reset();
        if (run_in_process(&f, part, err, errlen) != 0)
            goto done;
        bench_stages_read(&stages[r]);
        for (int i = 0; i < 3; i++)
            bench_series_add(&parts[i], part[i]);
        bench_series_add(&total, part[0] + part[1] + part[2]);
    }
    fig->read_ms = 1e3 * bench_series_median(&parts[0]);
    fig->evaluate_ms = 1e3 * bench_series_median(&parts[1]);
    fig->images_ms = 1e3 * bench_series_median(&parts[2]);
    fig->total_ms = 1e3 * bench_series_median(&total);
    /* The stage split of the run whose total is nearest the median. */
    int pick = 0;
    for (int r = 1; r < runs; r++)
        if (abs((int)(1e6 * (total.seconds[r] - 1e-3 * fig->total_ms))) <
            abs((int)(1e6 * (total.seconds[pick] - 1e-3 * fig->total_ms))))
            pick = r;
    fig->stages = stages[pick];
    rc = 0;
done:
    remove_replay_files(&f);
    return rc;
}
