/* Finding archived scans and deleting the oldest. A scan is the group of
 * files <id>.uwbscan, <id>.json and <id>-<kind>.png in one day directory;
 * an image's kind has no '-', so "a-2.json" is not taken for an image of "a".
 * Every directory is opened relative to its parent's fd with O_NOFOLLOW and
 * only regular files are looked at or deleted: a symlink placed in the
 * archive (a day directory pointing elsewhere) is never followed. */
#include "daemon/retention.h"
#include "daemon/verdict_log.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/timex.h>
#include <unistd.h>

struct archived_scan {
    char day[16]; /* "YYYY/MM/DD" under archive/ */
    char id[UWBD_SCAN_ID_MAX + 1];
    struct timespec mtime; /* to the nanosecond: scans a second apart still sort */
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

/* A directory below dirfd, never through a symlink; -1 if absent or not a
 * real directory. */
static int open_subdir(int dirfd, const char *name)
{
    return openat(dirfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
}

/* A directory stream over a copy of fd (the caller keeps fd). */
static DIR *list_fd(int fd)
{
    int copy = dup(fd);
    DIR *d = copy >= 0 ? fdopendir(copy) : NULL;
    if (!d && copy >= 0)
        close(copy);
    return d;
}

/* archive/YYYY/MM/DD opened level by level; -1 if any level is missing or
 * is not a real directory. */
static int open_day(const struct uwbd_store *store, const char *day)
{
    char parts[16];
    snprintf(parts, sizeof parts, "%s", day);
    int fd = open(store->archive, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    for (char *save = NULL, *p = strtok_r(parts, "/", &save); fd >= 0 && p; p = strtok_r(NULL, "/", &save)) {
        int next = open_subdir(fd, p);
        close(fd);
        fd = next;
    }
    return fd;
}

/* A scan's files all lie in its day directory, whose scans are the list's
 * items from day_start on: only those can be this one again. */
static int add_scan(struct scan_list *list, size_t day_start, const char *day, const char *id, size_t id_len,
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
    snprintf(s->day, sizeof s->day, "%s", day);
    memcpy(s->id, id, id_len);
    s->id[id_len] = '\0';
    s->mtime = mtime;
    return 0;
}

/* The scans of one day directory: one per .json (a cycle's record) or
 * .uwbscan (a cycle cut short before its verdict), regular files only. */
static int list_day(int dayfd, const char *day, struct scan_list *list)
{
    DIR *d = list_fd(dayfd);
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
        struct stat st;
        if (fstatat(dayfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode))
            continue;
        rc = add_scan(list, day_start, day, e->d_name, stem, st.st_mtim);
    }
    closedir(d);
    return rc;
}

static int is_number_dir(const char *name, size_t digits)
{
    return strlen(name) == digits && strspn(name, "0123456789") == digits;
}

/* Walk archive/YYYY/MM/DD and list the scans of every day directory. */
static int walk_days(int dirfd, int level, const char *prefix, struct scan_list *list)
{
    static const size_t digits[] = {4, 2, 2};
    DIR *d = list_fd(dirfd);
    if (!d)
        return 0;
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d)) != NULL) {
        if (!is_number_dir(e->d_name, digits[level]))
            continue;
        int sub = open_subdir(dirfd, e->d_name);
        if (sub < 0)
            continue; /* a symlink or a file: not ours to walk */
        char day[16];
        snprintf(day, sizeof day, "%s%s%s", prefix, level ? "/" : "", e->d_name);
        rc = level == 2 ? list_day(sub, day, list) : walk_days(sub, level + 1, day, list);
        close(sub);
    }
    closedir(d);
    return rc;
}

static int oldest_first(const void *a, const void *b)
{
    const struct archived_scan *x = a, *y = b;
    if (later(x->mtime, y->mtime) || later(y->mtime, x->mtime))
        return later(y->mtime, x->mtime) ? -1 : 1;
    int c = strcmp(x->day, y->day);
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

/* Remove archive/YYYY/MM/DD's directories that are empty, deepest first
 * (unlinkat with AT_REMOVEDIR fails harmlessly on a non-empty one). */
static void remove_empty_days(const struct uwbd_store *store, const char *day)
{
    char path[16];
    snprintf(path, sizeof path, "%s", day);
    for (int level = 0; level < 3; level++) {
        char *slash = strrchr(path, '/');
        const char *leaf = slash ? slash + 1 : path;
        int parent;
        if (slash) {
            *slash = '\0';
            parent = open_day(store, path);
        } else {
            parent = open(store->archive, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        }
        int gone = parent >= 0 && unlinkat(parent, leaf, AT_REMOVEDIR) == 0;
        if (parent >= 0)
            close(parent);
        if (!gone || !slash)
            break;
    }
}

static int delete_scan(const struct uwbd_store *store, const struct archived_scan *s, char *err,
                       size_t errlen)
{
    int dayfd = open_day(store, s->day);
    if (dayfd < 0) {
        snprintf(err, errlen, "%s/%s: cannot open as a directory: %s", store->archive, s->day,
                 strerror(errno));
        return -1;
    }
    DIR *d = list_fd(dayfd);
    if (!d) {
        snprintf(err, errlen, "%s/%s: cannot list: %s", store->archive, s->day, strerror(errno));
        close(dayfd);
        return -1;
    }
    struct dirent *e;
    int rc = 0;
    while ((e = readdir(d)) != NULL) {
        if (!is_file_of_scan(e->d_name, s->id))
            continue;
        struct stat st;
        if (fstatat(dayfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (unlinkat(dayfd, e->d_name, 0) != 0 && errno != ENOENT) {
            snprintf(err, errlen, "%s/%s/%s: cannot delete: %s", store->archive, s->day, e->d_name,
                     strerror(errno));
            rc = -1;
        }
    }
    closedir(d);
    close(dayfd);
    remove_empty_days(store, s->day);
    return rc;
}

static int list_scans(const struct uwbd_store *store, struct scan_list *list)
{
    memset(list, 0, sizeof *list);
    int archive = open(store->archive, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (archive < 0)
        return 0;
    int rc = walk_days(archive, 0, "", list);
    close(archive);
    if (rc != 0)
        return -1;
    if (list->count > 1)
        qsort(list->items, list->count, sizeof list->items[0], oldest_first);
    return 0;
}

int uwbd_clock_synchronised(void)
{
    struct timex t;
    memset(&t, 0, sizeof t); /* modes 0: read only */
    int state = ntp_adjtime(&t);
    return state >= 0 && state != TIME_ERROR && !(t.status & STA_UNSYNC);
}

int uwbd_retention_apply(const struct uwbd_store *store, int max_scans, double max_age_days, time_t now,
                         int clock_synchronised, int *removed, char *err, size_t errlen)
{
    if (removed)
        *removed = 0;
    /* An unsynchronised clock (a board without RTC booting in 1970, or one
     * jumped ahead) would make every scan look old: age waits for the sync. */
    if (!clock_synchronised)
        max_age_days = 0;
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
        /* Age never takes the newest scan: the archive keeps at least one. */
        int too_old = max_age_days > 0 && list.items[i].mtime.tv_sec < cutoff && i + 1 < list.count;
        if (!too_many && !too_old)
            break; /* oldest first: everything after is newer */
        if (delete_scan(store, &list.items[i], err, errlen) != 0)
            rc = -1;
        else if (removed)
            ++*removed;
    }
    if (uwbd_verdict_log_trim(store, max_scans, max_age_days, now, NULL, err, errlen) != 0)
        rc = -1; /* verdicts.jsonl spans what the archive keeps */
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
