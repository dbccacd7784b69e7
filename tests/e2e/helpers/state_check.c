/* state_check: what the fault tests (tests/e2e/test_daemon_faults.sh) ask
 * of a state directory and of the daemon's JSON replies, with the project's
 * own readers instead of a Python interpreter or jq, which `make test` does not install.
 *
 *   state_check tree STATE_DIR [--verdict-files]
 *       Every file whole: no temporary left (any hidden file, e.g.
 *       atomic_file's ".uwbd-tmp.NAME.XXXXXX.part"), every
 *       .json one JSON object, every line of verdicts.jsonl one JSON object
 *       ending in a newline, every .uwbscan readable by the uwbscan reader,
 *       every .png decoded to its last row and ending in its IEND chunk, and
 *       baseline/current.json naming the scan in current.uwbscan.
 *       --verdict-files: also every scan_file and image a verdict line names
 *       exists (only when retention has deleted nothing).
 *       Prints one summary line; each problem goes to stderr; exit 1 if any.
 *   state_check get KEY... < JSON
 *       One line per KEY (dotted path, array items by index: images.0) from
 *       the JSON object on stdin: strings bare, anything else as JSON,
 *       "(missing)" when absent. Exit 2 if stdin is not a JSON object.
 *   state_check kill-on-write PID SKIP DELAY_US TIMEOUT_S DIR...
 *       Watches the DIRs (inotify) for the daemon's writes: a temporary
 *       being created (a hidden name, atomic_file's ".uwbd-tmp.NAME.XXXXXX.part") or verdicts.jsonl
 *       growing. At the (SKIP+1)-th one it waits DELAY_US microseconds and
 *       sends SIGKILL to PID, so the kill lands while that file is being
 *       written. Prints the file's path; exit 0 when it killed, 1 when
 *       TIMEOUT_S passed or PID ended first (nothing sent). */
#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <png.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "state/store.h"
#include "uwb/monotonic.h"
#include "uwb/read_file.h"
#include "uwb/scan.h"

/* Far above anything the daemon writes; bounds what a broken file costs. */
#define MAX_FILE_BYTES ((size_t)64 * 1024 * 1024)

struct tally {
    int problems, json, lines, uwbscan, png, other;
    int verdict_files; /* check the files verdict lines name */
};

static void problem(struct tally *t, const char *path, const char *what)
{
    fprintf(stderr, "state_check: %s: %s\n", path, what);
    t->problems++;
}

/* A problem the reader has described already, path included. */
static void read_problem(struct tally *t, const char *message)
{
    fprintf(stderr, "state_check: %s\n", message);
    t->problems++;
}

static int is_object(const char *text, size_t len)
{
    cJSON *o = cJSON_ParseWithLength(text, len);
    int ok = cJSON_IsObject(o);
    cJSON_Delete(o);
    return ok;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

static int is_regular_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* A file the daemon writes as one JSON object and a newline. */
static void check_json(struct tally *t, const char *path)
{
    char *text, err[1024];
    size_t len;
    if (uwb_read_file(path, MAX_FILE_BYTES, &text, &len, err, sizeof err) != UWB_READ_OK)
        read_problem(t, err);
    else if (len == 0 || text[len - 1] != '\n')
        problem(t, path, "does not end in a newline (cut short?)");
    else if (!is_object(text, len - 1))
        problem(t, path, "not one JSON object");
    t->json++;
    free(text);
}

static void check_named_files(struct tally *t, const char *log, int line_no, const cJSON *verdict)
{
    char where[4200];
    const cJSON *scan = cJSON_GetObjectItemCaseSensitive(verdict, "scan_file");
    if (cJSON_IsString(scan) && !is_regular_file(scan->valuestring)) {
        snprintf(where, sizeof where, "line %d names %s, which is not there", line_no, scan->valuestring);
        problem(t, log, where);
    }
    const cJSON *image;
    cJSON_ArrayForEach(image, cJSON_GetObjectItemCaseSensitive(verdict, "images"))
    {
        if (cJSON_IsString(image) && !is_regular_file(image->valuestring)) {
            snprintf(where, sizeof where, "line %d names %s, which is not there", line_no,
                     image->valuestring);
            problem(t, log, where);
        }
    }
}

static void check_verdict_log(struct tally *t, const char *path)
{
    char *text, err[1024];
    size_t len;
    if (uwb_read_file(path, MAX_FILE_BYTES, &text, &len, err, sizeof err) != UWB_READ_OK) {
        read_problem(t, err);
        return;
    }
    if (len > 0 && text[len - 1] != '\n')
        problem(t, path, "the last line has no newline (torn)");
    int line_no = 0;
    for (char *line = text; line < text + len;) {
        char *nl = memchr(line, '\n', (size_t)(text + len - line));
        size_t n = nl ? (size_t)(nl - line) : (size_t)(text + len - line);
        line_no++;
        cJSON *o = cJSON_ParseWithLength(line, n);
        if (!cJSON_IsObject(o)) {
            char what[64];
            snprintf(what, sizeof what, "line %d is not one JSON object", line_no);
            problem(t, path, what);
        } else if (t->verdict_files) {
            check_named_files(t, path, line_no, o);
        }
        cJSON_Delete(o);
        line = line + n + 1;
    }
    t->lines += line_no;
    free(text);
}

static void check_uwbscan(struct tally *t, const char *path)
{
    struct uwb_scan scan = {0};
    char err[1024];
    if (uwbscan_read_file(path, &scan, err, sizeof err) != 0)
        problem(t, path, err);
    uwb_scan_free(&scan);
    t->uwbscan++;
}

static void check_png(struct tally *t, const char *path)
{
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    t->png++;
    char *bytes, err[1024];
    size_t len;
    /* An unreadable file fails as "does not end in IEND" below (bytes NULL). */
    uwb_read_file(path, MAX_FILE_BYTES, &bytes, &len, err, sizeof err);
    int ends_whole = bytes && len >= sizeof iend && memcmp(bytes + len - sizeof iend, iend, sizeof iend) == 0;
    free(bytes);
    if (!ends_whole) {
        problem(t, path, "does not end in a PNG IEND chunk (cut short?)");
        return;
    }
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path)) {
        problem(t, path, image.message);
        return;
    }
    image.format = PNG_FORMAT_RGB;
    png_bytep pixels = malloc(PNG_IMAGE_SIZE(image));
    if (!pixels) {
        png_image_free(&image);
        problem(t, path, "out of memory");
        return;
    }
    if (!png_image_finish_read(&image, NULL, pixels, 0, NULL))
        problem(t, path, image.message);
    free(pixels);
    png_image_free(&image);
}

/* baseline/current.json must describe current.uwbscan once the daemon has
 * started on the directory (it rebuilds a description a crash left behind). */
static void check_baseline(struct tally *t, const char *root)
{
    char scan_path[4200], info_path[4200];
    snprintf(scan_path, sizeof scan_path, "%s/baseline/current.uwbscan", root);
    snprintf(info_path, sizeof info_path, "%s/baseline/current.json", root);
    struct uwb_scan scan = {0};
    char err[1024];
    if (!is_regular_file(scan_path) || uwbscan_read_file(scan_path, &scan, err, sizeof err) != 0)
        return; /* no baseline, or already reported */
    char id[UWBD_SCAN_ID_MAX + 1];
    uwbd_safe_scan_id(scan.scan_id ? scan.scan_id : "", id, sizeof id);
    uwb_scan_free(&scan);
    char *text;
    size_t len;
    /* Unreadable is reported below as not naming the scan (text NULL). */
    uwb_read_file(info_path, MAX_FILE_BYTES, &text, &len, err, sizeof err);
    cJSON *info = text ? cJSON_ParseWithLength(text, len) : NULL;
    const cJSON *named = cJSON_GetObjectItemCaseSensitive(info, "scan_id");
    if (!cJSON_IsString(named) || strcmp(named->valuestring, id) != 0) {
        char what[300];
        snprintf(what, sizeof what, "does not name the baseline scan %s", id);
        problem(t, info_path, what);
    }
    cJSON_Delete(info);
    free(text);
}

static void walk(struct tally *t, const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) {
        problem(t, dir, strerror(errno));
        return;
    }
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        char path[4200];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(path, &st) != 0) {
            problem(t, path, strerror(errno));
            continue;
        }
        if (S_ISDIR(st.st_mode)) {
            walk(t, path);
            continue;
        }
        if (e->d_name[0] == '.')
            problem(t, path, "temporary file left behind");
        else if (strcmp(e->d_name, "verdicts.jsonl") == 0)
            check_verdict_log(t, path);
        else if (ends_with(e->d_name, ".json"))
            check_json(t, path);
        else if (ends_with(e->d_name, ".uwbscan"))
            check_uwbscan(t, path);
        else if (ends_with(e->d_name, ".png"))
            check_png(t, path);
        else
            t->other++; /* uwbd.lock, a test's filler file */
    }
    closedir(d);
}

static int tree(int argc, char **argv)
{
    struct tally t = {0};
    t.verdict_files = argc > 1 && strcmp(argv[1], "--verdict-files") == 0;
    walk(&t, argv[0]);
    check_baseline(&t, argv[0]);
    printf("%s: %d json, %d verdict lines, %d uwbscan, %d png, %d other; %d problem%s\n", argv[0], t.json,
           t.lines, t.uwbscan, t.png, t.other, t.problems, t.problems == 1 ? "" : "s");
    return t.problems ? 1 : 0;
}

static const cJSON *lookup(const cJSON *o, const char *path)
{
    char key[256];
    while (o && *path) {
        size_t n = strcspn(path, ".");
        snprintf(key, sizeof key, "%.*s", (int)n, path);
        path += n + (path[n] == '.');
        if (cJSON_IsArray(o)) {
            char *end;
            long i = strtol(key, &end, 10);
            o = *end == '\0' ? cJSON_GetArrayItem(o, (int)i) : NULL;
        } else {
            o = cJSON_GetObjectItemCaseSensitive(o, key);
        }
    }
    return o;
}

static int get(int argc, char **argv)
{
    char *text, err[1024];
    size_t len;
    if (uwb_read_fd(STDIN_FILENO, "stdin", MAX_FILE_BYTES, &text, &len, err, sizeof err) != UWB_READ_OK) {
        fprintf(stderr, "state_check get: %s\n", err);
        return 2;
    }
    cJSON *o = cJSON_ParseWithLength(text, len);
    free(text);
    if (!cJSON_IsObject(o)) {
        cJSON_Delete(o);
        fprintf(stderr, "state_check get: stdin is not a JSON object\n");
        return 2;
    }
    for (int i = 0; i < argc; i++) {
        const cJSON *v = lookup(o, argv[i]);
        if (!v) {
            puts("(missing)");
        } else if (cJSON_IsString(v)) {
            puts(v->valuestring);
        } else {
            char *s = cJSON_PrintUnformatted(v);
            puts(s ? s : "(out of memory)");
            free(s);
        }
    }
    cJSON_Delete(o);
    return 0;
}

/* One of the daemon's writes: a temporary created, or the verdict log appended to. */
static int is_write(const struct inotify_event *ev)
{
    if (ev->len == 0)
        return 0;
    if (ev->mask & IN_CREATE)
        return ev->name[0] == '.';
    return (ev->mask & IN_MODIFY) && strcmp(ev->name, "verdicts.jsonl") == 0;
}

static int kill_on_write(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "state_check kill-on-write: PID SKIP DELAY_US TIMEOUT_S DIR...\n");
        return 64;
    }
    pid_t pid = (pid_t)atol(argv[0]);
    long skip = atol(argv[1]), delay_us = atol(argv[2]);
    double deadline = uwb_monotonic_s() + atof(argv[3]);
    int fd = inotify_init1(IN_CLOEXEC | IN_NONBLOCK);
    if (fd < 0 || pid <= 0) {
        fprintf(stderr, "state_check kill-on-write: %s\n", pid <= 0 ? "bad PID" : strerror(errno));
        return 64;
    }
    int watches[64];
    int n_watches = argc - 4 < 64 ? argc - 4 : 64;
    for (int i = 0; i < n_watches; i++) {
        watches[i] = inotify_add_watch(fd, argv[4 + i], IN_CREATE | IN_MODIFY);
        if (watches[i] < 0)
            fprintf(stderr, "state_check kill-on-write: %s: %s (not watched)\n", argv[4 + i],
                    strerror(errno));
    }
    char buf[8192] __attribute__((aligned(__alignof__(struct inotify_event))));
    while (uwb_monotonic_s() < deadline && kill(pid, 0) == 0) {
        struct pollfd p = {.fd = fd, .events = POLLIN};
        if (poll(&p, 1, 50) <= 0)
            continue;
        ssize_t n = read(fd, buf, sizeof buf);
        for (char *at = buf; n > 0 && at < buf + n;) {
            const struct inotify_event *ev = (const struct inotify_event *)at;
            at += sizeof *ev + ev->len;
            if (!is_write(ev) || skip-- > 0)
                continue;
            struct timespec pause = {.tv_sec = delay_us / 1000000, .tv_nsec = delay_us % 1000000 * 1000};
            while (nanosleep(&pause, &pause) != 0 && errno == EINTR) {
            }
            int rc = kill(pid, SIGKILL);
            const char *dir = "?";
            for (int i = 0; i < n_watches; i++)
                if (watches[i] == ev->wd)
                    dir = argv[4 + i];
            printf("%s/%s\n", dir, ev->name);
            close(fd);
            return rc == 0 ? 0 : 1;
        }
    }
    close(fd);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "tree") == 0)
        return tree(argc - 2, argv + 2);
    if (argc >= 3 && strcmp(argv[1], "get") == 0)
        return get(argc - 2, argv + 2);
    if (argc >= 2 && strcmp(argv[1], "kill-on-write") == 0)
        return kill_on_write(argc - 2, argv + 2);
    fprintf(stderr, "usage: state_check tree STATE_DIR [--verdict-files]\n"
                    "       state_check get KEY... < JSON\n"
                    "       state_check kill-on-write PID SKIP DELAY_US TIMEOUT_S DIR...\n");
    return 64;
}
