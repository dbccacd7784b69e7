/* Finding archived scans and deleting the oldest. A scan is the group of
 * files <id>.uwbscan, <id>.json and <id>-<kind>.png in one day directory;
 * an image's kind has no '-', so "a-2.json" is not taken for an image of "a".
 * Every directory is opened relative to its parent's fd with O_NOFOLLOW and
 * only regular files are looked at or deleted: a symlink placed in the
 * archive (a day directory pointing elsewhere) is never followed. */
#include "state/retention.h"
#include "state/verdict_log.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/timex.h>
#include <unistd.h>

#include "uwb/monotonic.h"

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

static int push_scan(struct scan_list *list, const char *day, const char *id, size_t id_len,
                     struct timespec mtime)
{
    if (id_len > UWBD_SCAN_ID_MAX)
        return 0;
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

static int by_id(const void *a, const void *b)
{
    return strcmp(((const struct archived_scan *)a)->id, ((const struct archived_scan *)b)->id);
}

/* A scan's .json and .uwbscan were listed apart: sorted by id, the two
 * are neighbours and become one, with the later time. Sorting, not a
 * search per file, so a day of 100,000 files costs n log n. */
static void merge_same_scans(struct scan_list *list, size_t day_start)
{
    size_t n = list->count - day_start;
    if (n < 2)
        return;
    struct archived_scan *day = list->items + day_start;
    qsort(day, n, sizeof *day, by_id);
    size_t kept = 0;
    for (size_t i = 0; i < n; i++) {
        if (kept > 0 && strcmp(day[kept - 1].id, day[i].id) == 0) {
            if (later(day[i].mtime, day[kept - 1].mtime))
                day[kept - 1].mtime = day[i].mtime;
            continue;
        }
        day[kept++] = day[i];
    }
    list->count = day_start + kept;
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
        rc = push_scan(list, day, e->d_name, stem, st.st_mtim);
    }
    closedir(d);
    merge_same_scans(list, day_start);
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

/* The length of the id of the scan a file belongs to: <id>.json,
 * <id>.uwbscan or <id>-<kind>.png with no '-' in kind; 0 for a file that
 * is no scan's. One answer per name, so a day is matched in one pass. */
static size_t scan_id_length(const char *name)
{
    size_t stem;
    if (has_suffix(name, ".json", &stem) || has_suffix(name, ".uwbscan", &stem))
        return stem;
    if (!has_suffix(name, ".png", &stem))
        return 0;
    size_t dash = stem;
    while (dash > 0 && name[dash - 1] != '-')
        dash--;
    /* "-<kind>" needs a kind and an id before it */
    return dash > 1 && dash < stem ? dash - 1 : 0;
}

/* Within a scan, its verdict record goes last: a clean-up cut short
 * leaves a scan that is still listed (and deleted next time), never
 * images nobody lists. */
static int file_rank(const char *name)
{
    size_t stem;
    if (has_suffix(name, ".json", &stem))
        return 2;
    return has_suffix(name, ".uwbscan", &stem) ? 1 : 0;
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

struct doomed_file {
    size_t scan; /* index into the day's doomed scans */
    int rank;    /* file_rank */
    char *name;
};

static int scan_then_rank(const void *a, const void *b)
{
    const struct doomed_file *x = a, *y = b;
    if (x->scan != y->scan)
        return x->scan < y->scan ? -1 : 1;
    return x->rank - y->rank;
}

static int by_day_then_id(const void *a, const void *b)
{
    const struct archived_scan *x = a, *y = b;
    int c = strcmp(x->day, y->day);
    return c ? c : strcmp(x->id, y->id);
}

struct retention_run {
    const struct uwbd_store *store;
    const struct uwbd_retention_budget *budget; /* NULL: none */
    double started_s;
    int removed;
    int out_of_time; /* the stop flag raised or the time used up */
};

/* Checked between two scans: a stop request, or the call's time used up. */
static int out_of_time(struct retention_run *r)
{
    const struct uwbd_retention_budget *b = r->budget;
    if (b &&
        ((b->stop && *b->stop) || (b->max_seconds > 0 && uwb_monotonic_s() - r->started_s >= b->max_seconds)))
        r->out_of_time = 1;
    return r->out_of_time;
}

static void free_doomed(struct doomed_file *files, size_t count)
{
    for (size_t i = 0; i < count; i++)
        free(files[i].name);
    free(files);
}

/* The files of the day's doomed scans (sorted by id), found in one read of
 * the directory; -1 when out of memory. */
static int find_doomed_files(int dayfd, const struct archived_scan *scans, size_t n, struct doomed_file **out,
                             size_t *out_count)
{
    *out = NULL;
    *out_count = 0;
    DIR *d = list_fd(dayfd);
    if (!d)
        return 0;
    struct doomed_file *files = NULL;
    size_t count = 0, cap = 0;
    struct archived_scan key;
    memset(&key, 0, sizeof key);
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d)) != NULL) {
        size_t id_len = e->d_name[0] == '.' ? 0 : scan_id_length(e->d_name);
        if (id_len == 0 || id_len > UWBD_SCAN_ID_MAX)
            continue;
        memcpy(key.id, e->d_name, id_len);
        key.id[id_len] = '\0';
        const struct archived_scan *hit = bsearch(&key, scans, n, sizeof *scans, by_id);
        if (!hit)
            continue;
        if (count == cap) {
            size_t grown_cap = cap ? cap * 2 : 64;
            struct doomed_file *grown = realloc(files, grown_cap * sizeof *grown);
            if (!grown) {
                rc = -1;
                break;
            }
            files = grown;
            cap = grown_cap;
        }
        char *name = strdup(e->d_name);
        if (!name) {
            rc = -1;
            break;
        }
        files[count++] = (struct doomed_file){(size_t)(hit - scans), file_rank(name), name};
    }
    closedir(d);
    if (rc != 0) {
        free_doomed(files, count);
        return -1;
    }
    if (count > 1)
        qsort(files, count, sizeof *files, scan_then_rank);
    *out = files;
    *out_count = count;
    return 0;
}

/* Delete the n doomed scans of one day directory (sorted by id): the
 * directory is read once, whatever its size, and the time budget and the
 * stop flag are looked at between two scans. */
static int delete_from_day(struct retention_run *r, const struct archived_scan *scans, size_t n, char *err,
                           size_t errlen)
{
    const struct uwbd_store *store = r->store;
    const char *day = scans[0].day;
    int dayfd = open_day(store, day);
    if (dayfd < 0) {
        snprintf(err, errlen, "%s/%s: cannot open as a directory: %s", store->archive, day, strerror(errno));
        return -1;
    }
    struct doomed_file *files;
    size_t count;
    if (find_doomed_files(dayfd, scans, n, &files, &count) != 0) {
        snprintf(err, errlen, "%s/%s: out of memory listing the day", store->archive, day);
        close(dayfd);
        return -1;
    }
    int rc = 0;
    size_t i = 0;
    while (i < count && !out_of_time(r)) {
        size_t scan = files[i].scan;
        int failed = 0;
        for (; i < count && files[i].scan == scan; i++) {
            struct stat st;
            if (fstatat(dayfd, files[i].name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode))
                continue;
            if (unlinkat(dayfd, files[i].name, 0) != 0 && errno != ENOENT) {
                snprintf(err, errlen, "%s/%s/%s: cannot delete: %s", store->archive, day, files[i].name,
                         strerror(errno));
                failed = 1;
            }
        }
        if (failed)
            rc = -1;
        else
            r->removed++;
    }
    free_doomed(files, count);
    close(dayfd);
    remove_empty_days(store, day);
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

int uwbd_clock_synchronised_from(const char *timesync_flag, const char **how)
{
    const char *said = NULL;
    struct timex t;
    memset(&t, 0, sizeof t); /* modes 0: read only */
    int state = ntp_adjtime(&t);
    int synchronised = 0;
    if (state >= 0) {
        said = "the kernel says so (adjtimex)";
        synchronised = state != TIME_ERROR && !(t.status & STA_UNSYNC);
    } else {
        /* A sandbox that filters the clock syscalls (ProtectClock=yes, or a
         * SystemCallFilter= without them) refuses even this read. Then
         * systemd-timesyncd's flag, which it creates once it has set the
         * clock, is the next best witness. */
        struct stat st;
        synchronised = timesync_flag != NULL && stat(timesync_flag, &st) == 0;
        said = synchronised ? "systemd-timesyncd says so (its flag file; adjtimex is filtered)"
                            : "adjtimex is filtered (a sandbox) and systemd-timesyncd has not said so";
    }
    if (how)
        *how = said;
    return synchronised;
}

int uwbd_clock_synchronised(void)
{
    return uwbd_clock_synchronised_from(UWBD_TIMESYNC_FLAG, NULL);
}

int uwbd_retention_apply_within(const struct uwbd_store *store, int max_scans, double max_age_days,
                                time_t now, int clock_synchronised, struct uwbd_retention_budget *budget,
                                int *removed, char *err, size_t errlen)
{
    if (removed)
        *removed = 0;
    if (budget)
        budget->cut_short = 0;
    /* An unsynchronised clock (a board without RTC booting in 1970, or one
     * jumped ahead) would make every scan look old: age waits for the sync. */
    if (!clock_synchronised)
        max_age_days = 0;
    if (max_scans <= 0 && max_age_days <= 0)
        return 0;
    struct retention_run run = {.store = store, .budget = budget, .started_s = uwb_monotonic_s()};
    struct scan_list list;
    if (list_scans(store, &list) != 0) {
        free(list.items);
        snprintf(err, errlen, "%s: out of memory listing the archive", store->archive);
        return -1;
    }
    size_t excess = max_scans > 0 && list.count > (size_t)max_scans ? list.count - (size_t)max_scans : 0;
    time_t cutoff = max_age_days > 0 ? now - (time_t)(max_age_days * 86400.0) : 0;
    size_t doomed = 0;
    for (; doomed < list.count; doomed++) {
        int too_many = doomed < excess;
        /* Age never takes the newest scan: the archive keeps at least one. */
        int too_old = max_age_days > 0 && list.items[doomed].mtime.tv_sec < cutoff && doomed + 1 < list.count;
        if (!too_many && !too_old)
            break; /* oldest first: everything after is newer */
    }
    int capped = budget && budget->max_deletions > 0 && doomed > (size_t)budget->max_deletions;
    if (capped)
        doomed = (size_t)budget->max_deletions; /* the oldest; the rest at the next call */
    /* Grouped by day, so each day directory is read once. */
    if (doomed > 1)
        qsort(list.items, doomed, sizeof list.items[0], by_day_then_id);
    int rc = 0;
    for (size_t first = 0; first < doomed && !out_of_time(&run);) {
        size_t last = first + 1;
        while (last < doomed && strcmp(list.items[last].day, list.items[first].day) == 0)
            last++;
        if (delete_from_day(&run, list.items + first, last - first, err, errlen) != 0)
            rc = -1;
        first = last;
    }
    free(list.items);
    if (removed)
        *removed = run.removed;
    if (budget)
        budget->cut_short = capped || run.out_of_time;
    if (budget && budget->stop && *budget->stop)
        return rc; /* stopping: the log's trim waits for the next cycle */
    if (uwbd_verdict_log_trim(store, max_scans, max_age_days, now, NULL, err, errlen) != 0)
        rc = -1; /* verdicts.jsonl spans what the archive keeps */
    return rc;
}

int uwbd_retention_apply(const struct uwbd_store *store, int max_scans, double max_age_days, time_t now,
                         int clock_synchronised, int *removed, char *err, size_t errlen)
{
    return uwbd_retention_apply_within(store, max_scans, max_age_days, now, clock_synchronised, NULL, removed,
                                       err, errlen);
}

int uwbd_archive_count(const struct uwbd_store *store)
{
    struct scan_list list;
    int rc = list_scans(store, &list);
    int n = rc == 0 ? (int)list.count : -1;
    free(list.items);
    return n;
}
