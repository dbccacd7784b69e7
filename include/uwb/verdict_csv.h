/* The published verdict as one CSV row for spreadsheets (RFC 4180): comma
 * separated, CRLF line ends as the RFC says (spreadsheets and Python's csv
 * read them, and a reason holding a bare LF inside quotes stays told apart
 * from the end of a row). A field holding a comma, a quote, CR or LF is
 * quoted, its quotes doubled. Figures are printed as the JSON prints them
 * (the record holds the published values); a figure the record does not
 * hold is an empty cell, never 0, and the reason column says why when the
 * record knows. */
#ifndef UWB_VERDICT_CSV_H
#define UWB_VERDICT_CSV_H

#include <stddef.h>

#include "uwb/verdict_fields.h"
#include "uwb/verdict_record.h"

/* The header row, CRLF included: each column's name with its unit, from the
 * field table (uwb/verdict_fields.h). */
const char *uwb_verdict_csv_header(void);

/* The record's row, CRLF included, in buf (NUL-terminated): its length, or
 * -1 when it does not fit in len bytes (buf then holds an empty string,
 * never part of a row). */
int uwb_verdict_csv_row(const struct uwb_verdict_record *r, char *buf, size_t len);

/* The same from any field table whose rows lie in a record that begins
 * with struct uwb_verdict_record (a test's table with a row added): the
 * table's CSV columns, with the cycle's and the reason at their places. */
int uwb_fields_csv_header(const struct uwb_field_table *t, char *buf, size_t len);
int uwb_fields_csv_row(const struct uwb_field_table *t, const struct uwb_verdict_record *r, char *buf,
                       size_t len);

#endif
