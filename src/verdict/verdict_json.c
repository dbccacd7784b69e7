#include "uwb/verdict_json.h"

#include <cjson/cJSON.h>
#include <math.h>

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

/* Millimetres to 0.01 mm: finer digits would claim precision nobody has.
 * (+ 0.0 turns a -0 from rounding a small negative into 0.) */
static void add_mm(cJSON *obj, const char *key, double metres)
{
    cJSON_AddNumberToObject(obj, key, round(metres * 1e5) / 100.0 + 0.0);
}

static void add_edges(cJSON *obj, const struct uwb_edges *e)
{
    add_mm(obj, "lower_edge_mm", e->lower_m);
    add_mm(obj, "upper_edge_mm", e->upper_m);
    add_mm(obj, "center_mm", e->center_m);
    add_mm(obj, "height_mm", e->height_m);
}

void uwb_json_add_ps(cJSON *obj, const char *key, double seconds)
{
    cJSON_AddNumberToObject(obj, key, round(seconds * 1e13) / 10.0 + 0.0);
}

cJSON *uwb_verdict_object(const struct uwb_verdict *v)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "class", "VERDICT");
    cJSON_AddStringToObject(o, "status", uwb_status_name(v->status));
    if (v->reason[0])
        cJSON_AddStringToObject(o, "reason", v->reason);
    if (v->fault[0])
        cJSON_AddStringToObject(o, "fault", v->fault);
    if (v->scan_id[0])
        cJSON_AddStringToObject(o, "scan_id", v->scan_id);
    if (v->created[0])
        cJSON_AddStringToObject(o, "created", v->created);
    int compared = v->has_baseline && v->current.found && v->baseline.found &&
                   v->status != UWB_STATUS_INCONCLUSIVE && v->status != UWB_STATUS_ERROR;
    if (compared) {
        add_mm(o, "axial_displacement_mm", v->axial_displacement_m);
        add_mm(o, "uncertainty_mm", v->uncertainty_m);
    }
    if (v->current.found) {
        add_edges(o, &v->current);
        if (compared && !v->height_change_withheld[0]) {
            add_mm(o, "height_change_mm", v->height_change_m);
            add_mm(o, "height_change_uncertainty_mm", v->height_change_uncertainty_m);
        } else if (compared) {
            cJSON_AddStringToObject(o, "height_change_withheld", v->height_change_withheld);
        }
        add_mm(o, "face_range_mm", v->current.face_z_m);
        cJSON_AddNumberToObject(o, "snr_db", round(v->current.snr_db * 10.0) / 10.0);
        add_mm(o, "edge_uncertainty_mm", fmax(v->current.sigma_lower_m, v->current.sigma_upper_m));
        if (v->current.side_reflector)
            add_mm(o, "side_reflector_mm", v->current.side_reflector_y_m);
    }
    if (v->has_baseline && v->baseline.found) {
        cJSON *b = cJSON_AddObjectToObject(o, "baseline");
        if (b) {
            add_mm(b, "lower_edge_mm", v->baseline.lower_m);
            add_mm(b, "upper_edge_mm", v->baseline.upper_m);
            add_mm(b, "center_mm", v->baseline.center_m);
            if (v->baseline_scan_id[0])
                cJSON_AddStringToObject(b, "scan_id", v->baseline_scan_id);
        }
    }
    if (v->has_direct_coupling)
        uwb_json_add_ps(o, "direct_coupling_ps", v->direct_coupling_s);
    if (v->has_direct_coupling_shift)
        uwb_json_add_ps(o, "direct_coupling_shift_ps", v->direct_coupling_shift_s);
    cJSON *images = cJSON_AddArrayToObject(o, "images");
    for (int i = 0; images && i < v->n_images; i++)
        cJSON_AddItemToArray(images, cJSON_CreateString(v->images[i]));
    return o;
}

char *uwb_verdict_to_json(const struct uwb_verdict *v)
{
    cJSON *o = uwb_verdict_object(v);
    char *text = o ? cJSON_PrintUnformatted(o) : NULL;
    cJSON_Delete(o);
    return text;
}
