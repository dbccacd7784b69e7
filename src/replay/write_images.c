#include "uwb/evaluate.h"

#include <stdio.h>

#include "uwb/render.h"

int uwb_write_images(const char *dir, const char *stem, const struct uwb_scan *current,
                     const struct uwb_analysis *cur_a, const struct uwb_analysis *base_a,
                     struct uwb_verdict *v, char *err, size_t errlen)
{
    static const char *const kinds[] = {"migrated", "bscan", "comparison"};
    v->n_images = 0;
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
            rc = uwb_render_migrated_png(path, &cur_a->intensity, v, err, errlen);
        else if (i == 1)
            rc = uwb_render_bscan_png(path, current, v, err, errlen);
        else
            rc = uwb_render_comparison_png(path, cur_a, base_a && base_a->intensity.pix ? base_a : NULL,
                                       v, err, errlen);
        if (rc != 0)
            return -1;
        v->n_images++;
    }
    return 0;
}
