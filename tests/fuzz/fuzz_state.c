/* Fuzzing the daemon's readers of its own state files (issue 17): the
 * input becomes verdicts.jsonl, latest.json and baseline/current.json of a
 * scratch state directory (beside a valid baseline/current.uwbscan), and
 * goes through what the daemon does with them at start and per scan: the
 * torn-line repair, the history tail, the newest line's time, the trim,
 * latest.json and the baseline's description.
 *
 * Contract: each reader gives a result or an error with a message; the
 * tail hands over only lines that are JSON objects, at most as many as
 * asked; after the repair the log ends with a newline (or is empty). */
#include <cjson/cJSON.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fuzz_harness.h"
#include "state/baseline_store.h"
#include "util/log.h"
#include "state/store.h"
#include "state/verdict_log.h"
#include "uwb/scan.h"

static char root[64];
static struct uwbd_store store;

/* The scratch tree is two levels deep (baseline/history, archive). */
static void remove_tree(const char *dir, int depth)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (depth > 0 && e->d_type == DT_DIR)
            remove_tree(path, depth - 1);
        else
            unlink(path);
    }
    closedir(d);
    rmdir(dir);
}

static void remove_root(void)
{
    if (root[0])
        remove_tree(root, 3);
}

static int setup(char *why, size_t whylen)
{
    if (root[0])
        return 0;
    uwbd_log_setup(0, 0); /* the repairs' warnings are expected here */
    snprintf(root, sizeof root, "/tmp/uwbd-fuzz-state-XXXXXX");
    char err[512];
    if (!mkdtemp(root) || uwbd_store_open(&store, root, NULL, err, sizeof err) != 0) {
        root[0] = '\0';
        return fuzz_broken(why, whylen, "cannot make a scratch state directory");
    }
    atexit(remove_root);
    struct uwb_scan s;
    if (uwb_scan_alloc(&s, 2, 64, err, sizeof err) != 0)
        return fuzz_broken(why, whylen, "%s", err);
    s.sample_interval_s = 10e-12;
    s.t0_s = -1e-10;
    s.antenna_y_m[1] = 0.03;
    s.data[10] = s.data[74] = 1.0f;
    s.scan_id = strdup("fuzz-baseline");
    char path[UWBD_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/current.uwbscan", store.baseline_dir);
    int rc = uwbscan_write_file(path, &s, err, sizeof err);
    uwb_scan_free(&s);
    return rc == 0 ? 0 : fuzz_broken(why, whylen, "%s", err);
}

static int put(const char *path, const uint8_t *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t w = size ? fwrite(data, 1, size, f) : 0;
    return fclose(f) == 0 && w == size ? 0 : -1;
}

int fuzz_state_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    if (setup(why, whylen) != 0)
        return FUZZ_BROKEN;
    char description[UWBD_PATH_MAX + 64];
    snprintf(description, sizeof description, "%s/current.json", store.baseline_dir);
    if (put(store.verdict_log, data, size) != 0 || put(store.latest, data, size) != 0 ||
        put(description, data, size) != 0)
        return fuzz_broken(why, whylen, "cannot write the scratch state files");

    char err[512] = "";
    long dropped = 0;
    if (uwbd_verdict_log_repair(&store, &dropped, err, sizeof err) != 0 && !err[0])
        return fuzz_broken(why, whylen, "repair failed without a message");
    char **lines = NULL;
    int count = 0, skipped = 0;
    err[0] = '\0';
    if (uwbd_verdict_log_tail(&store, 5, &lines, &count, &skipped, err, sizeof err) != 0) {
        if (!err[0])
            return fuzz_broken(why, whylen, "tail failed without a message");
    } else {
        if (count < 0 || count > 5)
            return fuzz_broken(why, whylen, "tail of 5 gave %d lines", count);
        for (int i = 0; i < count; i++) {
            cJSON *o = cJSON_Parse(lines[i]);
            int object = cJSON_IsObject(o);
            cJSON_Delete(o);
            if (!object) {
                uwbd_verdict_lines_free(lines, count);
                return fuzz_broken(why, whylen, "tail handed over a line that is not a JSON object");
            }
        }
    }
    uwbd_verdict_lines_free(lines, count);
    char created[64];
    uwbd_verdict_log_latest_created(&store, created, sizeof created);
    if (!memchr(created, '\0', sizeof created))
        return fuzz_broken(why, whylen, "latest created unterminated");
    err[0] = '\0';
    if (uwbd_verdict_log_trim(&store, 3, 30, 2000000000, NULL, err, sizeof err) != 0 && !err[0])
        return fuzz_broken(why, whylen, "trim failed without a message");

    char *latest = NULL;
    err[0] = '\0';
    int rc = uwbd_latest_read(&store, &latest, err, sizeof err);
    if (rc != 0 && (!err[0] || latest))
        return fuzz_broken(why, whylen, "latest.json refused without a message, or with a result");
    if (latest) {
        cJSON *o = cJSON_Parse(latest);
        int object = cJSON_IsObject(o);
        cJSON_Delete(o);
        free(latest);
        if (!object)
            return fuzz_broken(why, whylen, "latest.json accepted, but its text is not a JSON object");
    }

    struct uwbd_baseline_info info;
    int repaired = 0;
    err[0] = '\0';
    rc = uwbd_baseline_load(&store, 2e-9, NULL, &info, &repaired, err, sizeof err);
    if (rc == UWBD_BASELINE_ERROR && !err[0])
        return fuzz_broken(why, whylen, "baseline refused without a message");
    if (rc == UWBD_BASELINE_LOADED && !memchr(info.scan_id, '\0', sizeof info.scan_id))
        return fuzz_broken(why, whylen, "baseline scan_id unterminated");
    snprintf(why, whylen, "state files of %zu bytes", size);
    return FUZZ_ACCEPTED;
}

UWB_FUZZ_TARGET(fuzz_state_input)
