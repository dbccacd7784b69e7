/* The state directory: creating its rooms, tidying what a crash left, and
 * naming files inside it. */
#include "state/store.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "uwb/atomic_file.h"
#include "uwb/regular_file.h"
#include "util/log.h"

int uwbd_path_join(char *out, size_t n, const char *dir, const char *name)
{
    int w = snprintf(out, n, "%s/%s", dir, name);
    return w < 0 || (size_t)w >= n ? -1 : 0;
}

static int make_dir(const char *path, char *err, size_t errlen)
{
    if (mkdir(path, 0755) == 0 || errno == EEXIST) {
        struct stat st;
        if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
            return 0;
        snprintf(err, errlen, "%s: exists but is not a directory", path);
        return -1;
    }
    snprintf(err, errlen, "%s: cannot create directory: %s", path, strerror(errno));
    return -1;
}

/* mkdir -p */
static int make_dirs(const char *path, char *err, size_t errlen)
{
    char buf[UWBD_PATH_MAX];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf) {
        snprintf(err, errlen, "%.64s...: path too long", path);
        return -1;
    }
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (make_dir(buf, err, errlen) != 0)
            return -1;
        *p = '/';
    }
    return make_dir(buf, err, errlen);
}

/* At most this many files that are not ours are named one by one in the
 * start-up warning; the rest are counted. */
#define FOREIGN_NAMED_MAX 8

struct cleanup {
    int removed;
    int foreign; /* hidden files or symlinks left alone */
};

static int all_digits(const char *s, size_t len)
{
    if (strlen(s) != len)
        return 0;
    for (size_t i = 0; i < len; i++)
        if (s[i] < '0' || s[i] > '9')
            return 0;
    return 1;
}

static void note_foreign(struct cleanup *c, const char *where, const char *name, const char *what)
{
    if (c->foreign++ < FOREIGN_NAMED_MAX)
        uwbd_log(UWBD_LOG_WARNING, "state directory: %s/%s is %s, not uwbd's: left alone", where, name, what);
}

/* Remove our temporaries (uwb_atomic_file_is_temporary_name) from one directory
 * uwbd writes, given as an fd opened without following a symlink. Anything
 * else hidden, and any symlink, is named and left alone. `levels` are the
 * digit-widths of the subdirectories to descend into (archive/YYYY/MM/DD),
 * each opened with O_NOFOLLOW relative to its parent's fd. */
static void clean_directory(int dfd, const char *where, const int *levels, struct cleanup *c)
{
    int lfd = dup(dfd);
    DIR *d = lfd >= 0 ? fdopendir(lfd) : NULL;
    if (!d) {
        if (lfd >= 0)
            close(lfd);
        return;
    }
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const char *name = e->d_name;
        if (strcmp(name, ".") == 0 || strcmp(name, "..") == 0)
            continue;
        struct stat st;
        if (fstatat(dfd, name, &st, AT_SYMLINK_NOFOLLOW) != 0)
            continue;
        if (S_ISLNK(st.st_mode)) {
            note_foreign(c, where, name, "a symbolic link");
        } else if (S_ISDIR(st.st_mode)) {
            if (levels == NULL || levels[0] == 0 || !all_digits(name, (size_t)levels[0]))
                continue;
            int sub = openat(dfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
            if (sub < 0)
                continue;
            char sub_where[UWBD_PATH_MAX + 300];
            snprintf(sub_where, sizeof sub_where, "%s/%s", where, name);
            clean_directory(sub, sub_where, levels + 1, c);
            close(sub);
        } else if (S_ISREG(st.st_mode) && uwb_atomic_file_is_temporary_name(name)) {
            if (unlinkat(dfd, name, 0) == 0)
                ++c->removed;
        } else if (name[0] == '.') {
            note_foreign(c, where, name, "a hidden file");
        }
    }
    closedir(d);
}

/* The directories uwbd writes: the root, baseline/, baseline/history/ and
 * archive/YYYY/MM/DD/. Nothing else under the root is looked at. */
static void remove_stale_temporaries(const struct uwbd_store *store, struct cleanup *c)
{
    static const int archive_levels[] = {4, 2, 2, 0};
    int root = open(store->root, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (root < 0)
        return;
    clean_directory(root, store->root, NULL, c);
    int baseline = openat(root, "baseline", O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (baseline >= 0) {
        clean_directory(baseline, store->baseline_dir, NULL, c);
        int history = openat(baseline, "history", O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (history >= 0) {
            clean_directory(history, store->baseline_history, NULL, c);
            close(history);
        }
        close(baseline);
    }
    int archive = openat(root, "archive", O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (archive >= 0) {
        clean_directory(archive, store->archive, archive_levels, c);
        close(archive);
    }
    close(root);
    if (c->foreign > FOREIGN_NAMED_MAX)
        uwbd_log(UWBD_LOG_WARNING, "state directory: %d more files that are not uwbd's left alone",
                 c->foreign - FOREIGN_NAMED_MAX);
}

int uwbd_store_open(struct uwbd_store *store, const char *state_dir, int *repairs, char *err, size_t errlen)
{
    memset(store, 0, sizeof *store);
    if (repairs)
        *repairs = 0;
    if (make_dirs(state_dir, err, errlen) != 0)
        return -1;
    char resolved[PATH_MAX];
    if (!realpath(state_dir, resolved)) {
        snprintf(err, errlen, "%s: cannot resolve: %s", state_dir, strerror(errno));
        return -1;
    }
    if (snprintf(store->root, sizeof store->root, "%s", resolved) >= (int)sizeof store->root) {
        snprintf(err, errlen, "%.64s...: state directory path too long", resolved);
        return -1;
    }
    uwbd_path_join(store->archive, sizeof store->archive, store->root, "archive");
    uwbd_path_join(store->baseline_dir, sizeof store->baseline_dir, store->root, "baseline");
    uwbd_path_join(store->baseline_history, sizeof store->baseline_history, store->baseline_dir, "history");
    uwbd_path_join(store->verdict_log, sizeof store->verdict_log, store->root, "verdicts.jsonl");
    uwbd_path_join(store->latest, sizeof store->latest, store->root, "latest.json");
    if (make_dir(store->archive, err, errlen) != 0 || make_dir(store->baseline_dir, err, errlen) != 0 ||
        make_dir(store->baseline_history, err, errlen) != 0)
        return -1;
    /* The root itself must be writable: find out now rather than at the first scan. */
    if (access(store->root, W_OK) != 0) {
        snprintf(err, errlen, "%s: not writable: %s", store->root, strerror(errno));
        return -1;
    }
    struct cleanup cleanup = {0, 0};
    remove_stale_temporaries(store, &cleanup);
    if (repairs)
        *repairs = cleanup.removed;
    return 0;
}

int uwbd_store_lock(const char *state_dir, char *err, size_t errlen)
{
    if (make_dirs(state_dir, err, errlen) != 0)
        return -1;
    char path[UWBD_PATH_MAX + 16];
    /* Unreachable on purpose: make_dirs refused a state_dir this long. */
    if (uwbd_path_join(path, sizeof path, state_dir, "uwbd.lock") != 0) {
        snprintf(err, errlen, "%.64s...: state directory path too long", state_dir);
        return -1;
    }
    const char *problem = NULL;
    int fd = uwb_open_regular(path, O_RDWR | O_CREAT | O_NOFOLLOW, 0644, &problem);
    if (fd < 0) {
        snprintf(err, errlen, "%s: cannot open: %s", path, problem);
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        int e = errno;
        close(fd);
        if (e == EWOULDBLOCK)
            snprintf(err, errlen, "%s: another uwbd is using this state directory", state_dir);
        else
            snprintf(err, errlen, "%s: cannot lock: %s", path, strerror(e));
        return -1;
    }
    return fd;
}

int uwbd_store_day_dir(const struct uwbd_store *store, const struct tm *utc, char *dir, size_t n, char *err,
                       size_t errlen)
{
    int w = snprintf(dir, n, "%s/%04d/%02d/%02d", store->archive, utc->tm_year + 1900, utc->tm_mon + 1,
                     utc->tm_mday);
    if (w < 0 || (size_t)w >= n) {
        snprintf(err, errlen, "%s: archive path too long", store->archive);
        return -1;
    }
    return make_dirs(dir, err, errlen);
}

void uwbd_safe_scan_id(const char *in, char *out, size_t n)
{
    size_t limit = n - 1 < UWBD_SCAN_ID_MAX ? n - 1 : UWBD_SCAN_ID_MAX;
    size_t j = 0;
    for (size_t i = 0; in && in[i] && j < limit; i++) {
        char c = in[i];
        int safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                   c == '_' || c == '.';
        out[j++] = safe ? c : '_';
    }
    out[j] = '\0';
    if (out[0] == '.')
        out[0] = '_';
}

int uwbd_write_json_file(const char *path, const char *json, char *err, size_t errlen)
{
    struct atomic_file af;
    if (uwb_atomic_file_open(&af, path, err, errlen) != 0)
        return -1;
    fprintf(af.fp, "%s\n", json); /* a failed write shows at the commit's flush */
    return uwb_atomic_file_commit(&af, err, errlen);
}

void uwbd_utc_text(time_t t, char *buf, size_t n)
{
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(buf, n, "%Y-%m-%dT%H:%M:%SZ", &tm);
}
