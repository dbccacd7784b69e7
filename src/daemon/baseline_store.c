/* Keeping the baseline: current.uwbscan is written before current.json, so
 * after any crash the scan is either the old or the new baseline, whole,
 * and the json can be rebuilt from it. */
#include "uwb/daemon/baseline_store.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "uwb/daemon/direct_coupling.h"
#include "uwb/daemon/log.h"

#define INFO_MAX 65536

struct baseline_paths {
    char scan[UWBD_PATH_MAX + 64];
    char info[UWBD_PATH_MAX + 64];
};

static void current_paths(const struct uwbd_store *store, struct baseline_paths *p)
{
    uwbd_path_join(p->scan, sizeof p->scan, store->baseline_dir, "current.uwbscan");
    uwbd_path_join(p->info, sizeof p->info, store->baseline_dir, "current.json");
}

static int write_info(const char *path, const struct uwbd_baseline_info *info, char *err, size_t errlen)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) {
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    cJSON_AddStringToObject(o, "scan_id", info->scan_id);
    if (info->created[0])
        cJSON_AddStringToObject(o, "created", info->created);
    if (info->set_at[0])
        cJSON_AddStringToObject(o, "set_at", info->set_at);
    if (info->has_direct_coupling)
        cJSON_AddNumberToObject(o, "direct_coupling_ps", info->direct_coupling_s * 1e12);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    if (!text) {
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    int rc = uwbd_write_json_file(path, text, err, errlen);
    free(text);
    return rc;
}

/* 0 read, 1 absent, -1 unreadable or malformed (err says which). */
static int read_info(const char *path, struct uwbd_baseline_info *info, char *err, size_t errlen)
{
    memset(info, 0, sizeof *info);
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (errno == ENOENT)
            return 1;
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    char *text = malloc(INFO_MAX);
    size_t len = text ? fread(text, 1, INFO_MAX - 1, f) : 0;
    fclose(f);
    if (!text) {
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    cJSON *o = cJSON_ParseWithLength(text, len);
    free(text);
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(o, "scan_id");
    if (!cJSON_IsObject(o) || !cJSON_IsString(id)) {
        cJSON_Delete(o);
        snprintf(err, errlen, "%s: not a baseline description", path);
        return -1;
    }
    snprintf(info->scan_id, sizeof info->scan_id, "%s", id->valuestring);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, "created");
    if (cJSON_IsString(v))
        snprintf(info->created, sizeof info->created, "%s", v->valuestring);
    v = cJSON_GetObjectItemCaseSensitive(o, "set_at");
    if (cJSON_IsString(v))
        snprintf(info->set_at, sizeof info->set_at, "%s", v->valuestring);
    v = cJSON_GetObjectItemCaseSensitive(o, "direct_coupling_ps");
    if (cJSON_IsNumber(v)) {
        info->has_direct_coupling = 1;
        info->direct_coupling_s = v->valuedouble * 1e-12;
    }
    cJSON_Delete(o);
    return 0;
}

static void info_from_scan(const struct uwb_scan *scan, double window_end_s, struct uwbd_baseline_info *info)
{
    memset(info, 0, sizeof *info);
    uwbd_safe_scan_id(scan->scan_id ? scan->scan_id : "", info->scan_id, sizeof info->scan_id);
    snprintf(info->created, sizeof info->created, "%s", scan->created ? scan->created : "");
    char why[160];
    info->has_direct_coupling =
        uwb_direct_coupling_arrival(scan, window_end_s, &info->direct_coupling_s, why, sizeof why) == 0;
}

int uwbd_baseline_load(const struct uwbd_store *store, double window_end_s, struct uwb_scan *scan_out,
                       struct uwbd_baseline_info *info, int *repaired, char *err, size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    if (repaired)
        *repaired = 0;
    memset(info, 0, sizeof *info);
    if (access(p.scan, F_OK) != 0) {
        if (errno == ENOENT)
            return UWBD_BASELINE_NONE;
        snprintf(err, errlen, "%s: %s", p.scan, strerror(errno));
        return UWBD_BASELINE_ERROR;
    }
    struct uwb_scan scan = {0};
    if (uwbscan_read_file(p.scan, &scan, err, errlen) != 0)
        return UWBD_BASELINE_ERROR;
    char id[UWBD_SCAN_ID_MAX + 1];
    uwbd_safe_scan_id(scan.scan_id ? scan.scan_id : "", id, sizeof id);
    char why[2 * UWBD_PATH_MAX];
    int rc = read_info(p.info, info, why, sizeof why);
    if (rc != 0 || strcmp(info->scan_id, id) != 0) {
        /* current.json is missing, damaged or one baseline behind: rebuild it.
         * When it cannot be written now (a full disk), the scan still is
         * the baseline: use the description taken from it and try again at
         * the next load, rather than stop comparing scans. */
        info_from_scan(&scan, window_end_s, info);
        char write_err[2 * UWBD_PATH_MAX];
        if (write_info(p.info, info, write_err, sizeof write_err) != 0)
            uwbd_log(UWBD_LOG_WARNING, "baseline: current.json does not describe current.uwbscan (%s) and cannot "
                                       "be rebuilt now: %s; using the description taken from the scan",
                     info->scan_id, write_err);
        else if (repaired)
            *repaired = 1;
    }
    if (scan_out)
        *scan_out = scan;
    else
        uwb_scan_free(&scan);
    return UWBD_BASELINE_LOADED;
}

/* Keep the current baseline under history/ before it is replaced. */
static int keep_in_history(const struct uwbd_store *store, double window_end_s, char *err, size_t errlen)
{
    struct uwb_scan old = {0};
    struct uwbd_baseline_info old_info;
    int rc = uwbd_baseline_load(store, window_end_s, &old, &old_info, NULL, err, errlen);
    if (rc == UWBD_BASELINE_NONE)
        return 0;
    if (rc != UWBD_BASELINE_LOADED)
        return -1;
    char name[UWBD_SCAN_ID_MAX + 16], scan_path[UWBD_PATH_MAX + 160], info_path[UWBD_PATH_MAX + 160];
    const char *id = old_info.scan_id[0] ? old_info.scan_id : "unnamed";
    snprintf(name, sizeof name, "%s.uwbscan", id);
    uwbd_path_join(scan_path, sizeof scan_path, store->baseline_history, name);
    snprintf(name, sizeof name, "%s.json", id);
    uwbd_path_join(info_path, sizeof info_path, store->baseline_history, name);
    rc = 0;
    if (access(scan_path, F_OK) != 0)
        rc = uwbscan_write_file(scan_path, &old, err, errlen);
    if (rc == 0)
        rc = write_info(info_path, &old_info, err, errlen);
    uwb_scan_free(&old);
    return rc;
}

int uwbd_baseline_set(const struct uwbd_store *store, const struct uwb_scan *scan,
                      const struct uwbd_baseline_info *info, double window_end_s, char *err, size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    if (keep_in_history(store, window_end_s, err, errlen) != 0)
        return -1;
    if (uwbscan_write_file(p.scan, scan, err, errlen) != 0)
        return -1;
    /* From here the scan is the baseline: a description that cannot be
     * written is rebuilt from current.uwbscan at the next load. */
    char write_err[2 * UWBD_PATH_MAX];
    if (write_info(p.info, info, write_err, sizeof write_err) != 0)
        uwbd_log(UWBD_LOG_WARNING, "baseline: %s is the baseline, but %s; it is rebuilt from current.uwbscan",
                 info->scan_id, write_err);
    return 0;
}
