/* Whole-or-nothing file replacement: a hidden temporary in the target's own
 * directory (rename is only atomic within one filesystem), fsync'd before the
 * rename and the directory fsync'd after it, so a power cut leaves either the
 * old file or the new one. */
#include "uwb/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Mode for a file that did not exist before (what umask 022 would give). */
#define NEW_FILE_MODE 0644

static void set_error(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void set_error(char *err, size_t errlen, const char *fmt, ...)
{
    if (err == NULL || errlen == 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* The directory part of path ("." when there is none), for the fsync. */
static void directory_of(const char *path, char *dir, size_t dirlen)
{
    const char *slash = strrchr(path, '/');
    if (slash == NULL) {
        snprintf(dir, dirlen, ".");
    } else if (slash == path) {
        snprintf(dir, dirlen, "/");
    } else {
        snprintf(dir, dirlen, "%.*s", (int)(slash - path), path);
    }
}

static void discard_temp(struct atomic_file *af)
{
    if (af->fp != NULL) {
        fclose(af->fp);
        af->fp = NULL;
    }
    if (af->temp_path[0] != '\0') {
        unlink(af->temp_path);
        af->temp_path[0] = '\0';
    }
}

int uwb_atomic_file_open(struct atomic_file *af, const char *path, char *err, size_t errlen)
{
    memset(af, 0, sizeof *af);
    if (path == NULL || path[0] == '\0') {
        set_error(err, errlen, "(empty path): cannot write a file without a name");
        return -1;
    }
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (base[0] == '\0' || strcmp(base, ".") == 0 || strcmp(base, "..") == 0) {
        set_error(err, errlen, "%s: path names a directory, not a file", path);
        return -1;
    }
    int dir_len = slash ? (int)(slash - path + 1) : 0;
    int n = snprintf(af->temp_path, sizeof af->temp_path,
                     "%.*s" ATOMIC_FILE_TEMP_PREFIX "%s.XXXXXX" ATOMIC_FILE_TEMP_SUFFIX, dir_len, path, base);
    if (strlen(path) >= sizeof af->final_path || n < 0 || (size_t)n >= sizeof af->temp_path) {
        af->temp_path[0] = '\0';
        /* Quote only the start: the whole path would crowd out the reason. */
        set_error(err, errlen, "%.64s...: path is too long (%zu bytes)", path, strlen(path));
        return -1;
    }
    snprintf(af->final_path, sizeof af->final_path, "%s", path);

    int fd = mkstemps(af->temp_path, (int)strlen(ATOMIC_FILE_TEMP_SUFFIX));
    if (fd < 0) {
        int e = errno;
        af->temp_path[0] = '\0';
        set_error(err, errlen, "%s: cannot create temporary file: %s", path, strerror(e));
        return -1;
    }
    /* mkstemp gives 0600; keep a replaced file's mode, else a readable default. */
    struct stat st;
    mode_t mode = stat(path, &st) == 0 && S_ISREG(st.st_mode) ? st.st_mode & 07777 : NEW_FILE_MODE;
    if (fchmod(fd, mode) != 0) {
        int e = errno;
        close(fd);
        discard_temp(af);
        set_error(err, errlen, "%s: cannot set mode of %s: %s", path, af->temp_path, strerror(e));
        return -1;
    }
    af->fp = fdopen(fd, "wb");
    if (af->fp == NULL) {
        int e = errno;
        close(fd);
        discard_temp(af);
        set_error(err, errlen, "%s: cannot open temporary file: %s", path, strerror(e));
        return -1;
    }
    return 0;
}

int uwb_atomic_file_commit(struct atomic_file *af, char *err, size_t errlen)
{
    if (af->fp == NULL || af->temp_path[0] == '\0') {
        set_error(err, errlen, "%s: nothing to commit (not open)",
                  af->final_path[0] ? af->final_path : "(atomic file)");
        discard_temp(af);
        return -1;
    }
    const char *path = af->final_path;
    const char *step = NULL;
    int e = 0;
    if (fflush(af->fp) != 0 || ferror(af->fp)) {
        step = "cannot write";
    } else if (fsync(fileno(af->fp)) != 0) {
        step = "cannot fsync";
    }
    if (step != NULL) {
        e = errno;
        discard_temp(af);
        set_error(err, errlen, "%s: %s temporary file: %s", path, step, strerror(e));
        return -1;
    }
    int close_rc = fclose(af->fp);
    af->fp = NULL;
    if (close_rc != 0) {
        e = errno;
        discard_temp(af);
        set_error(err, errlen, "%s: cannot close temporary file: %s", path, strerror(e));
        return -1;
    }
    if (rename(af->temp_path, path) != 0) {
        e = errno;
        discard_temp(af);
        set_error(err, errlen, "%s: cannot replace with new file: %s", path, strerror(e));
        return -1;
    }
    af->temp_path[0] = '\0';

    /* Without this the rename itself may not survive a power cut. */
    char dir[sizeof af->final_path];
    directory_of(path, dir, sizeof dir);
    int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd < 0) {
        e = errno;
        set_error(err, errlen, "%s: written, but cannot open directory %s to fsync it: %s", path, dir,
                  strerror(e));
        return -1;
    }
    /* Some filesystems cannot fsync a directory (EINVAL); nothing more to do there. */
    if (fsync(dfd) != 0 && errno != EINVAL) {
        e = errno;
        close(dfd);
        set_error(err, errlen, "%s: written, but cannot fsync directory %s: %s", path, dir, strerror(e));
        return -1;
    }
    close(dfd);
    return 0;
}

void uwb_atomic_file_abort(struct atomic_file *af)
{
    discard_temp(af);
}

int uwb_atomic_write_file(const char *path, const void *data, size_t len, char *err, size_t errlen)
{
    struct atomic_file af;
    if (uwb_atomic_file_open(&af, path, err, errlen) != 0)
        return -1;
    if (len > 0 && fwrite(data, 1, len, af.fp) != len) {
        int e = errno;
        uwb_atomic_file_abort(&af);
        set_error(err, errlen, "%s: cannot write temporary file: %s", path, strerror(e));
        return -1;
    }
    return uwb_atomic_file_commit(&af, err, errlen);
}

int uwb_atomic_file_is_temporary_name(const char *name)
{
    size_t n = strlen(name), pre = strlen(ATOMIC_FILE_TEMP_PREFIX), suf = strlen(ATOMIC_FILE_TEMP_SUFFIX);
    /* prefix, at least one byte of name, '.', six random characters, suffix */
    if (n < pre + 1 + 1 + 6 + suf || strncmp(name, ATOMIC_FILE_TEMP_PREFIX, pre) != 0 ||
        strcmp(name + n - suf, ATOMIC_FILE_TEMP_SUFFIX) != 0)
        return 0;
    const char *random = name + n - suf - 6;
    if (random[-1] != '.')
        return 0;
    for (int i = 0; i < 6; i++) {
        char c = random[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9')))
            return 0;
    }
    return 1;
}
