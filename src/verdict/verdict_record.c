/* The evaluation's verdict as published (see the header): rounded here,
 * once, so every output carries the same figures. */
#include "uwb/verdict_record.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Millimetres to 0.01 mm: finer digits would claim precision nobody has.
 * (+ 0.0 turns a -0 from rounding a small negative into 0.) */
double uwb_record_mm(double metres)
{
    return round(metres * 1e5) / 100.0 + 0.0;
}

/* Seconds to picoseconds, to 0.1 ps. */
static double record_ps(double seconds)
{
    return round(seconds * 1e13) / 10.0 + 0.0;
}

void uwb_record_from_verdict(struct uwb_verdict_record *r, const struct uwb_verdict *v)
{
    memset(r, 0, sizeof *r);
    r->status = v->status;
    snprintf(r->reason, sizeof r->reason, "%s", v->reason);
    snprintf(r->fault, sizeof r->fault, "%s", v->fault);
    snprintf(r->scan_id, sizeof r->scan_id, "%s", v->scan_id);
    snprintf(r->created, sizeof r->created, "%s", v->created);
    int compared = v->has_baseline && v->current.found && v->baseline.found &&
                   v->status != UWB_STATUS_INCONCLUSIVE && v->status != UWB_STATUS_ERROR;
    if (compared && !v->axial_withheld) {
        r->has_displacement = 1;
        r->axial_displacement_mm = uwb_record_mm(v->axial_displacement_m);
        r->uncertainty_mm = uwb_record_mm(v->uncertainty_m);
    }
    if (v->current.found && v->edges_withheld[0])
        snprintf(r->edges_withheld, sizeof r->edges_withheld, "%s", v->edges_withheld);
    /* The height change is the pair's, published (or why not) whether or
     * not this scan's edges are. */
    if (v->current.found && compared && !v->height_change_withheld[0] && !v->edges_withheld[0]) {
        r->has_height_change = 1;
        r->height_change_mm = uwb_record_mm(v->height_change_m);
        r->height_change_uncertainty_mm = uwb_record_mm(v->height_change_uncertainty_m);
    } else if (v->current.found && compared) {
        snprintf(r->height_change_withheld, sizeof r->height_change_withheld, "%s",
                 v->height_change_withheld[0] ? v->height_change_withheld : v->edges_withheld);
    }
    if (v->current.found && !v->edges_withheld[0]) {
        r->has_edges = 1;
        r->lower_edge_mm = uwb_record_mm(v->current.lower_m);
        r->upper_edge_mm = uwb_record_mm(v->current.upper_m);
        r->center_mm = uwb_record_mm(v->current.center_m);
        r->height_mm = uwb_record_mm(v->current.height_m);
        r->face_range_mm = uwb_record_mm(v->current.face_z_m);
        r->snr_db = round(v->current.snr_db * 10.0) / 10.0;
        /* One sigma for every edge published: this scan's and the baseline's. */
        double edge_sigma = fmax(v->current.sigma_lower_m, v->current.sigma_upper_m);
        if (v->has_baseline && v->baseline.found)
            edge_sigma = fmax(edge_sigma, fmax(v->baseline.sigma_lower_m, v->baseline.sigma_upper_m));
        r->edge_uncertainty_mm = uwb_record_mm(edge_sigma);
        r->has_side_reflector = v->current.side_reflector != 0;
        if (r->has_side_reflector)
            r->side_reflector_mm = uwb_record_mm(v->current.side_reflector_y_m);
    }
    if (v->has_baseline && v->current.found && v->baseline.found && v->status != UWB_STATUS_ERROR) {
        const struct uwb_radial_verdict *rv = &v->radial;
        r->has_radial = 1;
        r->radial_status = rv->status;
        r->radial_measured = rv->measured;
        if (rv->measured) {
            r->radial_max_change_mm = uwb_record_mm(rv->max_change_m);
            r->radial_at_mm = uwb_record_mm(rv->at_m);
            r->radial_uncertainty_mm = uwb_record_mm(rv->uncertainty_m);
            r->radial_has_tilt = !rv->tilt_withheld[0];
            if (r->radial_has_tilt) {
                r->radial_tilt_mm = uwb_record_mm(rv->tilt_m);
                r->radial_has_tilt_uncertainty = 1;
                r->radial_tilt_uncertainty_mm = uwb_record_mm(rv->tilt_uncertainty_m);
            } else
                snprintf(r->radial_tilt_withheld, sizeof r->radial_tilt_withheld, "%s", rv->tilt_withheld);
            r->radial_has_span = rv->has_span;
            if (rv->has_span) {
                r->radial_from_mm = uwb_record_mm(rv->from_m);
                r->radial_to_mm = uwb_record_mm(rv->to_m);
            }
        }
        snprintf(r->radial_withheld, sizeof r->radial_withheld, "%s", rv->withheld);
    }
    if (v->has_baseline && v->baseline.found) {
        r->has_baseline = 1;
        r->baseline_lower_edge_mm = uwb_record_mm(v->baseline.lower_m);
        r->baseline_upper_edge_mm = uwb_record_mm(v->baseline.upper_m);
        r->baseline_center_mm = uwb_record_mm(v->baseline.center_m);
        snprintf(r->baseline_scan_id, sizeof r->baseline_scan_id, "%s", v->baseline_scan_id);
    }
    r->has_direct_coupling = v->has_direct_coupling != 0;
    if (r->has_direct_coupling)
        r->direct_coupling_ps = record_ps(v->direct_coupling_s);
    r->has_direct_coupling_shift = v->has_direct_coupling_shift != 0;
    if (r->has_direct_coupling_shift)
        r->direct_coupling_shift_ps = record_ps(v->direct_coupling_shift_s);
    r->n_images = v->n_images < 0 ? 0 : v->n_images > UWB_MAX_IMAGES ? UWB_MAX_IMAGES : v->n_images;
    for (int i = 0; i < r->n_images; i++)
        snprintf(r->images[i], sizeof r->images[i], "%s", v->images[i]);
}
