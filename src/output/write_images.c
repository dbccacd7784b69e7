#include "uwb/render.h"

#include <stdio.h>

int uwb_write_images(const char *dir, const char *stem, const struct uwb_provenance *site,
                     const struct uwb_scan *current, const struct uwb_analysis *cur_a,
                     const struct uwb_analysis *base_a, struct uwb_verdict *v, char *err, size_t errlen)
{
    static const char *const kinds[] = {"migrated", "bscan", "comparison"};
    v->n_images = 0;
    /* The stem names a scan that has no id (a replayed file). */
    struct uwb_provenance prov = {0};
    if (site)
        prov = *site;
    prov.scan_name = stem;
    prov.stack = current->stack;
    prov.eps_r = current->eps_r;
    if (current->positions > 0 && current->antenna_y_m) {
        prov.has_travel = 1;
        prov.travel_lo_m = current->antenna_y_m[0]; /* strictly increasing (uwb/scan.h) */
        prov.travel_hi_m = current->antenna_y_m[current->positions - 1];
    }
    if (cur_a->search_z_hi_m > cur_a->search_z_lo_m) {
        prov.has_search_window = 1;
        prov.search_z_lo_m = cur_a->search_z_lo_m;
        prov.search_z_hi_m = cur_a->search_z_hi_m;
    }
    struct uwb_render_options opt;
    uwb_render_options_default(&opt);
    opt.provenance = &prov;
    for (int i = 0; i < 3; i++) {
        char *path = v->images[v->n_images];
        int n = snprintf(path, sizeof v->images[0], "%s/%s-%s.png", dir, stem, kinds[i]);
        if (n < 0 || (size_t)n >= sizeof v->images[0]) {
            snprintf(err, errlen, "%s: output path too long", dir);
            return -1;
        }
        /* An analysis that stopped before imaging (e.g. an inconclusive "record
         * too short") has no migrated image: the B-scan alone is written. */
        if (i != 1 && !cur_a->intensity.pix)
            continue;
        int rc;
        if (i == 0)
            rc = uwb_render_migrated_png_opt(path, &cur_a->intensity, v, &opt, err, errlen);
        else if (i == 1) {
            /* The traces the migration ran on, when the analysis got that
             * far; the raw ones otherwise (titled so). */
            int conditioned = cur_a->conditioned.data && cur_a->conditioned.positions > 0;
            opt.bscan_conditioned = conditioned;
            rc = uwb_render_bscan_png_opt(path, conditioned ? &cur_a->conditioned : current, v, &opt, err,
                                          errlen);
            opt.bscan_conditioned = 0;
        } else
            rc = uwb_render_comparison_png_opt(path, cur_a, base_a && base_a->intensity.pix ? base_a : NULL,
                                               v, &opt, err, errlen);
        if (rc != 0)
            return -1;
        v->n_images++;
    }
    return 0;
}
