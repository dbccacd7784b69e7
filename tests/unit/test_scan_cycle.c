/* One scan cycle above the hardware, fed simulated scans: what lands in the
 * state directory, when the baseline changes (only when asked, keeping the
 * old one), the direct-coupling check, lost scans as `error` verdicts, and
 * a full disk that hides no verdict. */
#include "unity.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include "scene_support.h"
#include "scratch_support.h"
#include "state/baseline_store.h"
#include "config/config_load.h"
#include "state/retention.h"
#include "daemon/scan_cycle.h"
#include "state/store.h"
#include "state/verdict_log.h"
#include "uwb/atomic_file.h"
#include "uwb/direct_coupling.h"
#include "uwbsim/uwbsim.h"

/* 2030-01-02T00:00:00Z: the archive day is 2030/01/02. */
#define CYCLE_TIME ((time_t)1893542400)
#define DAY_DIR "archive/2030/01/02"

/* What the fake acquisition hands the cycle: a simulated scan of the scene,
 * made once per winding position (simulating is slow under qemu) and
 * copied for every cycle. */
struct fake_rig {
    struct sim_scene scene;
    int displaced;     /* the winding moved up 12 mm */
    int delay_samples; /* the whole record arrives this much later (a longer cable) */
    int fail;          /* report a lost scan */
    int stopped;       /* report a stop request */
    int blank;         /* noise only: no coupling, no winding */
};

static char dir[64];
static char err[2048];
static struct uwbd_store store;
static struct uwbd_config cfg;
static struct fake_rig rig;
static struct uwbd_cycle_result res;
static int scans_made;

static struct uwb_scan simulated[2]; /* intact, displaced; kept for the whole run */

static int fake_acquire(void *ctx, const volatile sig_atomic_t *stop, struct uwb_scan *out, char *e, size_t n)
{
    (void)stop;
    struct fake_rig *r = ctx;
    if (r->stopped)
        return UWBD_ACQUIRE_STOPPED;
    if (r->fail) {
        snprintf(e, n, "digitiser: no frame within 1000 ms (timeout)");
        return UWBD_ACQUIRE_FAILED;
    }
    struct uwb_scan *cached = &simulated[r->displaced];
    if (!cached->data) {
        struct sim_scene scene = r->scene;
        if (r->displaced && sim_scene_set(&scene, "displacement_m", "0.012", e, n) != 0)
            return UWBD_ACQUIRE_FAILED;
        if (sim_make_scan(&scene, 1 + (uint64_t)r->displaced, cached, e, n) != 0)
            return UWBD_ACQUIRE_FAILED;
    }
    if (uwb_scan_copy(out, cached, e, n) != 0)
        return UWBD_ACQUIRE_FAILED;
    int S = out->samples;
    for (int k = 0; k < out->positions; k++) {
        float *trace = out->data + (size_t)k * (size_t)S;
        if (r->delay_samples > 0) {
            memmove(trace + r->delay_samples, trace, sizeof(float) * (size_t)(S - r->delay_samples));
            for (int i = 0; i < r->delay_samples; i++)
                trace[i] = 0.0f;
        }
        if (r->blank)
            for (int i = 0; i < S; i++)
                trace[i] = (float)(1e-4 * ((i * 7919 + k * 104729) % 101 - 50));
    }
    char id[64];
    snprintf(id, sizeof id, "sim-%d", ++scans_made);
    free(out->scan_id);
    out->scan_id = strdup(id);
    return UWBD_ACQUIRE_OK;
}

/* A full disk without root (issue 43, break 6): this binary is linked with
 * -Wl,--wrap for fflush, writev and mkdir (Makefile, TEST_WRAPS_test_scan_cycle),
 * so while `disk_full` is set every write into the state directory fails
 * as a full file system fails it: a buffered file's flush with ENOSPC
 * (what an atomic file's commit sees; the bytes written before it are on
 * disk in the temporary), the first append cut short after half its bytes
 * (the room that was left) and the next refused, a new directory refused.
 * Everything else passes through. */
static int disk_full;

int __real_fflush(FILE *f);
ssize_t __real_writev(int fd, const struct iovec *iov, int count);
int __real_mkdir(const char *path, mode_t mode);

int __wrap_fflush(FILE *f)
{
    if (!disk_full || f == NULL || f == stdout || f == stderr)
        return __real_fflush(f);
    errno = ENOSPC;
    return EOF;
}

ssize_t __wrap_writev(int fd, const struct iovec *iov, int count)
{
    static int took_last_room; /* the first append after the disk filled takes what room was left */
    if (!disk_full || count < 1) {
        took_last_room = 0;
        return __real_writev(fd, iov, count);
    }
    if (took_last_room || iov[0].iov_len < 2) {
        errno = ENOSPC;
        return -1;
    }
    took_last_room = 1;
    struct iovec half = {.iov_base = iov[0].iov_base, .iov_len = iov[0].iov_len / 2};
    return __real_writev(fd, &half, 1);
}

int __wrap_mkdir(const char *path, mode_t mode)
{
    struct stat st;
    if (disk_full && stat(path, &st) != 0) {
        errno = ENOSPC;
        return -1;
    }
    return __real_mkdir(path, mode);
}

static void set_scene(const char *key, const char *value)
{
    scene_set_or_fail(&rig.scene, key, value);
}

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "cycle");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, NULL, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_config_load("board/emulated/uwbd.json", NULL, 0, &cfg, err, sizeof err), err);
    memset(&rig, 0, sizeof rig);
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&rig.scene));
    /* A clean scene, so a displacement is measured to a fraction of a millimetre. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, sim_scene_load_json("tools/uwbsim/scenes/winding-only-3d.json", &rig.scene, err, sizeof err), err);
    set_scene("coupling_gain", "0.05");
    set_scene("noise", "true");
    set_scene("snr_db", "50");
    set_scene("samples", "1024");
    scans_made = 0;
    memset(&res, 0, sizeof res);
}

void tearDown(void)
{
    uwbd_cycle_result_free(&res);
    scratch_remove_tree(dir);
}

static void run_cycle(int make_baseline)
{
    uwbd_cycle_result_free(&res);
    struct uwbd_cycle_request req = {.make_baseline = make_baseline, .now = CYCLE_TIME};
    TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
}

static cJSON *verdict(void)
{
    TEST_ASSERT_NOT_NULL(res.verdict_json);
    cJSON *v = cJSON_Parse(res.verdict_json);
    TEST_ASSERT_NOT_NULL(v);
    return v;
}

static double number(const cJSON *v, const char *key)
{
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(v, key);
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(n), key);
    return n->valuedouble;
}

static int in_state(const char *rel)
{
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", store.root, rel);
    return scratch_file_exists(p);
}

static void current_baseline(struct uwbd_baseline_info *info)
{
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_LOADED,
                          uwbd_baseline_load(&store, cfg.evaluate.direct_coupling.window_end_s, NULL, info,
                                             NULL, err, sizeof err));
}

static void test_a_scan_without_baseline_is_archived_with_edges_only(void)
{
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWBD_CYCLE_RECORDED, res.outcome);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_EDGES, res.status);
    TEST_ASSERT_EQUAL_STRING("sim-1", res.scan_id);
    static const char *const files[] = {DAY_DIR "/sim-1.uwbscan",
                                        DAY_DIR "/sim-1.json",
                                        DAY_DIR "/sim-1-migrated.png",
                                        DAY_DIR "/sim-1-bscan.png",
                                        DAY_DIR "/sim-1-comparison.png",
                                        "verdicts.jsonl",
                                        "latest.json"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++)
        TEST_ASSERT_TRUE_MESSAGE(in_state(files[i]), files[i]);
    TEST_ASSERT_FALSE(in_state("baseline/current.uwbscan"));
    char *latest;
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_read(&store, &latest, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING(res.verdict_json, latest);
    free(latest);
    cJSON *v = verdict();
    TEST_ASSERT_NOT_NULL(
        strstr(cJSON_GetObjectItemCaseSensitive(v, "scan_file")->valuestring, "sim-1.uwbscan"));
    TEST_ASSERT_TRUE(number(v, "direct_coupling_ps") > -1000 && number(v, "direct_coupling_ps") < 500);
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(v, "baseline_set"));
    cJSON_Delete(v);
    /* The archived raw scan reads back and carries the archive's name. */
    struct uwb_scan s;
    char p[2048];
    snprintf(p, sizeof p, "%s/" DAY_DIR "/sim-1.uwbscan", store.root);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(p, &s, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("sim-1", s.scan_id);
    uwb_scan_free(&s);
}

static void test_the_baseline_changes_only_when_asked_and_keeps_the_old_one(void)
{
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_set);
    struct uwbd_baseline_info info;
    current_baseline(&info);
    TEST_ASSERT_EQUAL_STRING("sim-1", info.scan_id);
    TEST_ASSERT_TRUE(info.has_direct_coupling);

    rig.displaced = 1;
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, res.status);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_set);
    cJSON *v = verdict();
    TEST_ASSERT_DOUBLE_WITHIN(0.5, 12.0, number(v, "axial_displacement_mm"));
    TEST_ASSERT_DOUBLE_WITHIN(5.0, 0.0, number(v, "direct_coupling_shift_ps"));
    cJSON_Delete(v);
    current_baseline(&info);
    TEST_ASSERT_EQUAL_STRING("sim-1", info.scan_id); /* an alarm does not move the baseline */

    /* ...nor does `baseline set` on an alarm: refused for good, with the reason. */
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ALARM, res.status);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_set);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_refused);
    v = verdict();
    const cJSON *note = cJSON_GetObjectItemCaseSensitive(v, "baseline_note");
    TEST_ASSERT_TRUE(cJSON_IsString(note));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note->valuestring, "refused: this scan is an alarm"),
                                 note->valuestring);
    cJSON_Delete(v);
    current_baseline(&info);
    TEST_ASSERT_EQUAL_STRING("sim-1", info.scan_id);

    rig.displaced = 0;
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_set);
    current_baseline(&info);
    TEST_ASSERT_EQUAL_STRING("sim-4", info.scan_id);
    TEST_ASSERT_TRUE(in_state("baseline/history/sim-1.uwbscan"));
    TEST_ASSERT_TRUE(in_state("baseline/history/sim-1.json"));
    TEST_ASSERT_EQUAL_INT(4, scratch_count_lines(store.verdict_log));
}

/* Make the intact scan the baseline through the store, as a commissioning
 * cycle would, without a cycle's imaging (slow under qemu). */
static void commission_directly(void)
{
    struct uwb_scan scan;
    const volatile sig_atomic_t never = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWBD_ACQUIRE_OK, fake_acquire(&rig, &never, &scan, err, sizeof err), err);
    struct uwbd_baseline_info info = {0};
    snprintf(info.scan_id, sizeof info.scan_id, "%s", scan.scan_id);
    info.has_direct_coupling = uwb_direct_coupling_arrival(&scan, cfg.evaluate.direct_coupling.window_end_s,
                                                           &info.direct_coupling_s, err, sizeof err) == 0;
    TEST_ASSERT_TRUE_MESSAGE(info.has_direct_coupling, err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0,
        uwbd_baseline_set(&store, &scan, &info, cfg.evaluate.direct_coupling.window_end_s, err, sizeof err),
        err);
    uwb_scan_free(&scan);
}

static void test_moved_direct_coupling_is_inconclusive_not_compared(void)
{
    commission_directly();
    rig.delay_samples = 4; /* 40 ps, twice the tolerance */
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_INCONCLUSIVE, res.status);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(res.reason, "direct coupling moved +40 ps"), res.reason);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(res.reason, "cable or antenna changed?"), res.reason);
    cJSON *v = verdict();
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(v, "axial_displacement_mm"));
    /* The evaluation's figure for the move, also when it declined the scan. */
    TEST_ASSERT_DOUBLE_WITHIN(1.0, 40.0, number(v, "direct_coupling_shift_ps"));
    cJSON_Delete(v);

    rig.delay_samples = 1; /* 10 ps: within the tolerance, compared */
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_OK, res.status);
}

static void test_a_lost_scan_is_an_error_verdict_and_the_baseline_stays(void)
{
    commission_directly();
    size_t before_len = 0, after_len = 0;
    char p[2048];
    snprintf(p, sizeof p, "%s/baseline/current.uwbscan", store.root);
    char *before = scratch_slurp(p, &before_len);
    rig.fail = 1;
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(UWBD_CYCLE_RECORDED, res.outcome);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ERROR, res.status);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_set);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(res.reason, "acquisition failed: digitiser: no frame"), res.reason);
    cJSON *v = verdict();
    TEST_ASSERT_EQUAL_STRING("error", cJSON_GetObjectItemCaseSensitive(v, "status")->valuestring);
    cJSON_Delete(v);
    char *after = scratch_slurp(p, &after_len);
    TEST_ASSERT_EQUAL_UINT64(before_len, after_len);
    TEST_ASSERT_EQUAL_MEMORY(before, after, before_len);
    free(before);
    free(after);
    char *latest;
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_read(&store, &latest, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(latest, "\"status\":\"error\""));
    free(latest);
    TEST_ASSERT_EQUAL_INT(1, scratch_count_lines(store.verdict_log));

    rig.fail = 0; /* the next cycle succeeds once the fault is gone */
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_OK, res.status);
}

static void test_a_scan_without_winding_or_coupling_does_not_become_the_baseline(void)
{
    rig.blank = 1;
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_set);
    TEST_ASSERT_FALSE(in_state("baseline/current.uwbscan"));
    if (res.status != UWB_STATUS_ERROR) {
        cJSON *v = verdict();
        const cJSON *note = cJSON_GetObjectItemCaseSensitive(v, "baseline_note");
        TEST_ASSERT_TRUE(cJSON_IsString(note));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note->valuestring, "not set"), note->valuestring);
        cJSON_Delete(v);
    }
}

/* Issue 28, item 1: what the drawings say of the winding's height is held
 * against the face of every scan that would become the baseline, also
 * when one is already set (that scan is compared without it). */
static void test_a_face_away_from_the_drawings_span_does_not_become_the_baseline(void)
{
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_set);
    struct uwbd_baseline_info first;
    current_baseline(&first);
    cfg.evaluate.analysis.has_winding_span = 1;
    cfg.evaluate.analysis.winding_span_m[0] = -0.9;
    cfg.evaluate.analysis.winding_span_m[1] = -0.8;
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_set);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_refused);
    cJSON *v = verdict();
    const cJSON *note = cJSON_GetObjectItemCaseSensitive(v, "baseline_note");
    TEST_ASSERT_TRUE(cJSON_IsString(note));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note->valuestring, "the drawings put the winding at -900..-800 mm"),
                                 note->valuestring);
    cJSON_Delete(v);
    struct uwbd_baseline_info still;
    current_baseline(&still);
    TEST_ASSERT_EQUAL_STRING(first.scan_id, still.scan_id);
}

static void test_a_stopped_scan_records_nothing(void)
{
    rig.stopped = 1;
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(UWBD_CYCLE_STOPPED, res.outcome);
    TEST_ASSERT_NULL(res.verdict_json);
    TEST_ASSERT_FALSE(in_state("verdicts.jsonl"));
    TEST_ASSERT_FALSE(in_state("latest.json"));
    TEST_ASSERT_EQUAL_INT(0, uwbd_archive_count(&store));
}

/* An archive that cannot take the scan (a file where its year directory
 * goes): the scan is still evaluated (issue 43: it was an `error` verdict,
 * which would hide an alarm), its verdict says the archive refused it, and
 * a scan that is not archived does not become the baseline. */
static void test_an_unusable_archive_still_evaluates_the_scan_and_says_so(void)
{
    char p[2048];
    snprintf(p, sizeof p, "%s/archive/2030", store.root);
    scratch_spit(p, "a file where the year directory should be");
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_STATUS_EDGES, res.status, res.reason);
    cJSON *v = verdict();
    const cJSON *why = cJSON_GetObjectItemCaseSensitive(v, "archive_error");
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsString(why), res.verdict_json);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why->valuestring, "archive/2030"), why->valuestring);
    TEST_ASSERT_NULL_MESSAGE(cJSON_GetObjectItemCaseSensitive(v, "scan_file"), res.verdict_json);
    const cJSON *note = cJSON_GetObjectItemCaseSensitive(v, "baseline_note");
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsString(note), res.verdict_json);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note->valuestring, "not set: the scan could not be archived"),
                                 note->valuestring);
    cJSON_Delete(v);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_set);
    TEST_ASSERT_EQUAL_INT(0, res.baseline_refused); /* still pending */
    TEST_ASSERT_FALSE(in_state("baseline/current.uwbscan"));
    TEST_ASSERT_EQUAL_INT(1, scratch_count_lines(store.verdict_log));
}

/* A file of the archive refused after the raw scan went in (a directory
 * stands where the b-scan image goes, as a full disk would refuse it): the
 * measurement stands, the verdict lists only the images written and says
 * which one was not. */
static void test_an_image_the_archive_refuses_is_named_and_the_verdict_kept(void)
{
    char p[2048];
    time_t now = CYCLE_TIME;
    struct tm utc;
    gmtime_r(&now, &utc);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_day_dir(&store, &utc, p, sizeof p, err, sizeof err), err);
    snprintf(p, sizeof p, "%s/" DAY_DIR "/sim-1-bscan.png", store.root);
    TEST_ASSERT_EQUAL_INT(0, mkdir(p, 0755));
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_EDGES, res.status);
    TEST_ASSERT_EQUAL_INT(1, res.archive_problems);
    cJSON *v = verdict();
    const cJSON *why = cJSON_GetObjectItemCaseSensitive(v, "archive_error");
    TEST_ASSERT_TRUE(cJSON_IsString(why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why->valuestring, "sim-1-bscan.png"), why->valuestring);
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(v, "images");
    TEST_ASSERT_EQUAL_INT(1, cJSON_GetArraySize(images));
    TEST_ASSERT_NOT_NULL(strstr(cJSON_GetArrayItem(images, 0)->valuestring, "sim-1-migrated.png"));
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(v, "record_error"));
    cJSON_Delete(v);
    /* The archived verdict and the verdicts.jsonl line are this verdict. */
    snprintf(p, sizeof p, "%s/" DAY_DIR "/sim-1.json", store.root);
    char *archived = scratch_slurp(p, NULL);
    TEST_ASSERT_NOT_NULL(archived);
    TEST_ASSERT_EQUAL_STRING_LEN(res.verdict_json, archived, strlen(res.verdict_json));
    free(archived);
    char **lines = NULL;
    int count = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_tail(&store, 1, &lines, &count, NULL, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_INT(1, count);
    TEST_ASSERT_EQUAL_STRING(res.verdict_json, lines[0]);
    uwbd_verdict_lines_free(lines, count);
}

/* verdicts.jsonl refuses the line (a directory in its place stands for a
 * full or read-only state directory): the verdict the reply and the status
 * carry says it was not recorded and why; latest.json still has it. */
static void test_a_verdict_the_log_refuses_says_so(void)
{
    TEST_ASSERT_EQUAL_INT(0, mkdir(store.verdict_log, 0755));
    rig.fail = 1;
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ERROR, res.status);
    cJSON *v = verdict();
    const cJSON *why = cJSON_GetObjectItemCaseSensitive(v, "record_error");
    TEST_ASSERT_TRUE(cJSON_IsString(why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why->valuestring, "verdicts.jsonl"), why->valuestring);
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(v, "archive_error"));
    cJSON_Delete(v);
    char *latest;
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_read(&store, &latest, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING(res.verdict_json, latest);
    free(latest);
}

/* Temporaries (atomic_file.h) anywhere under the state directory. */
static int temporaries_under(const char *path)
{
    DIR *d = opendir(path);
    if (!d)
        return 0;
    int found = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char sub[2048];
        snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
        struct stat st;
        if (lstat(sub, &st) == 0 && S_ISDIR(st.st_mode))
            found += temporaries_under(sub);
        else if (uwb_atomic_file_is_temporary_name(e->d_name))
            found++;
    }
    closedir(d);
    return found;
}

static char *state_file(const char *rel)
{
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", store.root, rel);
    char *text = scratch_slurp(p, NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(text, p);
    return text;
}

static const char *text_of(const cJSON *v, const char *key)
{
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(v, key);
    return cJSON_IsString(s) ? s->valuestring : NULL;
}

/* Issue 43, break 6: the disk fills in the middle of the archive. The
 * winding moves 12 mm meanwhile: the scan is still evaluated (alarm, not
 * an error), the verdict says what was not written and why, nothing
 * half-written stays, what was recorded before is intact, and once there
 * is room the next scan is archived as ever. Two full cycles: one whose
 * day directory exists (the raw scan's file fails), one on a new day (its
 * directory cannot be made). */
static void test_a_full_disk_still_evaluates_and_leaves_nothing_half_written(void)
{
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_set);
    run_cycle(0);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_STATUS_OK, res.status, res.reason);
    char *log_before = state_file("verdicts.jsonl"), *latest_before = state_file("latest.json");
    char *baseline_before = state_file("baseline/current.json");
    rig.displaced = 1;
    const time_t days[2] = {CYCLE_TIME + 60, CYCLE_TIME + 86400};
    for (int i = 0; i < 2; i++) {
        uwbd_cycle_result_free(&res);
        struct uwbd_cycle_request req = {.now = days[i]};
        disk_full = 1;
        int rc = uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res);
        disk_full = 0;
        TEST_ASSERT_EQUAL_INT(0, rc);
        TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_STATUS_ALARM, res.status, res.reason);
        cJSON *v = verdict();
        TEST_ASSERT_TRUE_MESSAGE(fabs(number(v, "axial_displacement_mm") - 12.0) < 1.0, res.verdict_json);
        const char *archive_error = text_of(v, "archive_error"), *record_error = text_of(v, "record_error");
        TEST_ASSERT_NOT_NULL_MESSAGE(archive_error, res.verdict_json);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(archive_error, "No space left on device"), archive_error);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(archive_error, i == 0 ? ".uwbscan" : "archive/2030/01/03"),
                                     archive_error);
        TEST_ASSERT_NOT_NULL_MESSAGE(record_error, res.verdict_json);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(record_error, "verdicts.jsonl"), record_error);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(record_error, "No space left on device"), record_error);
        /* It names no file that is not there. */
        TEST_ASSERT_NULL_MESSAGE(cJSON_GetObjectItemCaseSensitive(v, "scan_file"), res.verdict_json);
        TEST_ASSERT_EQUAL_INT(0, cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(v, "images")));
        cJSON_Delete(v);
        /* What the daemon's `status` is told: the cycle's first failed write. */
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(res.write_error, "No space left on device"), res.write_error);
        TEST_ASSERT_EQUAL_INT(0, temporaries_under(store.root));
        char *log_now = state_file("verdicts.jsonl"), *latest_now = state_file("latest.json");
        char *baseline_now = state_file("baseline/current.json");
        TEST_ASSERT_EQUAL_STRING(log_before, log_now);
        TEST_ASSERT_EQUAL_STRING(latest_before, latest_now);
        TEST_ASSERT_EQUAL_STRING(baseline_before, baseline_now);
        free(log_now);
        free(latest_now);
        free(baseline_now);
    }
    TEST_ASSERT_FALSE(in_state(DAY_DIR "/sim-3.uwbscan"));
    TEST_ASSERT_FALSE(in_state(DAY_DIR "/sim-3.json"));
    TEST_ASSERT_FALSE(in_state("archive/2030/01/03"));
    free(log_before);
    free(latest_before);
    free(baseline_before);

    /* Room again: archived as ever. */
    uwbd_cycle_result_free(&res);
    struct uwbd_cycle_request req = {.now = CYCLE_TIME + 2 * 86400};
    TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_STATUS_ALARM, res.status, res.reason);
    TEST_ASSERT_EQUAL_STRING("", res.write_error);
    cJSON *v = verdict();
    TEST_ASSERT_NULL_MESSAGE(cJSON_GetObjectItemCaseSensitive(v, "archive_error"), res.verdict_json);
    TEST_ASSERT_NULL_MESSAGE(cJSON_GetObjectItemCaseSensitive(v, "record_error"), res.verdict_json);
    TEST_ASSERT_TRUE(scratch_file_exists(text_of(v, "scan_file")));
    cJSON_Delete(v);
    TEST_ASSERT_EQUAL_INT(3, scratch_count_lines(store.verdict_log));
    char **lines = NULL;
    int count = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_tail(&store, 1, &lines, &count, NULL, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_INT(1, count);
    TEST_ASSERT_EQUAL_STRING(res.verdict_json, lines[0]);
    uwbd_verdict_lines_free(lines, count);
}

/* Lost scans keep the cycles cheap here: each leaves its verdict file,
 * which is what retention counts (test_daemon_store covers whole scans). */
/* Issue 17, break 3: a scan dated before the newest recorded one (the
 * clock went back, e.g. a board without RTC booting in 1970) is flagged in
 * its verdict, not silently archived out of order. */
static void test_a_scan_dated_before_the_newest_is_flagged(void)
{
    rig.fail = 1; /* error verdicts are quick, and flagged like any other */
    struct uwbd_cycle_request req = {.now = CYCLE_TIME};
    TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
    TEST_ASSERT_NULL_MESSAGE(strstr(res.verdict_json, "clock_warning"), res.verdict_json);
    uwbd_cycle_result_free(&res);
    req.now = CYCLE_TIME - 3600;
    TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
    cJSON *v = verdict();
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(v, "clock_warning");
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsString(w), res.verdict_json);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(w->valuestring, "earlier than the newest recorded scan"),
                                 w->valuestring);
    cJSON_Delete(v);
    uwbd_cycle_result_free(&res);
    req.now = CYCLE_TIME + 60; /* later again: no flag */
    TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
    TEST_ASSERT_NULL_MESSAGE(strstr(res.verdict_json, "clock_warning"), res.verdict_json);
}

static void test_retention_runs_after_each_cycle(void)
{
    cfg.retention_max_scans = 2;
    rig.fail = 1;
    char first[UWBD_SCAN_ID_MAX + 1], path[256];
    for (int i = 0; i < 3; i++) {
        struct uwbd_cycle_request req = {.now = CYCLE_TIME + i};
        uwbd_cycle_result_free(&res);
        TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
        if (i == 0)
            snprintf(first, sizeof first, "%s", res.scan_id);
    }
    TEST_ASSERT_EQUAL_INT(2, uwbd_archive_count(&store));
    snprintf(path, sizeof path, DAY_DIR "/%s.json", first);
    TEST_ASSERT_FALSE(in_state(path));
    snprintf(path, sizeof path, DAY_DIR "/%s.json", res.scan_id);
    TEST_ASSERT_TRUE(in_state(path));
    /* verdicts.jsonl keeps the same span as the archive. */
    TEST_ASSERT_EQUAL_INT(2, scratch_count_lines(store.verdict_log));
}

/* The Description text of an archived PNG ("" when there is none). */
static void png_description(const char *rel, char *out, size_t n)
{
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", store.root, rel);
    out[0] = '\0';
    FILE *fp = fopen(p, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, p);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    TEST_ASSERT_EQUAL_INT(0, setjmp(png_jmpbuf(png)));
    png_init_io(png, fp);
    png_read_info(png, info);
    png_textp texts;
    int count = 0;
    png_get_text(png, info, &texts, &count);
    for (int i = 0; i < count; i++)
        if (!strcmp(texts[i].key, "Description"))
            snprintf(out, n, "%s", texts[i].text);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
}

/* A commissioning scan's images say it became the baseline, not that none
 * was given; a scan without a baseline that was not asked to become one
 * still says "no baseline given". */
static void test_a_commissioning_scan_s_images_say_it_became_the_baseline(void)
{
    char d[4096];
    run_cycle(0);
    png_description(DAY_DIR "/sim-1-comparison.png", d, sizeof d);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "no baseline given"), d);
    TEST_ASSERT_NULL_MESSAGE(strstr(d, "became the baseline"), d);
    run_cycle(1);
    TEST_ASSERT_EQUAL_INT(1, res.baseline_set);
    static const char *const kinds[] = {"migrated", "bscan", "comparison"};
    for (int i = 0; i < 3; i++) {
        char rel[256];
        snprintf(rel, sizeof rel, DAY_DIR "/%s-%s.png", res.scan_id, kinds[i]);
        png_description(rel, d, sizeof d);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "edges only: this scan became the baseline"), d);
        TEST_ASSERT_NULL_MESSAGE(strstr(d, "no baseline given"), d);
    }
}

/* With site.asset_id set, the scan's id starts with it, so the archive's
 * file names, the verdict's scan_id and every log line about the scan
 * (they name it by its id) say which asset it is; the images' Asset text
 * names it too. */
static void test_the_asset_id_names_the_scan_and_its_archive_files(void)
{
    snprintf(cfg.site.asset_id, sizeof cfg.site.asset_id, "T3-north");
    run_cycle(0);
    cfg.site.asset_id[0] = '\0';
    TEST_ASSERT_EQUAL_STRING("T3-north-sim-1", res.scan_id);
    static const char *const files[] = {DAY_DIR "/T3-north-sim-1.uwbscan", DAY_DIR "/T3-north-sim-1.json",
                                        DAY_DIR "/T3-north-sim-1-migrated.png",
                                        DAY_DIR "/T3-north-sim-1-comparison.png"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++)
        TEST_ASSERT_TRUE_MESSAGE(in_state(files[i]), files[i]);
    TEST_ASSERT_FALSE(in_state(DAY_DIR "/sim-1.uwbscan"));
    cJSON *v = verdict();
    TEST_ASSERT_EQUAL_STRING("T3-north-sim-1", cJSON_GetObjectItemCaseSensitive(v, "scan_id")->valuestring);
    cJSON_Delete(v);
    char d[4096];
    png_description(DAY_DIR "/T3-north-sim-1-migrated.png", d, sizeof d);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "scan T3-north-sim-1 "), d);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(d, "asset T3-north"), d);
}

/* Issue 48, finding 4: a cycle that made no scan (an error verdict) is
 * named in the rig's form, asset first, to the millisecond: it was
 * "T3-north-uwbd-20300102T000000Z" beside the rig's
 * "T3-north-uwb-20300102T000000.000Z". */
static void test_an_error_verdict_has_the_scans_form_of_id(void)
{
    snprintf(cfg.site.asset_id, sizeof cfg.site.asset_id, "T3-north");
    rig.fail = 1;
    uwbd_cycle_result_free(&res);
    struct uwbd_cycle_request req = {.now = CYCLE_TIME, .now_ms = 813};
    TEST_ASSERT_EQUAL_INT(0, uwbd_cycle_run(&cfg, &store, fake_acquire, &rig, NULL, &req, &res));
    cfg.site.asset_id[0] = '\0';
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_ERROR, res.status);
    TEST_ASSERT_EQUAL_STRING("T3-north-uwb-20300102T000000.813Z", res.scan_id);
    cJSON *v = verdict();
    TEST_ASSERT_EQUAL_STRING("T3-north-uwb-20300102T000000.813Z",
                             cJSON_GetObjectItemCaseSensitive(v, "scan_id")->valuestring);
    cJSON_Delete(v);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_scan_without_baseline_is_archived_with_edges_only);
    RUN_TEST(test_the_baseline_changes_only_when_asked_and_keeps_the_old_one);
    RUN_TEST(test_a_commissioning_scan_s_images_say_it_became_the_baseline);
    RUN_TEST(test_the_asset_id_names_the_scan_and_its_archive_files);
    RUN_TEST(test_an_error_verdict_has_the_scans_form_of_id);
    RUN_TEST(test_moved_direct_coupling_is_inconclusive_not_compared);
    RUN_TEST(test_a_lost_scan_is_an_error_verdict_and_the_baseline_stays);
    RUN_TEST(test_a_scan_without_winding_or_coupling_does_not_become_the_baseline);
    RUN_TEST(test_a_face_away_from_the_drawings_span_does_not_become_the_baseline);
    RUN_TEST(test_a_stopped_scan_records_nothing);
    RUN_TEST(test_an_unusable_archive_still_evaluates_the_scan_and_says_so);
    RUN_TEST(test_an_image_the_archive_refuses_is_named_and_the_verdict_kept);
    RUN_TEST(test_a_verdict_the_log_refuses_says_so);
    RUN_TEST(test_a_full_disk_still_evaluates_and_leaves_nothing_half_written);
    RUN_TEST(test_retention_runs_after_each_cycle);
    RUN_TEST(test_a_scan_dated_before_the_newest_is_flagged);
    uwb_scan_free(&simulated[0]);
    uwb_scan_free(&simulated[1]);
    return UNITY_END();
}
