/* The published verdict's fields, one row per figure (gpsd's json_attr_t,
 * rtl_433's data_t): its JSON key and group, where its value and its
 * "given" flag live in the record, its unit and rounding, its CSV column,
 * its Prometheus gauge, whether the status summary, the history and the
 * trend carry it, and the key that says why when it is withheld. The
 * record's rounding, the JSON writer and reader (verdict_json.c), the CSV
 * row, the Prometheus textfile and the trend walk this table; a new figure
 * is a row here and a field in the record's summary (uwb/verdict_record.h),
 * nothing more. Offsets are into the record, and every row lies in its
 * summary part, so a walk takes a struct uwb_verdict_summary as well.
 * Modbus, the text pages and the PNG panels are designed by hand and read
 * the record. */
#ifndef UWB_VERDICT_FIELDS_H
#define UWB_VERDICT_FIELDS_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "uwb/verdict_record.h"

enum uwb_field_kind {
    UWB_FIELD_NUMBER, /* a double, written when its flag is set */
    UWB_FIELD_TEXT,   /* a char array, written when not empty */
    UWB_FIELD_STATUS  /* an enum uwb_status, written by name */
};

/* The JSON object a row is in: the verdict itself or one nested in it. */
struct uwb_field_group {
    const char *key; /* NULL: the verdict object itself */
    size_t given;    /* offsetof the record's int flag: the object is there (0: always) */
    int history;     /* its place in a history entry (1, 2, ...), 0: not there */
};

struct uwb_field {
    const char *key;
    const struct uwb_field_group *group;
    enum uwb_field_kind kind;
    size_t value;        /* offsetof the value in the record */
    size_t size;         /* a text's buffer */
    size_t given;        /* offsetof its int flag; 0 (the status): always given */
    int decides;         /* read: the key's presence sets the flag (all deciding rows present) */
    size_t from;         /* offsetof the figure in struct uwb_verdict (SI units); 0: none */
    const char *unit;    /* "mm", "dB", "ps" */
    double steps_per_si; /* rounding: the published value is round(si * steps_per_si) / steps_per_unit */
    double steps_per_unit;
    const char *withheld_key; /* written in the figure's place when it is not given */
    size_t withheld;          /* ...from this text */
    size_t withheld_size;
    int csv_column;       /* 1, 2, ...; 0: not a CSV column */
    int summary, history; /* place in the status summary and in a history entry (1, 2, ...); 0: not there */
    /* A Prometheus gauge in base units (the published value over
     * steps_per_si / steps_per_unit); a status row gives one sample per
     * status. Rows sharing a name are one metric, told apart by label. */
    const char *prom_name; /* NULL: none */
    const char *prom_help;
    const char *prom_label; /* e.g. edge="lower", or NULL */
    int prom;               /* its place in the textfile (1, 2, ...) */
    const char *trend_key;  /* its key in a TREND entry (NULL: not there) */
    int trend;              /* ...and its place there (1, 2, ...) */
};

struct uwb_field_table {
    const struct uwb_field *rows;
    size_t count;
};

/* The published verdict's table. */
extern const struct uwb_field_table uwb_verdict_fields;

/* Where a row's value and flag are in a record. */
double *uwb_field_number(const struct uwb_field *f, void *record);
int uwb_field_given(const struct uwb_field *f, const void *record);

/* The figures of v (struct uwb_verdict, SI units) into the record, rounded
 * as published, for every row that has a `from` and whose flag the record
 * already set: the one place metres become millimetres. */
void uwb_fields_publish(const struct uwb_field_table *t, void *record, const void *verdict);
/* One figure's published value from its SI value, and back (base units). */
double uwb_field_round(const struct uwb_field *f, double si);
double uwb_field_si(const struct uwb_field *f, double published);
/* The row for a key in its group (group NULL: top), or NULL. */
const struct uwb_field *uwb_field_find(const struct uwb_field_table *t, const char *group, const char *key);

/* The table's keys into o, in order (groups as nested objects). */
void uwb_fields_write(const struct uwb_field_table *t, const void *record, cJSON *o);
/* The table's keys from o into the record; the first problem in err as
 * "verdict: key `KEY`: PROBLEM". 0, or -1. */
int uwb_fields_read(const struct uwb_field_table *t, const cJSON *o, void *record, char *err, size_t errlen);

/* A TREND entry: the rows with a trend place, flat (radial_status), in
 * their order; and reading one back (a nested row's group is there when
 * one of its keys is). */
void uwb_fields_write_trend(const struct uwb_field_table *t, const void *record, cJSON *o);
int uwb_fields_read_trend(const struct uwb_field_table *t, const cJSON *o, void *record, char *err,
                          size_t errlen);

/* A row's name outside JSON (a CSV column, a TREND key): "radial_max_change_mm",
 * its group's key and its own; -1 when it does not fit in n. */
int uwb_field_flat_name(const struct uwb_field *f, char *buf, size_t n);

/* The keys a summary (which: 's'), a history entry ('h') or a TREND
 * entry ('t') has, in their order: up to max into keys. Rows, groups and
 * the extra keys (from the cycle) a caller names with their places. */
#define UWB_FIELD_PLACES 64 /* the last place a key can have */
struct uwb_field_extra {
    const char *key;
    int summary, history;
};
size_t uwb_fields_keys(const struct uwb_field_table *t, const struct uwb_field_extra *extra, size_t n_extra,
                       char which, const char **keys, size_t max);

#endif
