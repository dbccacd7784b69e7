/* Finding archived scans and deleting the oldest. A scan is the group of
 * files <id>.uwbscan, <id>.json and <id>-<kind>.png in one day directory;
 * an image's kind has no '-', so "a-2.json" is not taken for an image of "a". */
#include "uwb/daemon/retention.h"
#include "uwb/daemon/verdict_log.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct archived_scan {
    char day_dir[UWBD_PATH_MAX + 32];
    char id[UWBD_SCAN_ID_MAX + 1];
    struct timespec mtime;   /* to the nanosecond: scans a second apart still sort */
};

struct scan_list {
    struct archived_scan *items;
    size_t count, cap;
};

static int has_suffix(const char *name, const char *suffix, size_t *stem_len)
{
    size_t n = strlen(name), s = strlen(suffix);
    if (n <= s || strcmp(name + n - s, suffix) != 0)
        return 0;
    *stem_len = n - s;
    return 1;
}

static int later(struct timespec a, struct timespec b)
{
    return a.tv_sec != b.tv_sec ? a.tv_sec > b.tv_sec : a.tv_nsec > b.tv_nsec;
}

/* A scan's files all lie in its day directory, whose scans are the list's
 * items from day_start on: only those can be this one again. */
static int add_scan(struct scan_list *list, size_t day_start, const char *day_dir, const char *id, size_t id_len,
                    struct timespec mtime)
{
    if (id_len > UWBD_SCAN_ID_MAX)
        return 0;
    for (size_t i = day_start; i < list->count; i++) {
        struct archived_scan *s = &list->items[i];
        if (strncmp(s->id, id, id_len) == 0 && s->id[id_len] == '\0') {
            if (later(mtime, s->mtime))
                s->mtime = mtime;
            return 0;
        }
    }
    if (list->count == list->cap) {
        size_t cap = list->cap ? list->cap * 2 : 64;
        struct archived_scan *grown = realloc(list->items, cap * sizeof *grown);
        if (!grown)
            return -1;
        list->items = grown;
        list->cap = cap;
    }
    struct archived_scan *s = &list->items[list->count++];
    snprintf(s->day_dir, sizeof s->day_dir, "%s", day_dir);
    memcpy(s->id, id, id_len);
    s->id[id_len] = '\0';
    s->mtime = mtime;
    return 0;
}

/* The scans of one day directory: one per .json (a cycle's record) or
 * .uwbscan (a cycle cut short before its verdict). */
static int list_day(const char *day_dir, struct scan_list *list)
{
    DIR *d = opendir(day_dir);
    if (!d)
        return 0;
    size_t day_start = list->count;
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        size_t stem;
        if (!has_suffix(e->d_name, ".json", &stem) && !has_suffix(e->d_name, ".uwbscan", &stem))
            continue;
        char path[UWBD_PATH_MAX + 300];
        struct stat st;
        if (uwbd_path_join(path, sizeof path, day_dir, e->d_name) != 0 || stat(path, &st) != 0)
            continue;
        rc = add_scan(list, day_start, day_dir, e->d_name, stem, st.st_mtim);
    }
    closedir(d);
    return rc;
}

static int is_number_dir(const char *name, size_t digits)
{
    return strlen(name) == digits && strspn(name, "0123456789") == digits;
}

/* Walk archive/YYYY/MM/DD and list the scans of every day directory. */
static int walk_days(const char *dir, int level, struct scan_list *list)
{
    static const size_t digits[] = {4, 2, 2};
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d)) != NULL) {
        if (!is_number_dir(e->d_name, digits[level]))
            continue;
        char path[UWBD_PATH_MAX + 32];
        if (uwbd_path_join(path, sizeof path, dir, e->d_name) != 0)
            continue;
        rc = level == 2 ? list_day(path, list) : walk_days(path, level + 1, list);
    }
    closedir(d);
    return rc;
}

static int oldest_first(const void *a, const void *b)
{
    const struct archived_scan *x = a, *y = b;
    if (later(x->mtime, y->mtime) || later(y->mtime, x->mtime))
        return later(y->mtime, x->mtime) ? -1 : 1;
    int c = strcmp(x->day_dir, y->day_dir);
    return c ? c : strcmp(x->id, y->id);
}

static int is_file_of_scan(const char *name, const char *id)
{
    size_t n = strlen(id);
    if (strncmp(name, id, n) != 0)
        return 0;
    const char *rest = name + n;
    if (strcmp(rest, ".json") == 0 || strcmp(rest, ".uwbscan") == 0)
        return 1;
    size_t kind_len;
    if (rest[0] != '-' || !has_suffix(rest + 1, ".png", &kind_len))
        return 0;
    for (size_t i = 0; i < kind_len; i++)
        if (rest[1 + i] == '-')
            return 0;
    return 1;
}

static int delete_scan(const struct archived_scan *s, char *err, size_t errlen)
{
    DIR *d = opendir(s->day_dir);
    if (!d) {
        snprintf(err, errlen, "%s: cannot list: %s", s->day_dir, strerror(errno));
        return -1;
    }
    struct dirent *e;
    int rc = 0;
    while ((e = readdir(d)) != NULL) {
        if (!is_file_of_scan(e->d_name, s->id))
            continue;
        char path[UWBD_PATH_MAX + 300];
        if (uwbd_path_join(path, sizeof path, s->day_dir, e->d_name) == 0 && unlink(path) != 0 &&
            errno != ENOENT) {
            snprintf(err, errlen, "%s: cannot delete: %s", path, strerror(errno));
            rc = -1;
        }
    }
    closedir(d);
    /* Empty day, month, year directories: rmdir fails harmlessly on a non-empty one. */
    char dir[UWBD_PATH_MAX + 32];
    snprintf(dir, sizeof dir, "%s", s->day_dir);
    for (int level = 0; level < 3 && rmdir(dir) == 0; level++) {
        char *slash = strrchr(dir, '/');
        if (!slash)
            break;
        *slash = '\0';
    }
    return rc;
}

static int list_scans(const struct uwbd_store *store, struct scan_list *list)
{
    memset(list, 0, sizeof *list);
    if (walk_days(store->archive, 0, list) != 0)
        return -1;
    if (list->count > 1)
        qsort(list->items, list->count, sizeof list->items[0], oldest_first);
    return 0;
}

int uwbd_retention_apply(const struct uwbd_store *store, int max_scans, double max_age_days, time_t now,
                         int *removed, char *err, size_t errlen)
{
    if (removed)
        *removed = 0;
    if (max_scans <= 0 && max_age_days <= 0)
        return 0;
    struct scan_list list;
    if (list_scans(store, &list) != 0) {
        free(list.items);
        snprintf(err, errlen, "%s: out of memory listing the archive", store->archive);
        return -1;
    }
    size_t excess = max_scans > 0 && list.count > (size_t)max_scans ? list.count - (size_t)max_scans : 0;
    time_t cutoff = max_age_days > 0 ? now - (time_t)(max_age_days * 86400.0) : 0;
    int rc = 0;
    for (size_t i = 0; i < list.count; i++) {
        int too_many = i < excess;
        int too_old = max_age_days > 0 && list.items[i].mtime.tv_sec < cutoff;
        if (!too_many && !too_old)
            break;   /* oldest first: everything after is newer */
        if (delete_scan(&list.items[i], err, errlen) != 0)
            rc = -1;
        else if (removed)
            ++*removed;
    }
    if (uwbd_verdict_log_trim(store, max_scans, max_age_days, now, NULL, err, errlen) != 0)
        rc = -1;   /* verdicts.jsonl spans what the archive keeps */
    free(list.items);
    return rc;
}

int uwbd_archive_count(const struct uwbd_store *store)
{
    struct scan_list list;
    int rc = list_scans(store, &list);
    int n = rc == 0 ? (int)list.count : -1;
    free(list.items);
    return n;
}
