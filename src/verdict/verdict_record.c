/* The evaluation's verdict as published (see the header): rounded here,
 * once, by the field table (uwb/verdict_fields.h), so every output
 * carries the same figures. */
#include "uwb/verdict_record.h"

#include "uwb/verdict_fields.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void uwb_record_from_verdict(struct uwb_verdict_record *r, const struct uwb_verdict *v)
{
    memset(r, 0, sizeof *r);
    r->status = v->status;
    snprintf(r->reason, sizeof r->reason, "%s", v->reason);
    snprintf(r->fault, sizeof r->fault, "%s", v->fault);
    snprintf(r->scan_id, sizeof r->scan_id, "%s", v->scan_id);
    snprintf(r->created, sizeof r->created, "%s", v->created);
    /* Which figures the verdict gives; their values come from the table. */
    int compared = v->has_baseline && v->current.found && v->baseline.found &&
                   v->status != UWB_STATUS_INCONCLUSIVE && v->status != UWB_STATUS_ERROR;
    r->has_displacement = compared && !v->axial_withheld;
    if (v->current.found && v->edges_withheld[0])
        snprintf(r->edges_withheld, sizeof r->edges_withheld, "%s", v->edges_withheld);
    /* The height change is the pair's, published (or why not) whether or
     * not this scan's edges are. */
    r->has_height_change =
        v->current.found && compared && !v->height_change_withheld[0] && !v->edges_withheld[0];
    if (v->current.found && compared && !r->has_height_change)
        snprintf(r->height_change_withheld, sizeof r->height_change_withheld, "%s",
                 v->height_change_withheld[0] ? v->height_change_withheld : v->edges_withheld);
    if (v->current.found && !v->edges_withheld[0]) {
        r->has_edges = 1;
        r->has_side_reflector = v->current.side_reflector != 0;
    }
    if (v->has_baseline && v->current.found && v->baseline.found && v->status != UWB_STATUS_ERROR) {
        const struct uwb_radial_verdict *rv = &v->radial;
        r->has_radial = 1;
        r->radial_status = rv->status;
        r->radial_measured = rv->measured;
        if (rv->measured) {
            r->radial_has_tilt = !rv->tilt_withheld[0];
            r->radial_has_tilt_uncertainty = r->radial_has_tilt;
            if (!r->radial_has_tilt)
                snprintf(r->radial_tilt_withheld, sizeof r->radial_tilt_withheld, "%s", rv->tilt_withheld);
            r->radial_has_span = rv->has_span;
        }
        snprintf(r->radial_withheld, sizeof r->radial_withheld, "%s", rv->withheld);
    }
    if (v->has_baseline && v->baseline.found) {
        r->has_baseline = 1;
        snprintf(r->baseline_scan_id, sizeof r->baseline_scan_id, "%s", v->baseline_scan_id);
    }
    r->has_direct_coupling = v->has_direct_coupling != 0;
    r->has_direct_coupling_shift = v->has_direct_coupling_shift != 0;
    uwb_fields_publish(&uwb_verdict_fields, r, v);
    if (r->has_edges) {
        /* One sigma for every edge published: this scan's and the baseline's. */
        double edge_sigma = fmax(v->current.sigma_lower_m, v->current.sigma_upper_m);
        if (v->has_baseline && v->baseline.found)
            edge_sigma = fmax(edge_sigma, fmax(v->baseline.sigma_lower_m, v->baseline.sigma_upper_m));
        r->edge_uncertainty_mm =
            uwb_field_round(uwb_field_find(&uwb_verdict_fields, NULL, "edge_uncertainty_mm"), edge_sigma);
    }
    r->n_images = v->n_images < 0 ? 0 : v->n_images > UWB_MAX_IMAGES ? UWB_MAX_IMAGES : v->n_images;
    for (int i = 0; i < r->n_images; i++)
        snprintf(r->images[i], sizeof r->images[i], "%s", v->images[i]);
}
