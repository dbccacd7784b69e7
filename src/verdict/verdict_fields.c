/* The published verdict's field table and the walks over it (see the header). */
#include "uwb/verdict_fields.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "uwb/verdict.h"
#include "verdict/json_key_reader.h"

#define R(member) offsetof(struct uwb_verdict_record, member)
#define V(member) offsetof(struct uwb_verdict, member)
#define TEXT(member) .value = R(member), .size = sizeof(((struct uwb_verdict_record *)0)->member)
#define WITHHELD(key_, member) \
    .withheld_key = (key_), .withheld = R(member), \
    .withheld_size = sizeof(((struct uwb_verdict_record *)0)->member)
/* Millimetres to 0.01 mm (from metres), dB to 0.1 dB, picoseconds to 0.1 ps
 * (from seconds): finer digits would claim precision nobody has. */
#define MM .unit = "mm", .steps_per_si = 1e5, .steps_per_unit = 100.0
#define DB .unit = "dB", .steps_per_si = 10.0, .steps_per_unit = 10.0
#define PS .unit = "ps", .steps_per_si = 1e13, .steps_per_unit = 10.0
#define NUMBER .kind = UWB_FIELD_NUMBER

static const struct uwb_field_group top = {NULL, 0, 0};
static const struct uwb_field_group radial = {"radial", R(has_radial), 21};
static const struct uwb_field_group baseline = {"baseline", R(has_baseline), 17};

/* In the JSON's order. */
static const struct uwb_field rows[] = {
    {"status", &top, .kind = UWB_FIELD_STATUS, .value = R(status), .csv_column = 3, .summary = 3,
     .history = 3, .trend_key = "status", .trend = 3},
    {"reason", &top, .kind = UWB_FIELD_TEXT, TEXT(reason), .summary = 4, .history = 4, .trend_key = "reason",
     .trend = 10},
    {"fault", &top, .kind = UWB_FIELD_TEXT, TEXT(fault), .csv_column = 16, .history = 18},
    {"scan_id", &top, .kind = UWB_FIELD_TEXT, TEXT(scan_id), .csv_column = 2, .summary = 1, .history = 1,
     .trend_key = "scan_id", .trend = 2},
    {"created", &top, .kind = UWB_FIELD_TEXT, TEXT(created), .csv_column = 1, .summary = 2, .history = 2,
     .trend_key = "created", .trend = 1},
    {"axial_displacement_mm", &top, NUMBER, .value = R(axial_displacement_mm), .given = R(has_displacement),
     .decides = 1, .from = V(axial_displacement_m), MM, .csv_column = 4, .summary = 5, .history = 5,
     .trend_key = "axial_displacement_mm", .trend = 4, .prom = 1,
     .prom_name = "uwbd_axial_displacement_meters",
     .prom_help = "The latest axial displacement of the winding from the baseline, positive up."},
    {"uncertainty_mm", &top, NUMBER, .value = R(uncertainty_mm), .given = R(has_displacement),
     .from = V(uncertainty_m), MM, .csv_column = 5, .summary = 6, .history = 6, .trend_key = "uncertainty_mm",
     .trend = 5, .prom = 2, .prom_name = "uwbd_axial_displacement_uncertainty_meters",
     .prom_help = "Its 1-sigma uncertainty."},
    {"lower_edge_mm", &top, NUMBER, .value = R(lower_edge_mm), .given = R(has_edges), .decides = 1,
     .from = V(current.lower_m), MM, .csv_column = 8, .history = 12, .prom = 3,
     .prom_name = "uwbd_edge_meters", .prom_label = "edge=\"lower\"",
     .prom_help = "The winding's lower and upper edges in the latest scan."},
    {"upper_edge_mm", &top, NUMBER, .value = R(upper_edge_mm), .given = R(has_edges), .decides = 1,
     .from = V(current.upper_m), MM, .csv_column = 9, .history = 13, .prom = 4,
     .prom_name = "uwbd_edge_meters", .prom_label = "edge=\"upper\"",
     .prom_help = "The winding's lower and upper edges in the latest scan."},
    {"center_mm", &top, NUMBER, .value = R(center_mm), .given = R(has_edges), .from = V(current.center_m), MM,
     .csv_column = 10, .summary = 7, .history = 7},
    {"height_mm", &top, NUMBER, .value = R(height_mm), .given = R(has_edges), .from = V(current.height_m), MM,
     .csv_column = 11, .history = 14},
    {"height_change_mm", &top, NUMBER, .value = R(height_change_mm), .given = R(has_height_change),
     .decides = 1, .from = V(height_change_m), MM, WITHHELD("height_change_withheld", height_change_withheld),
     .csv_column = 6, .summary = 8, .history = 8, .trend_key = "height_change_mm", .trend = 6, .prom = 5,
     .prom_name = "uwbd_height_change_meters",
     .prom_help = "The winding's height change from the baseline (latest scan)."},
    {"height_change_uncertainty_mm", &top, NUMBER, .value = R(height_change_uncertainty_mm),
     .given = R(has_height_change), .from = V(height_change_uncertainty_m), MM, .csv_column = 7,
     .history = 10},
    {"face_range_mm", &top, NUMBER, .value = R(face_range_mm), .given = R(has_edges),
     .from = V(current.face_z_m), MM, .csv_column = 12, .history = 15},
    {"snr_db", &top, NUMBER, .value = R(snr_db), .given = R(has_edges), .from = V(current.snr_db), DB,
     .csv_column = 13, .history = 16},
    /* the larger of the two edges' sigmas: uwb_record_from_verdict */
    {"edge_uncertainty_mm", &top, NUMBER, .value = R(edge_uncertainty_mm), .given = R(has_edges), MM},
    {"side_reflector_mm", &top, NUMBER, .value = R(side_reflector_mm), .given = R(has_side_reflector),
     .decides = 1, .from = V(current.side_reflector_y_m), MM},
    /* the face found, its edges not published: why (uwb_record_from_verdict) */
    {"edges_withheld", &top, .kind = UWB_FIELD_TEXT, TEXT(edges_withheld)},
    {"status", &radial, .kind = UWB_FIELD_STATUS, .value = R(radial_status), .csv_column = 20,
     .trend_key = "radial_status", .trend = 7, .prom = 6, .prom_name = "uwbd_radial_status",
     .prom_help = "The latest verdict's radial status: 1 for the one it has, 0 for the others."},
    {"max_change_mm", &radial, NUMBER, .value = R(radial_max_change_mm), .given = R(radial_measured),
     .decides = 1, .from = V(radial.max_change_m), MM, .csv_column = 21, .trend_key = "radial_max_change_mm",
     .trend = 8, .prom = 7, .prom_name = "uwbd_radial_max_change_meters",
     .prom_help = "The latest largest radial change of the winding's face from the baseline, positive toward "
                  "the antenna."},
    {"at_mm", &radial, NUMBER, .value = R(radial_at_mm), .given = R(radial_measured), .from = V(radial.at_m),
     MM, .csv_column = 22, .prom = 9, .prom_name = "uwbd_radial_max_change_height_meters",
     .prom_help = "The height where it is largest."},
    {"from_mm", &radial, NUMBER, .value = R(radial_from_mm), .given = R(radial_has_span), .decides = 1,
     .from = V(radial.from_m), MM, .csv_column = 23},
    {"to_mm", &radial, NUMBER, .value = R(radial_to_mm), .given = R(radial_has_span), .decides = 1,
     .from = V(radial.to_m), MM, .csv_column = 24},
    {"uncertainty_mm", &radial, NUMBER, .value = R(radial_uncertainty_mm), .given = R(radial_measured),
     .from = V(radial.uncertainty_m), MM, .csv_column = 25, .trend_key = "radial_uncertainty_mm", .trend = 9,
     .prom = 8, .prom_name = "uwbd_radial_max_change_uncertainty_meters",
     .prom_help = "Its 1-sigma uncertainty."},
    {"tilt_mm", &radial, NUMBER, .value = R(radial_tilt_mm), .given = R(radial_has_tilt), .decides = 1,
     .from = V(radial.tilt_m), MM, WITHHELD("tilt_withheld", radial_tilt_withheld), .csv_column = 26,
     .prom = 10, .prom_name = "uwbd_radial_tilt_meters",
     .prom_help = "The face's tilt from the baseline, top minus bottom, positive top nearer."},
    {"tilt_uncertainty_mm", &radial, NUMBER, .value = R(radial_tilt_uncertainty_mm),
     .given = R(radial_has_tilt_uncertainty), .decides = 1, .from = V(radial.tilt_uncertainty_m), MM,
     .csv_column = 27, .prom = 11, .prom_name = "uwbd_radial_tilt_uncertainty_meters",
     .prom_help = "The 1-sigma uncertainty of the face's tilt."},
    {"withheld", &radial, .kind = UWB_FIELD_TEXT, TEXT(radial_withheld)},
    {"lower_edge_mm", &baseline, NUMBER, .value = R(baseline_lower_edge_mm), .given = R(has_baseline),
     .decides = 1, .from = V(baseline.lower_m), MM},
    {"upper_edge_mm", &baseline, NUMBER, .value = R(baseline_upper_edge_mm), .given = R(has_baseline),
     .decides = 1, .from = V(baseline.upper_m), MM},
    {"center_mm", &baseline, NUMBER, .value = R(baseline_center_mm), .given = R(has_baseline),
     .from = V(baseline.center_m), MM},
    {"scan_id", &baseline, .kind = UWB_FIELD_TEXT, TEXT(baseline_scan_id), .csv_column = 14,
     .trend_key = "baseline", .trend = 11},
    {"direct_coupling_ps", &top, NUMBER, .value = R(direct_coupling_ps), .given = R(has_direct_coupling),
     .decides = 1, .from = V(direct_coupling_s), PS},
    {"direct_coupling_shift_ps", &top, NUMBER, .value = R(direct_coupling_shift_ps),
     .given = R(has_direct_coupling_shift), .decides = 1, .from = V(direct_coupling_shift_s), PS},
};

const struct uwb_field_table uwb_verdict_fields = {rows, sizeof rows / sizeof rows[0]};

/* The statuses by their published names (uwb/verdict.h). */
const char *uwb_status_name(enum uwb_status status)
{
    switch (status) {
    case UWB_STATUS_EDGES: return "edges";
    case UWB_STATUS_OK: return "ok";
    case UWB_STATUS_WATCH: return "watch";
    case UWB_STATUS_ALARM: return "alarm";
    case UWB_STATUS_INCONCLUSIVE: return "inconclusive";
    case UWB_STATUS_ERROR: return "error";
    }
    return "unknown";
}

int uwb_status_from_name(const char *name, enum uwb_status *out)
{
    static const enum uwb_status all[] = {UWB_STATUS_EDGES, UWB_STATUS_OK,           UWB_STATUS_WATCH,
                                          UWB_STATUS_ALARM, UWB_STATUS_INCONCLUSIVE, UWB_STATUS_ERROR};
    for (size_t i = 0; name && i < sizeof all / sizeof all[0]; i++) {
        if (strcmp(name, uwb_status_name(all[i])) == 0) {
            *out = all[i];
            return 0;
        }
    }
    return -1;
}

double *uwb_field_number(const struct uwb_field *f, void *record)
{
    return (double *)(void *)((char *)record + f->value);
}

static int flag_at(const void *record, size_t at)
{
    return at == 0 || *(const int *)((const char *)record + at) != 0;
}

static int *flag(void *record, size_t at)
{
    return (int *)((char *)record + at);
}

int uwb_field_given(const struct uwb_field *f, const void *record)
{
    return flag_at(record, f->group->given) && flag_at(record, f->given);
}

static const char *text(const void *record, size_t at)
{
    return (const char *)record + at;
}

double uwb_field_round(const struct uwb_field *f, double si)
{
    /* + 0.0 turns a -0 from rounding a small negative into 0. */
    return round(si * f->steps_per_si) / f->steps_per_unit + 0.0;
}

double uwb_field_si(const struct uwb_field *f, double published)
{
    return published / (f->steps_per_si / f->steps_per_unit);
}

void uwb_fields_publish(const struct uwb_field_table *t, void *record, const void *verdict)
{
    for (size_t i = 0; i < t->count; i++) {
        const struct uwb_field *f = &t->rows[i];
        if (f->kind == UWB_FIELD_NUMBER && f->from != 0 && uwb_field_given(f, record))
            *uwb_field_number(f, record) =
                uwb_field_round(f, *(const double *)(const void *)((const char *)verdict + f->from));
    }
}

static int same_group(const struct uwb_field *f, const char *group)
{
    if (!group || !f->group->key)
        return !group && !f->group->key;
    return strcmp(group, f->group->key) == 0;
}

const struct uwb_field *uwb_field_find(const struct uwb_field_table *t, const char *group, const char *key)
{
    for (size_t i = 0; i < t->count; i++)
        if (same_group(&t->rows[i], group) && strcmp(t->rows[i].key, key) == 0)
            return &t->rows[i];
    return NULL;
}

int uwb_field_flat_name(const struct uwb_field *f, char *buf, size_t n)
{
    int len =
        f->group->key ? snprintf(buf, n, "%s_%s", f->group->key, f->key) : snprintf(buf, n, "%s", f->key);
    return len < 0 || (size_t)len >= n ? -1 : 0;
}

/* ---- writing ------------------------------------------------------------------ */

/* key: the row's own (with its withheld key) or a TREND entry's (flat: without). */
static void write_row(const struct uwb_field *f, int flat, const void *record, cJSON *o)
{
    const char *key = flat ? f->trend_key : f->key;
    switch (f->kind) {
    case UWB_FIELD_STATUS:
        cJSON_AddStringToObject(o, key, uwb_status_name(*(const enum uwb_status *)text(record, f->value)));
        break;
    case UWB_FIELD_TEXT:
        if (text(record, f->value)[0])
            cJSON_AddStringToObject(o, key, text(record, f->value));
        break;
    case UWB_FIELD_NUMBER:
        if (flag_at(record, f->given))
            cJSON_AddNumberToObject(o, key, *uwb_field_number(f, (void *)record));
        else if (f->withheld_key && !flat && text(record, f->withheld)[0])
            cJSON_AddStringToObject(o, f->withheld_key, text(record, f->withheld));
        break;
    }
}

void uwb_fields_write(const struct uwb_field_table *t, const void *record, cJSON *o)
{
    const struct uwb_field_group *group = NULL;
    cJSON *into = o;
    for (size_t i = 0; i < t->count; i++) {
        const struct uwb_field *f = &t->rows[i];
        if (f->group != group) {
            group = f->group;
            into = !group->key                     ? o
                   : flag_at(record, group->given) ? cJSON_AddObjectToObject(o, group->key)
                                                   : NULL;
        }
        if (into)
            write_row(f, 0, record, into);
    }
}

/* The row at a TREND entry's place, or NULL. */
static const struct uwb_field *trend_row(const struct uwb_field_table *t, int at)
{
    for (size_t i = 0; i < t->count; i++)
        if (t->rows[i].trend == at)
            return &t->rows[i];
    return NULL;
}

void uwb_fields_write_trend(const struct uwb_field_table *t, const void *record, cJSON *o)
{
    for (int at = 1; at <= UWB_FIELD_PLACES; at++) {
        const struct uwb_field *f = trend_row(t, at);
        /* A text is said wherever it is known (an older line's baseline
         * may give its scan_id without its edges). */
        if (f && (f->kind == UWB_FIELD_TEXT || flag_at(record, f->group->given)))
            write_row(f, 1, record, o);
    }
}

/* ---- reading ------------------------------------------------------------------ */

static void read_row(struct uwb_json_key_reader *rd, const struct uwb_field *f, int flat, const cJSON *o,
                     void *record)
{
    const char *key = flat ? f->trend_key : f->key;
    int nested = f->group->key && !flat;
    char *at = (char *)record + f->value;
    switch (f->kind) {
    case UWB_FIELD_STATUS: {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
        if (!cJSON_IsString(v) || uwb_status_from_name(v->valuestring, (enum uwb_status *)(void *)at) != 0) {
            char name[64];
            snprintf(name, sizeof name, "%s%s%s", nested ? f->group->key : "", nested ? "." : "", key);
            uwb_json_key_refuse(rd, name, "missing or not a status");
        }
        break;
    }
    case UWB_FIELD_TEXT: uwb_json_key_text(rd, o, key, at, f->size); break;
    case UWB_FIELD_NUMBER:
        /* A figure's presence decides; what comes with it is read when there. */
        if (!uwb_json_key_number(rd, o, key, (double *)(void *)at) && f->decides)
            *flag(record, f->given) = 0;
        if (f->withheld_key && !flat)
            uwb_json_key_text(rd, o, f->withheld_key, (char *)record + f->withheld, f->withheld_size);
        break;
    }
}

/* The object a row's group is in o, NULL when absent (or not an object). */
static const cJSON *group_object(struct uwb_json_key_reader *rd, const struct uwb_field_group *group,
                                 const cJSON *o)
{
    if (!group->key)
        return o;
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(o, group->key);
    if (g && !cJSON_IsObject(g))
        uwb_json_key_refuse(rd, group->key, "not an object");
    return cJSON_IsObject(g) ? g : NULL;
}

int uwb_fields_read(const struct uwb_field_table *t, const cJSON *o, void *record, char *err, size_t errlen)
{
    struct uwb_json_key_reader rd = {.err = err, .errlen = errlen};
    struct uwb_json_key_reader unreported = {
        .err = err, .errlen = errlen, .failed = 1}; /* the second pass reports */
    /* A flag that deciding rows set holds when all of them are there:
     * set it where its group is, and let each missing one clear it. */
    for (size_t i = 0; i < t->count; i++) {
        const struct uwb_field *f = &t->rows[i];
        const cJSON *in = group_object(&unreported, f->group, o);
        if (in && f->group->key)
            *flag(record, f->group->given) = 1;
        if (in && f->decides)
            *flag(record, f->given) = 1;
    }
    const struct uwb_field_group *group = NULL;
    const cJSON *in = o;
    for (size_t i = 0; i < t->count; i++) {
        const struct uwb_field *f = &t->rows[i];
        if (f->group != group) {
            group = f->group;
            in = group_object(&rd, group, o);
        }
        if (in)
            read_row(&rd, f, 0, in, record);
        if (rd.failed && f->kind == UWB_FIELD_STATUS && !f->group->key)
            return -1; /* no status, no verdict: nothing further is worth reading */
    }
    return rd.failed ? -1 : 0;
}

int uwb_fields_read_trend(const struct uwb_field_table *t, const cJSON *o, void *record, char *err,
                          size_t errlen)
{
    struct uwb_json_key_reader rd = {.err = err, .errlen = errlen};
    for (int at = 1; at <= UWB_FIELD_PLACES; at++) {
        const struct uwb_field *f = trend_row(t, at);
        if (!f)
            continue;
        int there = cJSON_HasObjectItem(o, f->trend_key);
        /* A nested row's group is there when one of its keys is. */
        if (there && f->group->given)
            *flag(record, f->group->given) = 1;
        if (f->decides)
            *flag(record, f->given) = 1;
        if (there || (f->kind == UWB_FIELD_STATUS && !f->group->key))
            read_row(&rd, f, 1, o, record);
        else if (f->decides)
            *flag(record, f->given) = 0;
        if (rd.failed && f->kind == UWB_FIELD_STATUS && !f->group->key)
            return -1;
    }
    return rd.failed ? -1 : 0;
}

/* ---- the summaries' keys ------------------------------------------------------ */

static int place(const struct uwb_field *f, char which)
{
    return which == 's' ? f->summary : which == 'h' ? f->history : f->trend;
}

size_t uwb_fields_keys(const struct uwb_field_table *t, const struct uwb_field_extra *extra, size_t n_extra,
                       char which, const char **keys, size_t max)
{
    size_t n = 0;
    for (int at = 1; at <= UWB_FIELD_PLACES && n < max; at++) {
        const char *key = NULL;
        for (size_t i = 0; !key && i < t->count; i++) {
            const struct uwb_field *f = &t->rows[i];
            if (place(f, which) == at)
                key = which == 't' ? f->trend_key : f->key;
            else if (which == 'h' && f->group->key && f->group->history == at)
                key = f->group->key;
        }
        for (size_t i = 0; !key && i < n_extra; i++)
            if ((which == 's' ? extra[i].summary : which == 'h' ? extra[i].history : 0) == at)
                key = extra[i].key;
        if (key)
            keys[n++] = key;
    }
    return n;
}
