/* The CSV output module: each verdict a row of csv.path (the columns of
 * `uwbd ctl --csv history`, src/output/verdict_csv.c), the file rotated
 * with the archive: it keeps the newest retention.max_scans rows. The file
 * is replaced atomically each time, so a reader never sees half a row. */
#include "daemon/output_csv.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "util/log.h"
#include "uwb/atomic_file.h"
#include "uwb/read_file.h"
#include "uwb/verdict_csv.h"

/* A file past this is not ours to rewrite (1000 rows take about 300 kB). */
#define CSV_FILE_MAX ((size_t)64 * 1024 * 1024)
#define CSV_ROW_MAX 8192

static int csv_failing; /* log a failing CSV file once, not every verdict */

/* The whole rows of the old file: each ends in CRLF outside quotes (a
 * quoted reason may hold line breaks); text past the last one (a row torn
 * by someone else's write) is not kept. */
struct csv_rows {
    size_t *start; /* where each row starts, the header first */
    size_t count, cap;
    size_t end; /* where the last whole row ends */
};

static int add_row_start(struct csv_rows *rows, size_t start)
{
    if (rows->count == rows->cap) {
        size_t cap = rows->cap ? rows->cap * 2 : 64;
        size_t *grown = realloc(rows->start, cap * sizeof *grown);
        if (!grown)
            return -1;
        rows->start = grown;
        rows->cap = cap;
    }
    rows->start[rows->count++] = start;
    return 0;
}

/* One pass over the text: 0, or -1 when out of memory. */
static int find_rows(const char *text, size_t len, struct csv_rows *rows)
{
    int quoted = 0;
    size_t start = 0;
    for (size_t i = 0; i < len; i++) {
        if (text[i] == '"') {
            quoted = !quoted;
        } else if (!quoted && text[i] == '\r' && i + 1 < len && text[i + 1] == '\n') {
            if (add_row_start(rows, start) != 0)
                return -1;
            start = i + 2;
            i++;
        }
    }
    rows->end = start;
    return 0;
}

int uwbd_csv_file_add(const char *path, const char *row, int max_rows, char *err, size_t errlen)
{
    char *old = NULL;
    size_t len = 0;
    struct csv_rows rows = {0};
    int rc = -1;
    struct stat st;
    if ((lstat(path, &st) == 0 || errno != ENOENT) &&
        uwb_read_file_nofollow(path, CSV_FILE_MAX, &old, &len, err, errlen) != UWB_READ_OK)
        goto done;
    if (old && find_rows(old, len, &rows) != 0) {
        snprintf(err, errlen, "%s: out of memory", path);
        goto done;
    }
    /* The old rows after its header (written afresh), the oldest dropped beyond max_rows. */
    size_t first = 1;
    if (max_rows > 0 && rows.count > first && rows.count - first > (size_t)max_rows - 1)
        first = rows.count - ((size_t)max_rows - 1);
    struct atomic_file af;
    rc = uwb_atomic_file_open(&af, path, err, errlen);
    if (rc == 0) {
        fputs(uwb_verdict_csv_header(), af.fp);
        if (first < rows.count)
            fwrite(old + rows.start[first], 1, rows.end - rows.start[first], af.fp);
        fputs(row, af.fp);
        rc = uwb_atomic_file_commit(&af, err, errlen);
    }
done:
    free(rows.start);
    free(old);
    return rc;
}

static void csv_verdict(const struct uwbd_daemon_port *port, const struct uwb_verdict_record *v,
                        const char *json, double duration_s)
{
    (void)duration_s;
    if (!port->cfg->csv.enabled || !json || !v)
        return;
    char path[UWBD_PATH_MAX + 32], row[CSV_ROW_MAX], err[UWBD_PATH_MAX + 512];
    if (port->cfg->csv.path[0])
        snprintf(path, sizeof path, "%s", port->cfg->csv.path);
    else if (uwbd_path_join(path, sizeof path, port->cfg->state_dir, "verdicts.csv") != 0)
        return;
    int rc = -1;
    if (uwb_verdict_csv_row(v, row, sizeof row) < 0)
        snprintf(err, sizeof err, "%s: the verdict's row is longer than %d bytes", path, CSV_ROW_MAX);
    else
        rc = uwbd_csv_file_add(path, row, port->cfg->retention_max_scans, err, sizeof err);
    if (rc != 0) {
        if (!csv_failing)
            uwbd_log(UWBD_LOG_ERR, "csv: %s (tried again at every verdict)", err);
        csv_failing = 1;
        return;
    }
    if (csv_failing)
        uwbd_log(UWBD_LOG_NOTICE, "csv: %s written again", path);
    csv_failing = 0;
}

const struct uwbd_output_module uwbd_output_csv = {
    .name = "csv",
    .verdict = csv_verdict,
};
