/* The CSV file as an output module (output_csv.c). */
#ifndef UWBD_DAEMON_OUTPUT_CSV_H
#define UWBD_DAEMON_OUTPUT_CSV_H

#include <stddef.h>

#include "daemon/output_module.h"

extern const struct uwbd_output_module uwbd_output_csv;

/* The CSV module's file: row (CRLF-terminated) appended after the header
 * and the newest old rows, max_rows in all (0: no limit), the file replaced
 * atomically. 0, or -1 with err naming the file. */
int uwbd_csv_file_add(const char *path, const char *row, int max_rows, char *err, size_t errlen);

#endif
