/* The state directory: verdicts.jsonl only ever holds whole lines and its
 * reader survives a torn one; latest.json; the baseline changes only when
 * set, keeping the one it replaces, and survives a crash between its two
 * files; retention deletes the oldest scans and never a baseline. */
#include "unity.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <unistd.h>

#include "scratch_support.h"
#include "uwb/atomic_file.h"
#include "state/baseline_store.h"
#include "state/retention.h"
#include "state/state_open.h"
#include "state/store.h"
#include "state/verdict_log.h"
#include "uwb/direct_coupling.h"

#define WINDOW_END_S 2e-9

static char dir[64];
static char err[2048];
static struct uwbd_store store;

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "store");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, NULL, err, sizeof err), err);
}

void tearDown(void)
{
    scratch_remove_tree(dir);
}

static void path_in(char *out, size_t n, const char *rel)
{
    snprintf(out, n, "%s/%s", store.root, rel);
}

/* A small scan whose direct coupling (a pulse) peaks at `pulse_sample`. */
static void make_scan(struct uwb_scan *s, const char *id, int pulse_sample, float fill)
{
    TEST_ASSERT_EQUAL_INT(0, uwb_scan_alloc(s, 4, 256, err, sizeof err));
    s->sample_interval_s = 10e-12;
    s->t0_s = -1e-9;
    s->eps_r = 2.2;
    for (int k = 0; k < 4; k++) {
        s->antenna_y_m[k] = 0.03 * k;
        for (int i = 0; i < 256; i++) {
            double x = (i - pulse_sample) / 4.0;
            s->data[k * 256 + i] = (float)(exp(-x * x) + fill);
        }
    }
    s->scan_id = strdup(id);
    s->created = strdup("2030-01-02T03:04:05Z");
}

static void test_open_makes_the_layout(void)
{
    char p[2048];
    static const char *const dirs[] = {"archive", "baseline", "baseline/history"};
    for (size_t i = 0; i < 3; i++) {
        path_in(p, sizeof p, dirs[i]);
        struct stat st;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, stat(p, &st), p);
        TEST_ASSERT_TRUE(S_ISDIR(st.st_mode));
    }
    TEST_ASSERT_EQUAL_INT('/', store.root[0]);
}

static void test_open_removes_leftover_temporaries_only(void)
{
    char p[2048];
    path_in(p, sizeof p, ATOMIC_FILE_TEMP_PREFIX "latest.json.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX);
    scratch_spit(p, "{\"half");
    path_in(p, sizeof p,
            "baseline/" ATOMIC_FILE_TEMP_PREFIX "current.uwbscan.zzzzzz" ATOMIC_FILE_TEMP_SUFFIX);
    scratch_spit(p, "half");
    path_in(p, sizeof p, "keep.txt");
    scratch_spit(p, "mine");
    int repairs = 0;
    TEST_ASSERT_EQUAL_INT(0, uwbd_store_open(&store, dir, &repairs, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(2, repairs);
    path_in(p, sizeof p, ATOMIC_FILE_TEMP_PREFIX "latest.json.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX);
    TEST_ASSERT_FALSE(scratch_file_exists(p));
    path_in(p, sizeof p,
            "baseline/" ATOMIC_FILE_TEMP_PREFIX "current.uwbscan.zzzzzz" ATOMIC_FILE_TEMP_SUFFIX);
    TEST_ASSERT_FALSE(scratch_file_exists(p));
    path_in(p, sizeof p, "keep.txt");
    TEST_ASSERT_TRUE(scratch_file_exists(p));
}

/* Issue 17, break 1: a state_dir holding someone else's tree lost every
 * file named like ".X.YYYYYY" four levels down. Now only our own temporary
 * names, only in the directories uwbd writes, never through a symlink. */
static void test_open_touches_nothing_that_is_not_ours(void)
{
    static const char *const foreign[] = {
        "home/alice/.bashrc.backup",
        "etc/.shadow.swp123",
        ".config/app/.settings.json~1",
        "var/lib/db/.journal.000001",
        ".latest.json.Ab12Cd",
        "baseline/.current.uwbscan.zzzzzz",
        "archive/2026/01/01/.scan.json.Ab12Cd",
        /* our name, but not in a directory uwbd writes */
        "home/alice/" ATOMIC_FILE_TEMP_PREFIX "x.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX,
        "archive/notes/" ATOMIC_FILE_TEMP_PREFIX "x.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX,
    };
    char p[2048], outside[96], link[2048];
    for (size_t i = 0; i < sizeof foreign / sizeof foreign[0]; i++) {
        path_in(p, sizeof p, foreign[i]);
        for (char *s = p + strlen(store.root) + 1; *s; s++)
            if (*s == '/') {
                *s = '\0';
                mkdir(p, 0755);
                *s = '/';
            }
        scratch_spit(p, "not uwbd's");
    }
    /* A day directory and baseline/history that are symlinks to elsewhere. */
    scratch_scratch_dir(outside, sizeof outside, "store-outside");
    char victim[256];
    snprintf(victim, sizeof victim, "%s/" ATOMIC_FILE_TEMP_PREFIX "y.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX,
             outside);
    scratch_spit(victim, "elsewhere");
    path_in(link, sizeof link, "archive/2026/01/02");
    TEST_ASSERT_EQUAL_INT(0, symlink(outside, link));
    path_in(link, sizeof link, "archive/2027");
    TEST_ASSERT_EQUAL_INT(0, symlink(outside, link));
    int repairs = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, &repairs, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, repairs);
    for (size_t i = 0; i < sizeof foreign / sizeof foreign[0]; i++) {
        path_in(p, sizeof p, foreign[i]);
        TEST_ASSERT_TRUE_MESSAGE(scratch_file_exists(p), foreign[i]);
    }
    TEST_ASSERT_TRUE_MESSAGE(scratch_file_exists(victim), victim);
    scratch_remove_tree(outside);
}

/* A state directory that cannot be used is refused with its name and the
 * reason, before anything is written: a path too long for the store's
 * buffers, a file where a directory must be, and an archive day
 * directory that would not fit the caller's buffer. */
static void test_unusable_state_paths_are_refused_by_name(void)
{
    char longdir[1200];
    int w = snprintf(longdir, sizeof longdir, "%s/", dir);
    memset(longdir + w, 'a', sizeof longdir - (size_t)w - 1);
    longdir[sizeof longdir - 1] = '\0';
    struct uwbd_store other;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_open(&other, longdir, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "...: path too long"), err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(err, dir, strlen(dir)));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_lock(longdir, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "...: path too long"), err);

    char file[128];
    snprintf(file, sizeof file, "%s/plain-file", dir);
    scratch_spit(file, "not a directory");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_open(&other, file, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "plain-file: exists but is not a directory"), err);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_lock(file, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "plain-file"), err);

    struct tm day = {.tm_year = 126, .tm_mon = 10, .tm_mday = 24};
    char small[16];
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_day_dir(&store, &day, small, sizeof small, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "archive path too long"), err);
    char fits[2048];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_day_dir(&store, &day, fits, sizeof fits, err, sizeof err),
                                  err);
    TEST_ASSERT_NOT_NULL(strstr(fits, "/archive/2026/11/24"));
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(fits, &st));
    TEST_ASSERT_TRUE(S_ISDIR(st.st_mode));
}

/* Past the first few, foreign files are counted, not each named; all are
 * left alone. */
static void test_many_foreign_files_are_all_left_alone(void)
{
    char p[2048];
    for (int i = 0; i < 12; i++) {
        char rel[32];
        snprintf(rel, sizeof rel, ".foreign-%d", i);
        path_in(p, sizeof p, rel);
        scratch_spit(p, "not uwbd's");
    }
    int repairs = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, &repairs, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, repairs);
    for (int i = 0; i < 12; i++) {
        char rel[32];
        snprintf(rel, sizeof rel, ".foreign-%d", i);
        path_in(p, sizeof p, rel);
        TEST_ASSERT_TRUE_MESSAGE(scratch_file_exists(p), rel);
    }
}

static void test_verdict_log_appends_whole_lines_and_reads_the_tail(void)
{
    char line[64];
    for (int i = 1; i <= 5; i++) {
        snprintf(line, sizeof line, "{\"class\":\"VERDICT\",\"n\":%d}", i);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_append(&store, line, err, sizeof err), err);
    }
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_append(&store, "{\"a\":1}\n{\"b\":2}", err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(err, "verdicts.jsonl: refusing to append an empty or multi-line record"), err);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_append(&store, "", err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "refusing to append an empty or multi-line record"), err);
    TEST_ASSERT_EQUAL_INT(5, scratch_count_lines(store.verdict_log));
    char **lines;
    int count, skipped;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 3, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(3, count);
    TEST_ASSERT_EQUAL_INT(0, skipped);
    TEST_ASSERT_EQUAL_STRING("{\"class\":\"VERDICT\",\"n\":3}", lines[0]);
    TEST_ASSERT_EQUAL_STRING("{\"class\":\"VERDICT\",\"n\":5}", lines[2]);
    uwbd_verdict_lines_free(lines, count);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 100, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(5, count);
    uwbd_verdict_lines_free(lines, count);
}

/* What a crash mid-write could leave: the reader skips the torn and the
 * damaged lines and counts them; opening the store cuts the torn tail so
 * the next append starts a clean line. */
static void test_torn_and_damaged_lines_are_tolerated_and_repaired(void)
{
    scratch_spit(store.verdict_log, "{\"n\":1}\n{\"n\":2, oops\n{\"n\":3}\n{\"n\":4,\"cut\":\"in the mid");
    char **lines;
    int count, skipped;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 10, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(2, count);
    TEST_ASSERT_EQUAL_INT(2, skipped);
    TEST_ASSERT_EQUAL_STRING("{\"n\":1}", lines[0]);
    TEST_ASSERT_EQUAL_STRING("{\"n\":3}", lines[1]);
    uwbd_verdict_lines_free(lines, count);

    int repairs = 0;
    TEST_ASSERT_EQUAL_INT(0, uwbd_state_open(&store, dir, &repairs, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, repairs);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, "{\"n\":5}", err, sizeof err));
    char *text = scratch_slurp(store.verdict_log, NULL);
    TEST_ASSERT_EQUAL_STRING("{\"n\":1}\n{\"n\":2, oops\n{\"n\":3}\n{\"n\":5}\n", text);
    free(text);
}

static void test_tail_reads_far_back_through_long_files(void)
{
    /* Long lines so the tail needs several 64 KiB blocks. */
    char *line = malloc(20000);
    for (int i = 0; i < 30; i++) {
        int n = snprintf(line, 20000, "{\"n\":%d,\"pad\":\"", i);
        memset(line + n, 'x', 15000);
        strcpy(line + n + 15000, "\"}");
        TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, line, err, sizeof err));
    }
    free(line);
    char **lines;
    int count, skipped;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 12, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(12, count);
    TEST_ASSERT_EQUAL_INT(0, skipped);
    TEST_ASSERT_EQUAL_INT(0, strncmp(lines[0], "{\"n\":18,", 8));
    TEST_ASSERT_EQUAL_INT(0, strncmp(lines[11], "{\"n\":29,", 8));
    uwbd_verdict_lines_free(lines, count);
}

static void test_latest_is_replaced_whole(void)
{
    char *json;
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_NULL(json);
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_write(&store, "{\"class\":\"VERDICT\",\"n\":1}", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_write(&store, "{\"class\":\"VERDICT\",\"n\":2}", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("{\"class\":\"VERDICT\",\"n\":2}", json);
    free(json);
    scratch_spit(store.latest, "{\"class\":");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_latest_read(&store, &json, err, sizeof err));
}

/* The time zero recorded is the scan's own (the loader checks it against the scan). */
static double own_direct_coupling(const struct uwb_scan *scan)
{
    double arrival = 0;
    char why[160];
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwb_direct_coupling_arrival(scan, WINDOW_END_S, &arrival, why, sizeof why), why);
    return arrival;
}

static void set_baseline(const struct uwb_scan *scan)
{
    double dc_s = own_direct_coupling(scan);
    struct uwbd_baseline_info info = {0};
    snprintf(info.scan_id, sizeof info.scan_id, "%s", scan->scan_id);
    snprintf(info.set_at, sizeof info.set_at, "2030-01-02T04:00:00Z");
    info.has_direct_coupling = 1;
    info.direct_coupling_s = dc_s;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_baseline_set(&store, scan, &info, WINDOW_END_S, err, sizeof err),
                                  err);
}

static void test_baseline_set_keeps_the_one_it_replaces(void)
{
    struct uwb_scan a = {0}, b = {0}, got = {0};
    struct uwbd_baseline_info info;
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_NONE,
                          uwbd_baseline_load(&store, WINDOW_END_S, &got, &info, NULL, err, sizeof err));
    make_scan(&a, "scan-a", 100, 0.0f);
    make_scan(&b, "scan-b", 100, 0.25f);
    set_baseline(&a);
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_LOADED,
                          uwbd_baseline_load(&store, WINDOW_END_S, &got, &info, NULL, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan-a", info.scan_id);
    TEST_ASSERT_TRUE(info.has_direct_coupling);
    /* a's pulse peaks at t0 + 100 dt = 0; less its mean, it reaches half height 32.6 ps before */
    TEST_ASSERT_DOUBLE_WITHIN(2e-12, -32.6e-12, info.direct_coupling_s);
    uwb_scan_free(&got);

    set_baseline(&b);
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_LOADED,
                          uwbd_baseline_load(&store, WINDOW_END_S, &got, &info, NULL, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("scan-b", info.scan_id);
    TEST_ASSERT_EQUAL_FLOAT(b.data[7], got.data[7]);
    uwb_scan_free(&got);

    char p[2048];
    path_in(p, sizeof p, "baseline/history/scan-a.uwbscan");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(p, &got, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("scan-a", got.scan_id);
    TEST_ASSERT_EQUAL_FLOAT(a.data[7], got.data[7]);
    uwb_scan_free(&got);
    path_in(p, sizeof p, "baseline/history/scan-a.json");
    char *json = scratch_slurp(p, NULL);
    TEST_ASSERT_NOT_NULL(json);
    TEST_ASSERT_NOT_NULL(strstr(json, "\"direct_coupling_ps\":-32."));
    free(json);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
}

/* A crash after current.uwbscan was replaced but before current.json: the
 * scan is the truth and its description is rebuilt from it. */
static void test_baseline_description_is_rebuilt_after_a_crash(void)
{
    struct uwb_scan a = {0}, b = {0};
    make_scan(&a, "scan-a", 100, 0.0f);
    make_scan(&b, "scan-b", 150, 0.0f);
    set_baseline(&a);
    char p[2048];
    path_in(p, sizeof p, "baseline/current.uwbscan");
    TEST_ASSERT_EQUAL_INT(0, uwbscan_write_file(p, &b, err, sizeof err)); /* the crash: json still says a */
    struct uwbd_baseline_info info;
    int repaired = 0;
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_LOADED,
                          uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, &repaired, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, repaired);
    TEST_ASSERT_EQUAL_STRING("scan-b", info.scan_id);
    TEST_ASSERT_TRUE(info.has_direct_coupling);
    /* b's pulse exp(-((i - 150) / 4)^2) peaks at t0 + 150 dt = 0.5 ns; less its mean over the
     * record, it reaches half height 3.26 samples before the peak. */
    TEST_ASSERT_DOUBLE_WITHIN(2e-12, 0.5e-9 - 32.6e-12, info.direct_coupling_s);
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_LOADED,
                          uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, &repaired, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, repaired);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
}

/* current.json cannot be written (a directory in its place stands for a
 * full disk) after current.uwbscan went in: the new scan is the baseline
 * all the same, loads with the description taken from it, and the file is
 * rebuilt once it can be written. */
static void test_baseline_set_counts_once_its_scan_is_in_place(void)
{
    struct uwb_scan a = {0}, b = {0};
    make_scan(&a, "scan-a", 100, 0.0f);
    make_scan(&b, "scan-b", 150, 0.0f);
    set_baseline(&a);
    char info_path[2048];
    path_in(info_path, sizeof info_path, "baseline/current.json");
    TEST_ASSERT_EQUAL_INT(0, unlink(info_path));
    TEST_ASSERT_EQUAL_INT(0, mkdir(info_path, 0755));

    struct uwbd_baseline_info info = {0};
    snprintf(info.scan_id, sizeof info.scan_id, "scan-b");
    info.has_direct_coupling = 1;
    info.direct_coupling_s = 4.7e-10;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_baseline_set(&store, &b, &info, WINDOW_END_S, err, sizeof err),
                                  err);
    int repaired = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        UWBD_BASELINE_LOADED,
        uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, &repaired, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("scan-b", info.scan_id);
    TEST_ASSERT_TRUE(info.has_direct_coupling);
    TEST_ASSERT_DOUBLE_WITHIN(2e-12, 0.5e-9 - 32.6e-12, info.direct_coupling_s); /* as in the test above */
    TEST_ASSERT_EQUAL_INT(0, repaired); /* not written: nothing repaired yet */
    char p[2048];
    path_in(p, sizeof p, "baseline/history/scan-a.uwbscan");
    TEST_ASSERT_TRUE(scratch_file_exists(p));

    TEST_ASSERT_EQUAL_INT(0, rmdir(info_path)); /* the disk has room again */
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_LOADED,
                          uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, &repaired, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, repaired);
    char *json = scratch_slurp(info_path, NULL);
    TEST_ASSERT_NOT_NULL(json);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(json, "\"scan_id\":\"scan-b\""), json);
    free(json);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
}

static void test_damaged_baseline_is_an_error_not_a_silent_replacement(void)
{
    char p[2048];
    path_in(p, sizeof p, "baseline/current.uwbscan");
    scratch_spit(p, "{\"format\":\"uwbscan/1\"}\n");
    struct uwbd_baseline_info info;
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_ERROR,
                          uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "current.uwbscan"), err);
}

/* An archived scan: its files, dated `age_days` ago. */
static void archive_scan(const char *day, const char *id, double age_days)
{
    static const char *const suffixes[] = {".uwbscan", ".json", "-migrated.png", "-bscan.png"};
    char d[2048], p[2300];
    snprintf(d, sizeof d, "%s/%s", store.archive, day);
    char cmd[2400];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", d);
    TEST_ASSERT_EQUAL_INT(0, system(cmd));
    struct timeval tv[2];
    gettimeofday(&tv[0], NULL);
    tv[0].tv_sec -= (time_t)(age_days * 86400);
    tv[1] = tv[0];
    for (size_t i = 0; i < 4; i++) {
        snprintf(p, sizeof p, "%s/%s%s", d, id, suffixes[i]);
        scratch_spit(p, "x");
        TEST_ASSERT_EQUAL_INT(0, utimes(p, tv));
    }
}

static int archived(const char *day, const char *id, const char *suffix)
{
    char p[2300];
    snprintf(p, sizeof p, "%s/%s/%s%s", store.archive, day, id, suffix);
    return scratch_file_exists(p);
}

static void test_retention_by_count_deletes_the_oldest_and_spares_baselines(void)
{
    struct uwb_scan a = {0};
    make_scan(&a, "a", 100, 0.0f);
    set_baseline(&a);
    archive_scan("2030/01/01", "a", 5);
    archive_scan("2030/01/01", "a-2", 4); /* its name begins like a's: not a's images */
    archive_scan("2030/01/02", "b", 3);
    archive_scan("2030/01/03", "c", 2);
    archive_scan("2030/01/03", "d", 1);
    TEST_ASSERT_EQUAL_INT(5, uwbd_archive_count(&store));
    int removed = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply(&store, 3, 0, time(NULL), 1, &removed, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(2, removed);
    TEST_ASSERT_EQUAL_INT(3, uwbd_archive_count(&store));
    TEST_ASSERT_FALSE(archived("2030/01/01", "a", ".uwbscan"));
    TEST_ASSERT_FALSE(archived("2030/01/01", "a", "-migrated.png"));
    TEST_ASSERT_FALSE(archived("2030/01/01", "a-2", ".json"));
    TEST_ASSERT_TRUE(archived("2030/01/02", "b", ".json"));
    TEST_ASSERT_TRUE(archived("2030/01/03", "d", "-bscan.png"));
    /* The emptied day directory went too; the baseline stayed. */
    char p[2048];
    snprintf(p, sizeof p, "%s/2030/01/01", store.archive);
    TEST_ASSERT_FALSE(scratch_file_exists(p));
    path_in(p, sizeof p, "baseline/current.uwbscan");
    TEST_ASSERT_TRUE(scratch_file_exists(p));
    uwb_scan_free(&a);
}

static void test_retention_keeps_a_scan_whose_name_begins_like_a_deleted_one(void)
{
    archive_scan("2030/01/01", "a", 5);
    archive_scan("2030/01/01", "a-2", 1);
    int removed = 0;
    TEST_ASSERT_EQUAL_INT(0, uwbd_retention_apply(&store, 1, 0, time(NULL), 1, &removed, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, removed);
    TEST_ASSERT_FALSE(archived("2030/01/01", "a", ".json"));
    TEST_ASSERT_TRUE(archived("2030/01/01", "a-2", ".json"));
    TEST_ASSERT_TRUE(archived("2030/01/01", "a-2", "-migrated.png"));
}

static void test_retention_by_age(void)
{
    archive_scan("2030/01/01", "old", 40);
    archive_scan("2030/01/02", "older", 50);
    archive_scan("2030/01/03", "new", 10);
    int removed = 0;
    TEST_ASSERT_EQUAL_INT(0, uwbd_retention_apply(&store, 0, 30, time(NULL), 1, &removed, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(2, removed);
    TEST_ASSERT_TRUE(archived("2030/01/03", "new", ".uwbscan"));
    TEST_ASSERT_EQUAL_INT(1, uwbd_archive_count(&store));
    TEST_ASSERT_EQUAL_INT(0, uwbd_retention_apply(&store, 0, 0, time(NULL), 1, &removed, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, removed);
}

/* Issue 17, break 3: one scan dated a year ahead (max_age_days 30) deleted
 * all 20 archived scans and all but one line of verdicts.jsonl. Age counts
 * only while the clock is synchronised; it never deletes the newest scan. */
static void test_retention_by_age_waits_for_a_synchronised_clock(void)
{
    char day[16], id[16], line[128], p[2048];
    path_in(p, sizeof p, "verdicts.jsonl");
    for (int i = 0; i < 20; i++) {
        snprintf(day, sizeof day, "2030/01/%02d", 1 + i);
        snprintf(id, sizeof id, "s%02d", i);
        archive_scan(day, id, 20 - i);
        char created[64];
        uwbd_utc_text(time(NULL) - (time_t)(20 - i) * 86400, created, sizeof created);
        snprintf(line, sizeof line, "{\"scan_id\":\"%s\",\"created\":\"%s\"}", id, created);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_append(&store, line, err, sizeof err), err);
    }
    time_t a_year_ahead = time(NULL) + 365 * 86400;
    int removed = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply(&store, 0, 30, a_year_ahead, 0, &removed, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, removed);
    TEST_ASSERT_EQUAL_INT(20, uwbd_archive_count(&store));
    TEST_ASSERT_EQUAL_INT(20, scratch_count_lines(p));
    /* Synchronised, the same clock is trusted, but the newest scan stays. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply(&store, 0, 30, a_year_ahead, 1, &removed, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(19, removed);
    TEST_ASSERT_EQUAL_INT(1, uwbd_archive_count(&store));
    TEST_ASSERT_TRUE(archived("2030/01/20", "s19", ".json"));
}

/* Issue 17, break 7: a day directory archive/2001/01/01 -> elsewhere, and
 * retention deleted the files there. */
static void test_retention_never_follows_a_symlink(void)
{
    char outside[96], p[2048], target[256];
    scratch_scratch_dir(outside, sizeof outside, "retention-outside");
    static const char *const theirs[] = {"x.json", "x.uwbscan", "x-bscan.png", "y.json"};
    for (size_t i = 0; i < 4; i++) {
        snprintf(target, sizeof target, "%s/%s", outside, theirs[i]);
        scratch_spit(target, "not uwbd's");
        struct timeval tv[2] = {{1000000000, 0}, {1000000000, 0}}; /* 2001: the oldest of all */
        TEST_ASSERT_EQUAL_INT(0, utimes(target, tv));
    }
    archive_scan("2030/01/01", "mine", 1);
    path_in(p, sizeof p, "archive/2001/01");
    char cmd[4400];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s' '%s/2001/01/02'", p, store.archive);
    TEST_ASSERT_EQUAL_INT(0, system(cmd));
    path_in(p, sizeof p, "archive/2001/01/01");
    TEST_ASSERT_EQUAL_INT(0, symlink(outside, p)); /* a day directory elsewhere */
    snprintf(target, sizeof target, "%s/y.json", outside);
    path_in(p, sizeof p, "archive/2001/01/02/y.json");
    TEST_ASSERT_EQUAL_INT(0, symlink(target, p)); /* a verdict file elsewhere */
    TEST_ASSERT_EQUAL_INT(1, uwbd_archive_count(&store));
    int removed = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply(&store, 1, 30, time(NULL), 1, &removed, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, removed);
    for (size_t i = 0; i < 4; i++) {
        snprintf(target, sizeof target, "%s/%s", outside, theirs[i]);
        TEST_ASSERT_TRUE_MESSAGE(scratch_file_exists(target), target);
    }
    TEST_ASSERT_TRUE(archived("2030/01/01", "mine", ".json"));
    scratch_remove_tree(outside);
}

/* Issue 17, break 7: verdicts.jsonl -> another file: verdicts were appended
 * to it, and its last line was cut at the next start. */
static void test_verdict_log_and_latest_are_never_written_through_a_symlink(void)
{
    char outside[96], victim[256], p[2048];
    scratch_scratch_dir(outside, sizeof outside, "verdicts-outside");
    snprintf(victim, sizeof victim, "%s/notes.txt", outside);
    scratch_spit(victim, "someone's file without a final newline");
    path_in(p, sizeof p, "verdicts.jsonl");
    TEST_ASSERT_EQUAL_INT(0, symlink(victim, p));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_append(&store, "{\"scan_id\":\"a\"}", err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is a symbolic link"), err);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_state_open(&store, dir, NULL, err, sizeof err)); /* the repair refuses */
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot open: is a symbolic link"), err);
    size_t len = 0;
    char *text = scratch_slurp(victim, &len);
    TEST_ASSERT_EQUAL_STRING("someone's file without a final newline", text);
    free(text);
    path_in(p, sizeof p, "latest.json");
    snprintf(victim, sizeof victim, "%s/latest.json", outside);
    scratch_spit(victim, "{\"status\":\"ok\"}");
    TEST_ASSERT_EQUAL_INT(0, symlink(victim, p));
    char *json = NULL;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_NULL(json);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is a symbolic link"), err);
    scratch_remove_tree(outside);
}

static void test_scan_ids_become_safe_file_names(void)
{
    char id[UWBD_SCAN_ID_MAX + 1];
    uwbd_safe_scan_id("../../etc/passwd", id, sizeof id);
    TEST_ASSERT_EQUAL_STRING("_._.._etc_passwd", id); /* no slash, no leading dot */
    uwbd_safe_scan_id("uwb-20300101T000000.123Z", id, sizeof id);
    TEST_ASSERT_EQUAL_STRING("uwb-20300101T000000.123Z", id);
    char longer[300];
    memset(longer, 'x', sizeof longer - 1);
    longer[sizeof longer - 1] = '\0';
    uwbd_safe_scan_id(longer, id, sizeof id);
    TEST_ASSERT_EQUAL_INT(UWBD_SCAN_ID_MAX, (int)strlen(id));
}

/* A current.json whose time zero disagrees with the baseline scan it
 * describes (edited, or written by a bug) is corrected from the scan at
 * load, instead of making every later scan inconclusive. */
static void test_a_wrong_time_zero_in_current_json_is_taken_from_the_scan(void)
{
    struct uwb_scan a = {0};
    make_scan(&a, "scan-a", 100, 0.0f);
    set_baseline(&a);
    char p[2048];
    path_in(p, sizeof p, "baseline/current.json");
    char *json = scratch_slurp(p, NULL);
    cJSON *o = cJSON_Parse(json);
    free(json);
    cJSON_ReplaceItemInObjectCaseSensitive(o, "direct_coupling_ps", cJSON_CreateNumber(1234.5));
    json = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    scratch_spit(p, json);
    free(json);
    struct uwbd_baseline_info info;
    int repaired = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        UWBD_BASELINE_LOADED,
        uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, &repaired, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(1, repaired);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, own_direct_coupling(&a), info.direct_coupling_s);
    json = scratch_slurp(p, NULL);
    TEST_ASSERT_NULL_MESSAGE(strstr(json, "1234.5"), json);
    free(json);
    uwb_scan_free(&a);
}

/* One changed byte in current.uwbscan: the checksum recorded at
 * commissioning says so; the watch calls it a fault; `baseline set` moves
 * the damaged files aside (kept, not deleted) and puts the new one in. */
static void test_a_damaged_baseline_is_noticed_and_moved_aside(void)
{
    struct uwb_scan a = {0}, b = {0};
    make_scan(&a, "scan-a", 100, 0.0f);
    make_scan(&b, "scan-b", 120, 0.0f);
    set_baseline(&a);
    char p[2048];
    path_in(p, sizeof p, "baseline/current.uwbscan");
    size_t len = 0;
    char *bytes = scratch_slurp(p, &len);
    bytes[len - 5] ^= 0x40; /* inside the last sample */
    FILE *f = fopen(p, "wb");
    TEST_ASSERT_NOT_NULL(f);
    TEST_ASSERT_EQUAL_INT((int)len, (int)fwrite(bytes, 1, len, f));
    fclose(f);
    free(bytes);
    struct uwbd_baseline_info info;
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_DAMAGED,
                          uwbd_baseline_load(&store, WINDOW_END_S, NULL, &info, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "recorded at commissioning"), err);
    struct uwb_scan got = {0};
    char why[1024];
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_FAULT,
                          uwbd_baseline_watch(&store, WINDOW_END_S, NULL, &got, &info, why, sizeof why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, "baseline damaged: "), why);

    set_baseline(&b);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        UWBD_BASELINE_LOADED, uwbd_baseline_watch(&store, WINDOW_END_S, NULL, &got, &info, why, sizeof why),
        why);
    TEST_ASSERT_EQUAL_STRING("scan-b", info.scan_id);
    uwb_scan_free(&got);
    path_in(p, sizeof p, "baseline/history/damaged-2030-01-02T04-00-00Z.uwbscan");
    bytes = scratch_slurp(p, &len);
    TEST_ASSERT_NOT_NULL_MESSAGE(bytes, p);
    free(bytes);

    /* Which baseline the daemon commissioned: another one in its place is a fault too. */
    struct uwbd_baseline_info expected = info;
    expected.checksum ^= 1;
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_FAULT,
                          uwbd_baseline_watch(&store, WINDOW_END_S, &expected, &got, &info, why, sizeof why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, "replaced outside uwbd"), why);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
}

/* Only one uwbd per state directory: a second lock is refused with the
 * directory's name and granted again once the first holder lets go; a
 * directory where the lock file must be is refused by the lock's path. */
static void test_a_second_lock_on_the_state_directory_is_refused(void)
{
    int first = uwbd_store_lock(dir, err, sizeof err);
    TEST_ASSERT_TRUE_MESSAGE(first >= 0, err);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_lock(dir, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "another uwbd is using this state directory"), err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(err, dir, strlen(dir)));
    close(first);
    int again = uwbd_store_lock(dir, err, sizeof err);
    TEST_ASSERT_TRUE_MESSAGE(again >= 0, err);
    close(again);

    char other[128], lock[160];
    snprintf(other, sizeof other, "%s/lock-is-a-dir", dir);
    snprintf(lock, sizeof lock, "%s/uwbd.lock", other);
    TEST_ASSERT_EQUAL_INT(0, mkdir(other, 0755));
    TEST_ASSERT_EQUAL_INT(0, mkdir(lock, 0755));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_lock(other, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "lock-is-a-dir/uwbd.lock: cannot open"), err);
}

/* The rooms of the state directory must be directories; a name the file
 * system cannot hold is refused with the system's reason; a short path
 * (a symlink) that resolves to one too long for the store is refused. */
static void test_state_directories_that_cannot_be_made_are_refused_by_name(void)
{
    static const char *const rooms[] = {"archive", "baseline", "baseline/history"};
    struct uwbd_store other;
    for (size_t i = 0; i < 3; i++) {
        char state[128], room[192];
        snprintf(state, sizeof state, "%s/state-%zu", dir, i);
        TEST_ASSERT_EQUAL_INT(0, mkdir(state, 0755));
        if (i == 2) {
            snprintf(room, sizeof room, "%s/baseline", state);
            TEST_ASSERT_EQUAL_INT(0, mkdir(room, 0755));
        }
        snprintf(room, sizeof room, "%s/%s", state, rooms[i]);
        scratch_spit(room, "a file where a directory belongs");
        TEST_ASSERT_EQUAL_INT(-1, uwbd_store_open(&other, state, NULL, err, sizeof err));
        char want[64];
        snprintf(want, sizeof want, "/%s: exists but is not a directory", rooms[i]);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, want), err);
    }

    /* a file part-way along the path */
    char below_file[192];
    snprintf(below_file, sizeof below_file, "%s/state-0/archive/deeper", dir);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_open(&other, below_file, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "state-0/archive: exists but is not a directory"), err);

    char toolong[400];
    int w = snprintf(toolong, sizeof toolong, "%s/", dir);
    memset(toolong + w, 'n', 300);
    toolong[w + 300] = '\0';
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_open(&other, toolong, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "nnn: cannot create directory: File name too long"), err);

    /* 6 levels of 200 characters: beyond the store's 1024 once resolved. */
    char deep[1400], link[128];
    size_t used = (size_t)snprintf(deep, sizeof deep, "%s", dir);
    for (int level = 0; level < 6; level++) {
        deep[used++] = '/';
        memset(deep + used, (char)('a' + level), 200);
        used += 200;
        deep[used] = '\0';
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, mkdir(deep, 0755), deep);
    }
    snprintf(link, sizeof link, "%s/short", dir);
    TEST_ASSERT_EQUAL_INT(0, symlink(deep, link));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_open(&other, link, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "...: state directory path too long"), err);
}

/* Under archive/ only YYYY/MM/DD directories are uwbd's: a temporary name
 * in a directory whose name only looks like a year is left alone. */
static void test_archive_directories_not_named_by_date_are_not_cleaned(void)
{
    static const char *const lookalikes[] = {"archive/20a6", "archive/2026/1x", "archive/2026/01/0"};
    char p[2048], file[2100];
    for (size_t i = 0; i < 3; i++) {
        path_in(p, sizeof p, lookalikes[i]);
        for (char *s = p + strlen(store.root) + 1; *s; s++)
            if (*s == '/') {
                *s = '\0';
                mkdir(p, 0755);
                *s = '/';
            }
        mkdir(p, 0755);
        snprintf(file, sizeof file, "%s/" ATOMIC_FILE_TEMP_PREFIX "x.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX, p);
        scratch_spit(file, "not in a day directory");
    }
    int repairs = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, &repairs, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, repairs);
    for (size_t i = 0; i < 3; i++) {
        path_in(p, sizeof p, lookalikes[i]);
        snprintf(file, sizeof file, "%s/" ATOMIC_FILE_TEMP_PREFIX "x.Ab12Cd" ATOMIC_FILE_TEMP_SUFFIX, p);
        TEST_ASSERT_TRUE_MESSAGE(scratch_file_exists(file), file);
    }
}

/* A JSON file that cannot be written is an error naming it; no file
 * appears. */
static void test_a_json_file_in_a_missing_directory_is_refused_by_name(void)
{
    char p[2048];
    path_in(p, sizeof p, "no-such-dir/latest.json");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_write_json_file(p, "{\"a\":1}", err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no-such-dir"), err);
    TEST_ASSERT_FALSE(scratch_file_exists(p));
}

/* A verdict that does not fit (the disk full, here the file-size limit)
 * is refused by the log's name and leaves no torn line: a partial write
 * is cut back, so the log holds exactly the records before it. */
static void test_a_verdict_that_does_not_fit_leaves_the_log_as_it_was(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_append(&store, "{\"n\":1}", err, sizeof err), err);
    size_t before_len = 0;
    char *before = scratch_slurp(store.verdict_log, &before_len);
    TEST_ASSERT_NOT_NULL(before);

    struct rlimit saved;
    TEST_ASSERT_EQUAL_INT(0, getrlimit(RLIMIT_FSIZE, &saved));
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    struct rlimit tight = saved;
    /* room for 4 more bytes: a short write. Then none: the write fails. */
    tight.rlim_cur = (rlim_t)before_len + 4;
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &tight));
    int short_rc = uwbd_verdict_log_append(&store, "{\"n\":2,\"long\":\"enough\"}", err, sizeof err);
    char short_err[sizeof err];
    snprintf(short_err, sizeof short_err, "%s", err);
    tight.rlim_cur = (rlim_t)before_len;
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &tight));
    int full_rc = uwbd_verdict_log_append(&store, "{\"n\":3}", err, sizeof err);
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &saved));
    signal(SIGXFSZ, old_handler);

    TEST_ASSERT_EQUAL_INT(-1, short_rc);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(short_err, "verdicts.jsonl: cannot append a verdict: short write"),
                                 short_err);
    TEST_ASSERT_EQUAL_INT(-1, full_rc);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot append a verdict: File too large"), err);
    scratch_assert_file_holds(store.verdict_log, before, before_len);
    free(before);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_append(&store, "{\"n\":4}", err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(2, scratch_count_lines(store.verdict_log));
}

/* The tail's edges: no lines asked, no log yet, a line with a NUL inside
 * (skipped: it would cut the line short for every reader), and a line too
 * long to be a verdict (never half-returned). */
static void test_the_tail_skips_what_is_not_one_whole_verdict(void)
{
    char **lines = NULL;
    int count = -1, skipped = -1;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 0, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_NULL(lines);
    TEST_ASSERT_EQUAL_INT(0, count);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 5, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_NULL(lines);
    TEST_ASSERT_EQUAL_INT(0, count);
    char created[32] = "unchanged";
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_latest_created(&store, created, sizeof created));
    TEST_ASSERT_EQUAL_STRING("", created); /* no log yet */

    FILE *f = fopen(store.verdict_log, "wb");
    TEST_ASSERT_NOT_NULL(f);
    fputs("{\"n\":1}\n", f);
    static const char with_nul[] = "{\"n\":2,\"x\":\"a\0b\"}\n";
    fwrite(with_nul, 1, sizeof with_nul - 1, f);
    fputs("{\"n\":3}\n", f);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 5, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(2, count);
    TEST_ASSERT_EQUAL_INT(1, skipped);
    TEST_ASSERT_EQUAL_STRING("{\"n\":1}", lines[0]);
    TEST_ASSERT_EQUAL_STRING("{\"n\":3}", lines[1]);
    uwbd_verdict_lines_free(lines, count);

    /* 600 KiB of one line (past a verdict's bound), then a verdict: asked for 2,
     * only the verdict comes; the long line is counted, never held whole. */
    size_t big = 600 * 1024;
    char *text = malloc(big + 32);
    TEST_ASSERT_NOT_NULL(text);
    memset(text, 'x', big);
    text[0] = '{';
    memcpy(text + big - 1, "}\n{\"n\":9}\n", 11);
    scratch_spit(store.verdict_log, text);
    free(text);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_tail(&store, 2, &lines, &count, &skipped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(1, count);
    TEST_ASSERT_EQUAL_INT(1, skipped);
    TEST_ASSERT_EQUAL_STRING("{\"n\":9}", lines[0]);
    uwbd_verdict_lines_free(lines, count);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_latest_created(&store, created, sizeof created));
    TEST_ASSERT_EQUAL_STRING("", created); /* the newest line has no "created" */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0,
        uwbd_verdict_log_append(&store, "{\"n\":10,\"created\":\"2030-01-02T03:04:05Z\"}", err, sizeof err),
        err);
    TEST_ASSERT_EQUAL_INT(1, uwbd_verdict_log_latest_created(&store, created, sizeof created));
    TEST_ASSERT_EQUAL_STRING("2030-01-02T03:04:05Z", created);
}

/* Issue 43, break 7: lines that cannot be read at the end of the log (more
 * than one read block of them) do not hide the valid lines before them:
 * the tail reads back until it has its lines, so `verdict` after a restart
 * without latest.json answers with the last valid one. */
static void test_the_tail_reads_back_past_unreadable_last_lines(void)
{
    char *line = malloc(2048);
    TEST_ASSERT_NOT_NULL(line);
    for (int i = 0; i < 40; i++) {
        int n = snprintf(line, 2048, "{\"n\":%d,\"pad\":\"", i);
        memset(line + n, 'v', 1000);
        strcpy(line + n + 1000, "\"}");
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_append(&store, line, err, sizeof err), err);
    }
    /* 100 KiB of damage after them: whole lines, none of them JSON. */
    FILE *f = fopen(store.verdict_log, "ab");
    TEST_ASSERT_NOT_NULL(f);
    for (int i = 0; i < 100; i++) {
        memset(line, 'x', 1023);
        line[0] = '{';
        line[1023] = '\n';
        TEST_ASSERT_EQUAL_INT(1024, (int)fwrite(line, 1, 1024, f));
    }
    fclose(f);
    free(line);
    char **lines;
    int count, skipped;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_verdict_log_tail(&store, 1, &lines, &count, &skipped, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(1, count);
    TEST_ASSERT_EQUAL_INT(100, skipped);
    TEST_ASSERT_EQUAL_INT(0, strncmp(lines[0], "{\"n\":39,", 8));
    uwbd_verdict_lines_free(lines, count);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_verdict_log_tail(&store, 3, &lines, &count, &skipped, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(3, count);
    TEST_ASSERT_EQUAL_INT(0, strncmp(lines[0], "{\"n\":37,", 8));
    TEST_ASSERT_EQUAL_INT(0, strncmp(lines[2], "{\"n\":39,", 8));
    uwbd_verdict_lines_free(lines, count);
}

/* Issue 43, break 7: the latest verdict at start is latest.json's, and
 * when latest.json is missing or damaged, the newest valid line of
 * verdicts.jsonl (damaged lines after it passed over), not "no scan has
 * been recorded". */
static void test_the_latest_verdict_at_start_falls_back_to_the_last_valid_line(void)
{
    char note[1024];
    TEST_ASSERT_NULL(uwbd_latest_line_at_start(&store, note, sizeof note)); /* nothing yet */
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, "{\"n\":1}", err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, "{\"n\":2}", err, sizeof err));
    FILE *f = fopen(store.verdict_log, "ab");
    TEST_ASSERT_NOT_NULL(f);
    fputs("{\"n\":3, damaged\n\x01\x02\n", f);
    fclose(f);

    /* latest.json missing */
    char *line = uwbd_latest_line_at_start(&store, note, sizeof note);
    TEST_ASSERT_NOT_NULL_MESSAGE(line, note);
    TEST_ASSERT_EQUAL_STRING("{\"n\":2}", line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note, "taken from verdicts.jsonl"), note);
    free(line);

    /* latest.json damaged */
    scratch_spit(store.latest, "{\"n\":");
    line = uwbd_latest_line_at_start(&store, note, sizeof note);
    TEST_ASSERT_NOT_NULL_MESSAGE(line, note);
    TEST_ASSERT_EQUAL_STRING("{\"n\":2}", line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note, "latest.json: not one JSON object"), note);
    free(line);

    /* latest.json whole: it is the latest, nothing to say */
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_write(&store, "{\"n\":4}", err, sizeof err));
    line = uwbd_latest_line_at_start(&store, note, sizeof note);
    TEST_ASSERT_EQUAL_STRING("{\"n\":4}", line);
    TEST_ASSERT_EQUAL_STRING("", note);
    free(line);
}

/* Issue 43, break 6: on a full disk the verdicts.jsonl line may go in (the
 * room left in its last page) while latest.json cannot be replaced; after
 * a restart the newer of the two is the latest verdict, by its time, not
 * the stale latest.json. A log whose newest valid line is older (damage
 * after it) leaves latest.json standing. */
static void test_a_stale_latest_json_yields_to_a_newer_logged_verdict(void)
{
    const char *first = "{\"n\":1,\"created\":\"2030-01-02T00:00:00Z\"}";
    const char *second = "{\"n\":2,\"created\":\"2030-01-02T01:00:00Z\"}";
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, first, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_write(&store, first, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, second, err, sizeof err));
    char note[1024];
    char *line = uwbd_latest_line_at_start(&store, note, sizeof note);
    TEST_ASSERT_EQUAL_STRING(second, line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(note, "older than the newest line of"), note);
    free(line);

    /* latest.json newer than the log's newest valid line: it stands. */
    const char *third = "{\"n\":3,\"created\":\"2030-01-02T02:00:00Z\"}";
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_write(&store, third, err, sizeof err));
    FILE *f = fopen(store.verdict_log, "ab");
    TEST_ASSERT_NOT_NULL(f);
    fputs("{\"n\":3, damaged\n", f);
    fclose(f);
    line = uwbd_latest_line_at_start(&store, note, sizeof note);
    TEST_ASSERT_EQUAL_STRING(third, line);
    TEST_ASSERT_EQUAL_STRING("", note);
    free(line);
}

/* A crash mid-line with no newline anywhere (over several read blocks):
 * the repair cuts it all, and says how much. */
static void test_repair_of_a_log_without_any_whole_line_empties_it(void)
{
    char *text = malloc(10001);
    TEST_ASSERT_NOT_NULL(text);
    memset(text, 'x', 10000);
    text[0] = '{';
    text[10000] = '\0';
    scratch_spit(store.verdict_log, text);
    free(text);
    long dropped = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_repair(&store, &dropped, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(10000, (int)dropped);
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(store.verdict_log, &st));
    TEST_ASSERT_EQUAL_INT(0, (int)st.st_size);
}

/* latest.json: missing is no error and no text; trailing line ends are
 * dropped; anything but one JSON object (an array, a NUL inside) is
 * refused by its name. */
static void test_latest_json_must_be_one_object(void)
{
    char *json = (char *)"unchanged";
    TEST_ASSERT_EQUAL_INT(0, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_NULL(json);
    scratch_spit(store.latest, "{\"status\":\"ok\"}\r\n\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_latest_read(&store, &json, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("{\"status\":\"ok\"}", json);
    free(json);
    scratch_spit(store.latest, "[1,2]\n");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_NULL(json);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "latest.json: not one JSON object"), err);
    FILE *f = fopen(store.latest, "wb");
    TEST_ASSERT_NOT_NULL(f);
    fwrite("{\"a\":\"\0\"}", 1, 9, f);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "latest.json: not one JSON object"), err);
}

/* A directory where verdicts.jsonl must be: every reader and writer
 * refuses it with the log's name and the system's reason, none loses it. */
static void test_a_directory_in_place_of_the_verdict_log_is_refused_by_name(void)
{
    TEST_ASSERT_EQUAL_INT(0, mkdir(store.verdict_log, 0755));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_append(&store, "{\"n\":1}", err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot open for appending: Is a directory"),
                                 err);
    long dropped = -1;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_repair(&store, &dropped, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot open: Is a directory"), err);
    char **lines = NULL;
    int count = -1;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_tail(&store, 3, &lines, &count, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot open: Is a directory"), err);
    TEST_ASSERT_NULL(lines);
    int trimmed = -1;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_trim(&store, 1, 0, time(NULL), &trimmed, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot open: Is a directory"), err);
    TEST_ASSERT_EQUAL_INT(0, trimmed);
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(store.verdict_log, &st));
    TEST_ASSERT_TRUE(S_ISDIR(st.st_mode));
}
int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_open_makes_the_layout);
    RUN_TEST(test_open_removes_leftover_temporaries_only);
    RUN_TEST(test_open_touches_nothing_that_is_not_ours);
    RUN_TEST(test_unusable_state_paths_are_refused_by_name);
    RUN_TEST(test_many_foreign_files_are_all_left_alone);
    RUN_TEST(test_verdict_log_appends_whole_lines_and_reads_the_tail);
    RUN_TEST(test_torn_and_damaged_lines_are_tolerated_and_repaired);
    RUN_TEST(test_tail_reads_far_back_through_long_files);
    RUN_TEST(test_latest_is_replaced_whole);
    RUN_TEST(test_baseline_set_keeps_the_one_it_replaces);
    RUN_TEST(test_baseline_description_is_rebuilt_after_a_crash);
    RUN_TEST(test_baseline_set_counts_once_its_scan_is_in_place);
    RUN_TEST(test_a_wrong_time_zero_in_current_json_is_taken_from_the_scan);
    RUN_TEST(test_a_damaged_baseline_is_noticed_and_moved_aside);
    RUN_TEST(test_damaged_baseline_is_an_error_not_a_silent_replacement);
    RUN_TEST(test_retention_by_count_deletes_the_oldest_and_spares_baselines);
    RUN_TEST(test_retention_keeps_a_scan_whose_name_begins_like_a_deleted_one);
    RUN_TEST(test_retention_by_age);
    RUN_TEST(test_retention_by_age_waits_for_a_synchronised_clock);
    RUN_TEST(test_retention_never_follows_a_symlink);
    RUN_TEST(test_verdict_log_and_latest_are_never_written_through_a_symlink);
    RUN_TEST(test_scan_ids_become_safe_file_names);
    RUN_TEST(test_a_second_lock_on_the_state_directory_is_refused);
    RUN_TEST(test_state_directories_that_cannot_be_made_are_refused_by_name);
    RUN_TEST(test_archive_directories_not_named_by_date_are_not_cleaned);
    RUN_TEST(test_a_json_file_in_a_missing_directory_is_refused_by_name);
    RUN_TEST(test_a_verdict_that_does_not_fit_leaves_the_log_as_it_was);
    RUN_TEST(test_the_tail_skips_what_is_not_one_whole_verdict);
    RUN_TEST(test_the_tail_reads_back_past_unreadable_last_lines);
    RUN_TEST(test_the_latest_verdict_at_start_falls_back_to_the_last_valid_line);
    RUN_TEST(test_a_stale_latest_json_yields_to_a_newer_logged_verdict);
    RUN_TEST(test_repair_of_a_log_without_any_whole_line_empties_it);
    RUN_TEST(test_latest_json_must_be_one_object);
    RUN_TEST(test_a_directory_in_place_of_the_verdict_log_is_refused_by_name);
    return UNITY_END();
}
