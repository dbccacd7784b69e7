/* Keeping the baseline: current.uwbscan is written before current.json, so
 * after any crash the scan is either the old or the new baseline, whole,
 * and the json can be rebuilt from it. current.json records the scan's
 * CRC-32 at commissioning, so a baseline damaged or replaced later is
 * noticed at the next scan instead of trusted. */
#include "state/baseline_store.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "util/log.h"
#include "uwb/direct_coupling.h"
#include "uwb/read_file.h"

#define INFO_MAX 65536
/* Far above any baseline a rig records (21 x 2048 samples are 172 kB). */
#define BASELINE_MAX_BYTES ((size_t)256 * 1024 * 1024)
/* current.json's direct coupling is the scan's own, measured the same way:
 * more than this apart, the scan's is right and the description is rebuilt. */
#define DIRECT_COUPLING_AGREE_S 0.05e-12

struct baseline_paths {
    char scan[UWBD_PATH_MAX + 64];
    char info[UWBD_PATH_MAX + 64];
    char pending[UWBD_PATH_MAX + 64];
};

static void current_paths(const struct uwbd_store *store, struct baseline_paths *p)
{
    uwbd_path_join(p->scan, sizeof p->scan, store->baseline_dir, "current.uwbscan");
    uwbd_path_join(p->info, sizeof p->info, store->baseline_dir, "current.json");
    uwbd_path_join(p->pending, sizeof p->pending, store->baseline_dir, "pending.json");
}

static unsigned long checksum_of(const void *bytes, size_t len)
{
    return crc32(crc32(0L, Z_NULL, 0), bytes, (uInt)len);
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
    if (info->has_checksum) {
        char hex[16];
        snprintf(hex, sizeof hex, "%08lx", info->checksum & 0xffffffffUL);
        cJSON_AddStringToObject(o, "crc32", hex);
    }
    if (info->scans > 0)
        cJSON_AddNumberToObject(o, "scans", info->scans);
    if (info->has_repeatability)
        cJSON_AddNumberToObject(o, "repeatability_mm", round(info->repeatability_m * 1e6) / 1e3);
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

int uwbd_baseline_info_read(const char *path, struct uwbd_baseline_info *info, char *err, size_t errlen)
{
    memset(info, 0, sizeof *info);
    char *text = NULL;
    size_t len = 0;
    if (uwb_read_file_nofollow(path, INFO_MAX, &text, &len, err, errlen) != UWB_READ_OK)
        return access(path, F_OK) != 0 && errno == ENOENT ? 1 : -1;
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
    if (cJSON_IsNumber(v) && isfinite(v->valuedouble)) {
        info->has_direct_coupling = 1;
        info->direct_coupling_s = v->valuedouble * 1e-12;
    }
    v = cJSON_GetObjectItemCaseSensitive(o, "crc32");
    char *end = NULL;
    if (cJSON_IsString(v) && strlen(v->valuestring) == 8) {
        unsigned long crc = strtoul(v->valuestring, &end, 16);
        if (end && *end == '\0') {
            info->has_checksum = 1;
            info->checksum = crc;
        }
    }
    v = cJSON_GetObjectItemCaseSensitive(o, "scans");
    if (cJSON_IsNumber(v) && v->valuedouble >= 1 && v->valuedouble <= 1000)
        info->scans = (int)v->valuedouble;
    v = cJSON_GetObjectItemCaseSensitive(o, "repeatability_mm");
    if (cJSON_IsNumber(v) && v->valuedouble >= 0 && v->valuedouble < 1e3) {
        info->has_repeatability = 1;
        info->repeatability_m = v->valuedouble * 1e-3;
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
        int e = errno;
        if (e == ENOENT && access(p.info, F_OK) != 0)
            return UWBD_BASELINE_NONE;
        if (e == ENOENT) { /* the scan is written first: a description alone is damage */
            snprintf(err, errlen, "%s: missing, though current.json describes a baseline", p.scan);
            return UWBD_BASELINE_ERROR;
        }
        snprintf(err, errlen, "%s: %s", p.scan, strerror(e));
        return UWBD_BASELINE_ERROR;
    }
    char *bytes = NULL;
    size_t len = 0;
    if (uwb_read_file_nofollow(p.scan, BASELINE_MAX_BYTES, &bytes, &len, err, errlen) != UWB_READ_OK)
        return UWBD_BASELINE_ERROR;
    unsigned long crc = checksum_of(bytes, len);
    struct uwb_scan scan = {0};
    int parsed = uwbscan_parse(bytes, len, p.scan, &scan, err, errlen);
    free(bytes);
    char why[2 * UWBD_PATH_MAX];
    int rc = uwbd_baseline_info_read(p.info, info, why, sizeof why);
    char id[UWBD_SCAN_ID_MAX + 1];
    uwbd_safe_scan_id(parsed == 0 && scan.scan_id ? scan.scan_id : "", id, sizeof id);
    /* A scan that names another baseline than current.json is a crash between
     * the two writes (rebuilt below); the same name with other bytes is damage. */
    if (rc == 0 && info->has_checksum && info->checksum != crc &&
        (parsed != 0 || strcmp(info->scan_id, id) == 0)) {
        uwb_scan_free(&scan);
        snprintf(err, errlen, "%s: CRC-32 %08lx, not the %08lx recorded at commissioning in current.json",
                 p.scan, crc, info->checksum);
        return UWBD_BASELINE_DAMAGED;
    }
    if (parsed != 0)
        return UWBD_BASELINE_ERROR;
    /* The scan's own direct coupling: a description that disagrees with
     * the scan it describes is the one that is wrong. */
    double own_arrival = 0;
    char dc_why[160];
    int own_dc = uwb_direct_coupling_arrival(&scan, window_end_s, &own_arrival, dc_why, sizeof dc_why) == 0;
    int rewrite = 0;
    if (rc != 0 || strcmp(info->scan_id, id) != 0) {
        /* current.json is missing, damaged or one baseline behind: rebuild it.
         * When it cannot be written now (a full disk), the scan still is
         * the baseline: use the description taken from it and try again at
         * the next load, rather than stop comparing scans. */
        info_from_scan(&scan, window_end_s, info);
        rewrite = 1;
    } else if (own_dc != info->has_direct_coupling ||
               (own_dc && fabs(own_arrival - info->direct_coupling_s) > DIRECT_COUPLING_AGREE_S)) {
        char own_text[64] = "none";
        if (own_dc)
            snprintf(own_text, sizeof own_text, "%.1f ps", own_arrival * 1e12);
        uwbd_log(UWBD_LOG_WARNING,
                 "baseline: current.json gives the direct coupling at %.1f ps, the baseline scan %s "
                 "itself %s; using the scan's",
                 info->direct_coupling_s * 1e12, id, own_text);
        info->has_direct_coupling = own_dc;
        info->direct_coupling_s = own_dc ? own_arrival : 0;
        rewrite = 1;
    }
    if (!info->has_checksum) { /* commissioned before checksums were recorded */
        info->has_checksum = 1;
        info->checksum = crc;
        rewrite = 1;
    }
    if (rewrite) {
        char write_err[2 * UWBD_PATH_MAX];
        if (write_info(p.info, info, write_err, sizeof write_err) != 0)
            uwbd_log(UWBD_LOG_WARNING,
                     "baseline: current.json does not describe current.uwbscan (%s) and cannot "
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
        return 1;
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

/* A damaged baseline is evidence: it goes to history/damaged-<time>.* by
 * rename, never deleted, before a new one takes its place. */
static int move_damaged_aside(const struct uwbd_store *store, const char *set_at, const char *why, char *err,
                              size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    char stamp[80];
    snprintf(stamp, sizeof stamp, "damaged-%s", set_at[0] ? set_at : "unknown");
    for (char *c = stamp; *c; c++)
        if (*c == ':')
            *c = '-';
    static const char *const suffixes[] = {".uwbscan", ".json"};
    const char *from[] = {p.scan, p.info};
    for (int i = 0; i < 2; i++) {
        char name[128], to[UWBD_PATH_MAX + 160];
        snprintf(name, sizeof name, "%s%s", stamp, suffixes[i]);
        uwbd_path_join(to, sizeof to, store->baseline_history, name);
        if (rename(from[i], to) != 0 && errno != ENOENT) {
            snprintf(err, errlen, "%s: cannot move the damaged baseline aside to %s: %s", from[i], to,
                     strerror(errno));
            return -1;
        }
    }
    uwbd_log(UWBD_LOG_WARNING, "baseline: the damaged baseline (%.300s) moved to baseline/history/%s.*", why,
             stamp);
    return 0;
}

int uwbd_baseline_set(const struct uwbd_store *store, const struct uwb_scan *scan,
                      const struct uwbd_baseline_info *info_in, double window_end_s, char *err, size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    char why[1024];
    int kept = keep_in_history(store, window_end_s, why, sizeof why);
    if (kept < 0) {
        snprintf(err, errlen, "%s", why);
        return -1;
    }
    if (kept > 0 && move_damaged_aside(store, info_in->set_at, why, err, errlen) != 0)
        return -1;
    struct uwbd_baseline_info info = *info_in;
    unsigned char *bytes = NULL;
    size_t len = 0;
    if (uwbscan_serialise(scan, &bytes, &len, err, errlen) != 0)
        return -1;
    info.has_checksum = 1;
    info.checksum = checksum_of(bytes, len);
    free(bytes);
    if (uwbscan_write_file(p.scan, scan, err, errlen) != 0)
        return -1;
    /* From here the scan is the baseline: a description that cannot be
     * written is rebuilt from current.uwbscan at the next load. */
    char write_err[2 * UWBD_PATH_MAX];
    if (write_info(p.info, &info, write_err, sizeof write_err) != 0)
        uwbd_log(UWBD_LOG_WARNING, "baseline: %s is the baseline, but %s; it is rebuilt from current.uwbscan",
                 info.scan_id, write_err);
    return 0;
}

int uwbd_baseline_watch(const struct uwbd_store *store, double window_end_s,
                        const struct uwbd_baseline_info *expected, struct uwb_scan *scan,
                        struct uwbd_baseline_info *info, char *why, size_t whylen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    if (access(p.scan, F_OK) != 0 && errno == ENOENT && (expected || access(p.info, F_OK) == 0)) {
        snprintf(why, whylen,
                 "baseline missing: baseline/current.uwbscan (%.100s, commissioned %.40s) is gone",
                 expected ? expected->scan_id : "described by current.json",
                 expected && expected->set_at[0] ? expected->set_at : "earlier");
        return UWBD_BASELINE_FAULT;
    }
    char err[1024] = "";
    int repaired = 0;
    int rc = uwbd_baseline_load(store, window_end_s, scan, info, &repaired, err, sizeof err);
    if (repaired)
        uwbd_log(UWBD_LOG_WARNING,
                 "baseline/current.json did not describe current.uwbscan; rebuilt it from the scan");
    switch (rc) {
    case UWBD_BASELINE_NONE: /* nothing commissioned, nothing expected (checked above) */
        return UWBD_BASELINE_NONE;
    case UWBD_BASELINE_ERROR:
    case UWBD_BASELINE_DAMAGED:
        snprintf(why, whylen, "baseline damaged: %.400s", err);
        return UWBD_BASELINE_FAULT;
    default: break;
    }
    if (expected && expected->has_checksum &&
        (strcmp(expected->scan_id, info->scan_id) != 0 || expected->checksum != info->checksum)) {
        snprintf(why, whylen,
                 "baseline replaced outside uwbd: baseline/current.uwbscan is %.100s (CRC-32 %08lx), uwbd "
                 "commissioned %.100s (CRC-32 %08lx)",
                 info->scan_id, info->checksum, expected->scan_id, expected->checksum);
        uwb_scan_free(scan);
        return UWBD_BASELINE_FAULT;
    }
    return UWBD_BASELINE_LOADED;
}

int uwbd_baseline_pending_write(const struct uwbd_store *store, int scans, int force, time_t requested,
                                char *err, size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    char at[64], text[160];
    uwbd_utc_text(requested, at, sizeof at);
    snprintf(text, sizeof text, "{\"requested_at\":\"%s\",\"scans\":%d,\"force\":%s}", at, scans,
             force ? "true" : "false");
    return uwbd_write_json_file(p.pending, text, err, errlen);
}

int uwbd_baseline_pending_read(const struct uwbd_store *store, int *scans, int *force, char *err,
                               size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    char *text = NULL;
    size_t len = 0;
    if (uwb_read_file_nofollow(p.pending, INFO_MAX, &text, &len, err, errlen) != UWB_READ_OK)
        return access(p.pending, F_OK) != 0 && errno == ENOENT ? 0 : -1;
    cJSON *o = cJSON_ParseWithLength(text, len);
    free(text);
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(o, "scans");
    int ok = cJSON_IsNumber(n) && n->valuedouble >= 1 && n->valuedouble <= UWBD_BASELINE_SCANS_MAX &&
             n->valuedouble == (int)n->valuedouble;
    if (ok) {
        *scans = (int)n->valuedouble;
        *force = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(o, "force"));
    } else
        snprintf(err, errlen, "%s: not a pending `baseline set` (scans 1..%d)", p.pending,
                 UWBD_BASELINE_SCANS_MAX);
    cJSON_Delete(o);
    return ok ? 1 : -1;
}

int uwbd_baseline_pending_clear(const struct uwbd_store *store, char *err, size_t errlen)
{
    struct baseline_paths p;
    current_paths(store, &p);
    if (unlink(p.pending) != 0 && errno != ENOENT) {
        snprintf(err, errlen, "%s: cannot remove: %s", p.pending, strerror(errno));
        return -1;
    }
    return 0;
}
