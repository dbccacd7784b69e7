/* The CSV output module: each verdict a row of csv.path (the columns of
 * `uwbd ctl --csv history`, src/output/verdict_csv.c), the file rotated
 * with the archive: it keeps the newest retention.max_scans rows. The file
 * is replaced atomically each time, so a reader never sees half a row. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"
#include "uwb/atomic_file.h"
#include "uwb/read_file.h"
#include "uwb/verdict_csv.h"

/* A file past this is not ours to rewrite (1000 rows take about 300 kB). */
#define CSV_FILE_MAX ((size_t)64 * 1024 * 1024)
#define CSV_ROW_MAX 8192

/* Where each row ends: CRLF outside quotes (a quoted reason may hold
 * line breaks). Returns the number of whole rows, their starts in starts
 * (may be NULL) and in *end where the last one ends (text past it, a row
 * torn by someone else's write, is not kept). */
static size_t row_starts(const char *text, size_t len, size_t *starts, size_t *end)
{
    size_t rows = 0;
    int quoted = 0;
    size_t start = 0;
    for (size_t i = 0; i < len; i++) {
        if (text[i] == '"')
            quoted = !quoted;
        else if (!quoted && text[i] == '\r' && i + 1 < len && text[i + 1] == '\n') {
            if (starts)
                starts[rows] = start;
            rows++;
            start = i + 2;
            i++;
        }
    }
    *end = start;
    return rows;
}

int uwbd_csv_file_add(const char *path, const char *row, int max_rows, char *err, size_t errlen)
{
    char *old = NULL;
    size_t len = 0;
    struct stat st;
    if (lstat(path, &st) == 0 || errno != ENOENT) {
        if (uwb_read_file_nofollow(path, CSV_FILE_MAX, &old, &len, err, errlen) != UWB_READ_OK)
            return -1;
    }
    /* The old rows after its header, the oldest dropped beyond max_rows. */
    size_t end = 0;
    size_t rows = old ? row_starts(old, len, NULL, &end) : 0;
    size_t *starts = rows ? malloc(rows * sizeof *starts) : NULL;
    if (rows && !starts) {
        free(old);
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    if (rows)
        row_starts(old, len, starts, &end);
    size_t first = 1; /* row 0 is the header, written afresh */
    if (max_rows > 0 && rows > first && rows - first > (size_t)max_rows - 1)
        first = rows - ((size_t)max_rows - 1);
    struct atomic_file af;
    int rc = uwb_atomic_file_open(&af, path, err, errlen);
    if (rc == 0) {
        fputs(uwb_verdict_csv_header(), af.fp);
        if (first < rows)
            fwrite(old + starts[first], 1, end - starts[first], af.fp);
        fputs(row, af.fp);
        rc = uwb_atomic_file_commit(&af, err, errlen);
    }
    free(starts);
    free(old);
    return rc;
}

static int failing; /* log a failing file once, not every verdict (one daemon per process) */

static void csv_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                        double duration_s)
{
    (void)duration_s;
    if (!d->cfg.csv.enabled || !json || !v)
        return;
    char path[UWBD_PATH_MAX + 32], row[CSV_ROW_MAX], err[UWBD_PATH_MAX + 512];
    if (d->cfg.csv.path[0])
        snprintf(path, sizeof path, "%s", d->cfg.csv.path);
    else if (uwbd_path_join(path, sizeof path, d->cfg.state_dir, "verdicts.csv") != 0)
        return;
    int rc = -1;
    if (uwb_verdict_csv_row(v, row, sizeof row) < 0)
        snprintf(err, sizeof err, "%s: the verdict's row is longer than %d bytes", path, CSV_ROW_MAX);
    else
        rc = uwbd_csv_file_add(path, row, d->cfg.retention_max_scans, err, sizeof err);
    if (rc != 0) {
        if (!failing)
            uwbd_log(UWBD_LOG_ERR, "csv: %s (tried again at every verdict)", err);
        failing = 1;
        return;
    }
    if (failing)
        uwbd_log(UWBD_LOG_NOTICE, "csv: %s written again", path);
    failing = 0;
}

const struct uwbd_output_module uwbd_output_csv = {
    .name = "csv",
    .verdict = csv_verdict,
};
