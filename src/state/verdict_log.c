/* verdicts.jsonl (grows by whole lines, trimmed by retention) and
 * latest.json (atomic). */
#include "state/verdict_log.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include "uwb/atomic_file.h"
#include "uwb/regular_file.h"

#define TAIL_BLOCK 65536
/* A verdict line is a few kilobytes; a "line" longer than this is damage. */
#define MAX_LINE ((size_t)256 * 1024)

/* Every file of the state directory is opened with O_NOFOLLOW and must be
 * a regular file (uwb_open_regular): a symlink put in place of
 * verdicts.jsonl or latest.json is refused, never written through (appends
 * and trims would otherwise reach another file), and a FIFO is refused
 * rather than waited on for ever. */

int uwbd_verdict_log_append(const struct uwbd_store *store, const char *json, char *err, size_t errlen)
{
    size_t n = strlen(json);
    if (n == 0 || memchr(json, '\n', n)) {
        snprintf(err, errlen, "%s: refusing to append an empty or multi-line record", store->verdict_log);
        return -1;
    }
    const char *problem = NULL;
    int fd = uwb_open_regular(store->verdict_log, O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW, 0644, &problem);
    if (fd < 0) {
        snprintf(err, errlen, "%s: cannot open for appending: %s", store->verdict_log, problem);
        return -1;
    }
    struct stat st;
    off_t before = fstat(fd, &st) == 0 ? st.st_size : -1;
    /* The record and its newline in one write. */
    struct iovec line[2] = {{.iov_base = (void *)json, .iov_len = n}, {.iov_base = "\n", .iov_len = 1}};
    ssize_t w = writev(fd, line, 2);
    int e = errno;
    int rc = 0;
    if (w >= 0 && (size_t)w < n + 1) {
        /* A short write: once more for the rest. Still short, the torn line
         * is taken back, and the system's reason said (ENOSPC: the disk
         * is full). */
        size_t done = (size_t)w;
        struct iovec rest[2];
        int parts = 0;
        if (done < n)
            rest[parts++] = (struct iovec){.iov_base = (void *)(json + done), .iov_len = n - done};
        rest[parts++] = (struct iovec){.iov_base = "\n", .iov_len = 1};
        ssize_t more = writev(fd, rest, parts);
        e = more < 0 ? errno : 0;
        if (more != (ssize_t)(n + 1 - done)) {
            if (before >= 0 && ftruncate(fd, before) != 0 && e == 0)
                e = errno;
            snprintf(err, errlen, "%s: cannot append a verdict: short write, then %s", store->verdict_log,
                     e ? strerror(e) : "another short one");
            rc = -1;
        }
    } else if (w < 0) {
        snprintf(err, errlen, "%s: cannot append a verdict: %s", store->verdict_log, strerror(e));
        rc = -1;
    }
    if (rc == 0 && fsync(fd) != 0) {
        snprintf(err, errlen, "%s: cannot fsync: %s", store->verdict_log, strerror(errno));
        rc = -1;
    }
    if (close(fd) != 0 && rc == 0) {
        snprintf(err, errlen, "%s: cannot close: %s", store->verdict_log, strerror(errno));
        rc = -1;
    }
    return rc;
}

/* Open the log and take its size. Returns 1 when it does not exist yet
 * (nothing logged), 0 with *fd open, or -1 with err filled. */
static int open_log(const struct uwbd_store *store, int flags, int *fd, off_t *size, char *err, size_t errlen)
{
    const char *problem = NULL;
    *fd = uwb_open_regular(store->verdict_log, flags | O_NOFOLLOW, 0, &problem);
    if (*fd < 0) {
        if (errno == ENOENT)
            return 1;
        snprintf(err, errlen, "%s: cannot open: %s", store->verdict_log, problem);
        return -1;
    }
    struct stat st;
    if (fstat(*fd, &st) != 0) {
        snprintf(err, errlen, "%s: cannot stat: %s", store->verdict_log, strerror(errno));
        close(*fd);
        return -1;
    }
    *size = st.st_size;
    return 0;
}

int uwbd_verdict_log_repair(const struct uwbd_store *store, long *dropped, char *err, size_t errlen)
{
    *dropped = 0;
    int fd;
    off_t size;
    int opened = open_log(store, O_RDWR, &fd, &size, err, errlen);
    if (opened != 0)
        return opened > 0 ? 0 : -1;
    /* Walk back from the end to the last newline. */
    off_t end = size, keep = 0;
    char buf[4096];
    while (end > 0) {
        off_t start = end > (off_t)sizeof buf ? end - (off_t)sizeof buf : 0;
        ssize_t r = pread(fd, buf, (size_t)(end - start), start);
        if (r != end - start) {
            snprintf(err, errlen, "%s: cannot read: %s", store->verdict_log,
                     r < 0 ? strerror(errno) : "short read");
            close(fd);
            return -1;
        }
        ssize_t i = r;
        while (i > 0 && buf[i - 1] != '\n')
            i--;
        if (i > 0) {
            keep = start + i;
            break;
        }
        end = start;
    }
    int rc = 0;
    if (keep < size) {
        if (ftruncate(fd, keep) != 0 || fsync(fd) != 0) {
            snprintf(err, errlen, "%s: cannot cut off a torn last line: %s", store->verdict_log,
                     strerror(errno));
            rc = -1;
        } else {
            *dropped = (long)(size - keep);
        }
    }
    close(fd);
    return rc;
}

void uwbd_verdict_lines_free(char **lines, int count)
{
    for (int i = 0; lines && i < count; i++)
        free(lines[i]);
    free(lines);
}

/* Keep text[0..len) if it is one JSON object; returns a malloc'd copy or NULL. */
static char *valid_line(const char *text, size_t len)
{
    if (memchr(text, '\0', len))
        return NULL; /* a NUL inside would cut the line short for every reader */
    cJSON *o = cJSON_ParseWithLength(text, len);
    int ok = o && cJSON_IsObject(o);
    cJSON_Delete(o);
    if (!ok)
        return NULL;
    char *copy = malloc(len + 1);
    if (copy) {
        memcpy(copy, text, len);
        copy[len] = '\0';
    }
    return copy;
}

/* The log's lines from its end backwards, one read block at a time, so
 * that reading back past any number of unreadable lines takes no more
 * memory than one line: a line is gathered at the end of `line` as its
 * blocks come in (right to left); one longer than MAX_LINE is only
 * counted, never held. */
struct backward_reader {
    int fd;
    off_t pos;                /* bytes [0, pos) not read yet */
    char block[TAIL_BLOCK];   /* [0, block_len) read from pos */
    size_t block_len, cursor; /* block[0, cursor) not looked at yet */
    char *line;               /* MAX_LINE bytes; the line gathered is its last line_len */
    size_t line_len;
    int overlong; /* the line gathered ran past MAX_LINE */
    int torn;     /* the line gathered is the file's unterminated last one */
};

enum { LINE_NONE = 0, LINE_WHOLE = 1, LINE_DAMAGED = 2 };

/* Prepend block[from, to) to the line gathered. */
static void gather(struct backward_reader *r, size_t from, size_t to)
{
    size_t len = to - from;
    if (r->overlong || r->line_len + len > MAX_LINE) {
        r->overlong = 1;
        return;
    }
    memcpy(r->line + MAX_LINE - r->line_len - len, r->block + from, len);
    r->line_len += len;
}

/* The next line back: LINE_WHOLE with its text in line[MAX_LINE - *len,
 * MAX_LINE), LINE_DAMAGED for one torn or too long, LINE_NONE at the start of
 * the file; -1 with err on a read error. Empty lines are passed over. */
static int previous_line(struct backward_reader *r, const char **text, size_t *len, const char *path,
                         char *err, size_t errlen)
{
    for (;;) {
        if (r->cursor == 0 && r->pos > 0) {
            size_t want = r->pos > (off_t)TAIL_BLOCK ? TAIL_BLOCK : (size_t)r->pos;
            ssize_t got = pread(r->fd, r->block, want, r->pos - (off_t)want);
            if (got != (ssize_t)want) {
                snprintf(err, errlen, "%s: cannot read: %s", path, got < 0 ? strerror(errno) : "short read");
                return -1;
            }
            r->pos -= (off_t)want;
            r->block_len = r->cursor = want;
        }
        size_t end = r->cursor, i = end;
        while (i > 0 && r->block[i - 1] != '\n')
            i--;
        gather(r, i, end);
        int at_start = i == 0 && r->pos == 0;
        if (i == 0 && !at_start) {
            r->cursor = 0; /* the line began in an earlier block */
            continue;
        }
        r->cursor = i > 0 ? i - 1 : 0; /* before the newline that ends the previous line */
        int kind = r->torn || r->overlong ? LINE_DAMAGED : r->line_len > 0 ? LINE_WHOLE : LINE_NONE;
        *text = r->line + MAX_LINE - r->line_len;
        *len = r->line_len;
        r->line_len = 0;
        r->overlong = r->torn = 0;
        if (kind != LINE_NONE)
            return kind;
        if (at_start)
            return LINE_NONE;
    }
}

int uwbd_verdict_log_tail(const struct uwbd_store *store, int n, char ***lines_out, int *count_out,
                          int *skipped_out, char *err, size_t errlen)
{
    *lines_out = NULL;
    *count_out = 0;
    if (skipped_out)
        *skipped_out = 0;
    if (n <= 0)
        return 0;
    int fd;
    off_t size;
    int opened = open_log(store, O_RDONLY, &fd, &size, err, errlen);
    if (opened != 0)
        return opened > 0 ? 0 : -1;
    struct backward_reader *r = calloc(1, sizeof *r);
    char **lines = calloc((size_t)n, sizeof *lines);
    char *line = malloc(MAX_LINE);
    if (!r || !lines || !line) {
        free(r);
        free(lines);
        free(line);
        close(fd);
        snprintf(err, errlen, "%s: out of memory", store->verdict_log);
        return -1;
    }
    r->fd = fd;
    r->pos = size;
    r->line = line;
    /* A last line without its newline is torn (a crash mid-write). */
    char last = '\n';
    if (size > 0 && pread(fd, &last, 1, size - 1) == 1 && last != '\n')
        r->torn = 1;
    else if (size > 0)
        r->pos = size - 1; /* the final newline ends the last line */
    /* Back until n valid lines are in hand or the start: lines that cannot
     * be read (damage after a crash, a full disk's) hide nothing before them. */
    int count = 0, skipped = 0, rc = 0;
    while (count < n) {
        const char *text;
        size_t len;
        int kind = previous_line(r, &text, &len, store->verdict_log, err, errlen);
        if (kind < 0) {
            rc = -1;
            break;
        }
        if (kind == LINE_NONE)
            break;
        char *copy = kind == LINE_WHOLE ? valid_line(text, len) : NULL;
        if (copy)
            lines[count++] = copy;
        else
            skipped++;
    }
    close(fd);
    free(line);
    free(r);
    if (rc != 0) {
        uwbd_verdict_lines_free(lines, count);
        return -1;
    }
    /* Collected newest first; hand them out oldest first. */
    for (int i = 0; i < count / 2; i++) {
        char *t = lines[i];
        lines[i] = lines[count - 1 - i];
        lines[count - 1 - i] = t;
    }
    *lines_out = lines;
    *count_out = count;
    if (skipped_out)
        *skipped_out = skipped;
    return 0;
}

/* One line of the log during a trim. */
struct log_line {
    size_t start, len; /* without the newline */
    int has_time;
    time_t created;
};

/* The verdict's "created" time (UTC, "YYYY-MM-DDTHH:MM:SSZ"); 0 when the
 * line is not a verdict with a readable one. */
static int line_created(const char *text, size_t len, time_t *created)
{
    cJSON *o = cJSON_ParseWithLength(text, len);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(o, "created");
    struct tm tm = {0};
    // NOLINTNEXTLINE(cert-err34-c): uwbd writes this field; a bad one only misdates a line for trimming
    int ok = cJSON_IsString(c) && sscanf(c->valuestring, "%d-%d-%dT%d:%d:%d", &tm.tm_year, &tm.tm_mon,
                                         &tm.tm_mday, &tm.tm_hour, &tm.tm_min, &tm.tm_sec) == 6;
    cJSON_Delete(o);
    if (!ok)
        return 0;
    tm.tm_year -= 1900;
    tm.tm_mon -= 1;
    *created = timegm(&tm);
    return 1;
}

/* Split text into its complete lines; a torn last line is left out. */
static struct log_line *split_lines(const char *text, size_t size, size_t *count)
{
    size_t n = 0;
    for (size_t i = 0; i < size; i++)
        n += text[i] == '\n';
    *count = n;
    struct log_line *lines = calloc(n ? n : 1, sizeof *lines);
    if (!lines)
        return NULL;
    size_t start = 0, k = 0;
    for (size_t i = 0; i < size && k < n; i++) {
        if (text[i] != '\n')
            continue;
        lines[k].start = start;
        lines[k].len = i - start;
        k++;
        start = i + 1;
    }
    return lines;
}

/* Give each line without a readable time its predecessor's (the log is
 * in time order, so that is its best estimate); leading ones take the first
 * known time. Returns 0 when no line has a time. */
static int fill_times(struct log_line *lines, size_t count)
{
    size_t first = 0;
    while (first < count && !lines[first].has_time)
        first++;
    if (first == count)
        return 0;
    for (size_t i = 0; i < count; i++) {
        if (lines[i].has_time)
            continue;
        lines[i].created = i < first ? lines[first].created : lines[i - 1].created;
        lines[i].has_time = 1;
    }
    return 1;
}

static int write_kept(const struct uwbd_store *store, const char *text, const struct log_line *lines,
                      const unsigned char *keep, size_t count, char *err, size_t errlen)
{
    struct atomic_file af;
    if (uwb_atomic_file_open(&af, store->verdict_log, err, errlen) != 0)
        return -1;
    for (size_t i = 0; i < count; i++) {
        if (!keep[i])
            continue;
        if (fwrite(text + lines[i].start, 1, lines[i].len, af.fp) != lines[i].len ||
            fputc('\n', af.fp) == EOF) {
            snprintf(err, errlen, "%s: cannot write the trimmed log: %s", store->verdict_log,
                     strerror(errno));
            uwb_atomic_file_abort(&af);
            return -1;
        }
    }
    return uwb_atomic_file_commit(&af, err, errlen);
}

int uwbd_verdict_log_trim(const struct uwbd_store *store, int max_lines, double max_age_days, time_t now,
                          int *dropped, char *err, size_t errlen)
{
    if (dropped)
        *dropped = 0;
    if (max_lines <= 0 && max_age_days <= 0)
        return 0;
    int fd;
    off_t size;
    int opened = open_log(store, O_RDONLY, &fd, &size, err, errlen);
    if (opened != 0)
        return opened > 0 ? 0 : -1;
    int rc = -1;
    struct log_line *lines = NULL;
    unsigned char *keep = NULL;
    char *text = malloc(size > 0 ? (size_t)size : 1);
    ssize_t r = text ? pread(fd, text, (size_t)size, 0) : -1;
    int e = errno;
    close(fd);
    if (!text || r != (ssize_t)size) {
        snprintf(err, errlen, "%s: cannot read for trimming: %s", store->verdict_log,
                 !text   ? "out of memory"
                 : r < 0 ? strerror(e)
                         : "short read");
        goto done;
    }
    size_t count;
    lines = split_lines(text, (size_t)size, &count);
    keep = lines ? malloc(count ? count : 1) : NULL;
    if (!keep) {
        snprintf(err, errlen, "%s: out of memory trimming", store->verdict_log);
        goto done;
    }
    /* The same rules as the archive's: the newest max_lines, nothing older
     * than the cutoff (to the second, as retention.c counts). */
    size_t excess = max_lines > 0 && count > (size_t)max_lines ? count - (size_t)max_lines : 0;
    int use_age = 0;
    time_t cutoff = 0;
    if (max_age_days > 0) {
        cutoff = now - (time_t)(max_age_days * 86400.0);
        for (size_t i = excess; i < count; i++)
            lines[i].has_time = line_created(text + lines[i].start, lines[i].len, &lines[i].created);
        use_age = fill_times(lines + excess, count - excess);
    }
    size_t kept = 0;
    for (size_t i = 0; i < count; i++) {
        keep[i] = i >= excess && !(use_age && lines[i].created < cutoff);
        kept += keep[i];
    }
    /* Rewrite only when a line goes: an unchanged log is not written at all
     * (a flash card's wear). A torn last line is not kept by a rewrite. */
    rc = 0;
    if (kept < count) {
        rc = write_kept(store, text, lines, keep, count, err, errlen);
        if (rc == 0 && dropped)
            *dropped = (int)(count - kept);
    }
done:
    free(keep);
    free(lines);
    free(text);
    return rc;
}

int uwbd_latest_write(const struct uwbd_store *store, const char *json, char *err, size_t errlen)
{
    return uwbd_write_json_file(store->latest, json, err, errlen);
}

int uwbd_latest_read(const struct uwbd_store *store, char **json, char *err, size_t errlen)
{
    *json = NULL;
    char *text = NULL;
    const char *problem = NULL;
    int fd = uwb_open_regular(store->latest, O_RDONLY | O_NOFOLLOW, 0, &problem);
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        int e = errno;
        if (fd >= 0)
            close(fd);
        if (e == ENOENT)
            return 0;
        snprintf(err, errlen, "%s: cannot open: %s", store->latest, problem ? problem : strerror(e));
        goto fail;
    }
    text = malloc(MAX_LINE + 1);
    size_t len = text ? fread(text, 1, MAX_LINE, f) : 0;
    fclose(f);
    if (!text) {
        snprintf(err, errlen, "%s: out of memory", store->latest);
        goto fail;
    }
    while (len > 0 && (text[len - 1] == '\n' || text[len - 1] == '\r'))
        len--;
    text[len] = '\0';
    cJSON *o = memchr(text, '\0', len) ? NULL : cJSON_ParseWithLength(text, len);
    int ok = o && cJSON_IsObject(o);
    cJSON_Delete(o);
    if (!ok) {
        snprintf(err, errlen, "%s: not one JSON object", store->latest);
        goto fail;
    }
    *json = text;
    return 0;
fail:
    free(text);
    return -1;
}

int uwbd_verdict_log_latest_created(const struct uwbd_store *store, char *created, size_t n)
{
    created[0] = '\0';
    char **lines = NULL, err[256];
    int count = 0;
    if (uwbd_verdict_log_tail(store, 1, &lines, &count, NULL, err, sizeof err) != 0 || count < 1) {
        uwbd_verdict_lines_free(lines, count);
        return 0;
    }
    cJSON *o = cJSON_Parse(lines[0]);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(o, "created");
    if (cJSON_IsString(c) && c->valuestring)
        snprintf(created, n, "%s", c->valuestring);
    cJSON_Delete(o);
    uwbd_verdict_lines_free(lines, count);
    return created[0] != '\0';
}

/* The "created" text of a verdict line into out ("" when it has none). */
static void created_of(const char *line, char *out, size_t n)
{
    out[0] = '\0';
    cJSON *o = cJSON_Parse(line);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(o, "created");
    if (cJSON_IsString(c) && c->valuestring)
        snprintf(out, n, "%s", c->valuestring);
    cJSON_Delete(o);
}

/* latest.json whole, but a newer verdict in the log: on a full disk the
 * line may go in (room left in the log's last page) while latest.json
 * cannot be replaced. The newer by its time is the latest. */
static char *newer_of_latest_and_log(const struct uwbd_store *store, char *latest, char *note, size_t n)
{
    char **lines = NULL, err[512], at_latest[64], at_log[64];
    int count = 0;
    if (uwbd_verdict_log_tail(store, 1, &lines, &count, NULL, err, sizeof err) == 0 && count == 1) {
        created_of(latest, at_latest, sizeof at_latest);
        created_of(lines[0], at_log, sizeof at_log);
        if (at_latest[0] && at_log[0] && strcmp(at_log, at_latest) > 0) {
            snprintf(note, n,
                     "%.600s (%s) is older than the newest line of verdicts.jsonl (%s): it could not be "
                     "replaced (a full disk?); the latest verdict is taken from verdicts.jsonl",
                     store->latest, at_latest, at_log);
            free(latest);
            latest = lines[0];
            lines[0] = NULL;
        }
    }
    uwbd_verdict_lines_free(lines, count);
    return latest;
}

char *uwbd_latest_line_at_start(const struct uwbd_store *store, char *note, size_t n)
{
    note[0] = '\0';
    char err[1024], *latest = NULL;
    int read_rc = uwbd_latest_read(store, &latest, err, sizeof err);
    if (read_rc == 0 && latest)
        return newer_of_latest_and_log(store, latest, note, n);
    /* Missing counts like damaged: verdicts.jsonl may still hold verdicts
     * (latest.json deleted, or never written on a full disk). */
    if (read_rc == 0)
        snprintf(err, sizeof err, "%.900s: missing", store->latest);
    char **lines = NULL, log_err[512];
    int count = 0;
    if (uwbd_verdict_log_tail(store, 1, &lines, &count, NULL, log_err, sizeof log_err) == 0 && count == 1) {
        latest = lines[0];
        lines[0] = NULL;
        snprintf(note, n, "%.700s; the latest verdict is taken from verdicts.jsonl until the next scan", err);
    } else if (read_rc != 0) {
        snprintf(note, n, "%.700s; it is replaced at the next scan", err);
    }
    uwbd_verdict_lines_free(lines, count);
    return latest;
}
