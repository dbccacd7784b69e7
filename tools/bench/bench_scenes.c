/* The bench's inputs: scans simulated by uwbsim (the default 3-D scene with
 * clutter and noise), conditioned as the pipeline conditions them, so the
 * migration sums realistic traces rather than zeros. */
#include "bench.h"

#include <stdio.h>

#include "uwb/condition.h"
#include "uwbsim/uwbsim.h"

static int set_number(struct sim_scene *sc, const char *key, double value, char *err, size_t errlen)
{
    char text[64];
    snprintf(text, sizeof text, "%.17g", value);
    return sim_scene_set(sc, key, text, err, errlen);
}

int bench_simulate(const struct bench_case *c, double displacement_m, struct uwb_scan *raw,
                   struct uwb_scan *conditioned, char *err, size_t errlen)
{
    struct sim_scene sc;
    if (sim_scene_default(&sc) != 0) {
        snprintf(err, errlen, "uwbsim: default scene rejected");
        return -1;
    }
    if (set_number(&sc, "positions", c->positions, err, errlen) != 0 ||
        set_number(&sc, "samples", c->samples, err, errlen) != 0 ||
        set_number(&sc, "position_step_m", c->position_step_m, err, errlen) != 0 ||
        set_number(&sc, "displacement_m", displacement_m, err, errlen) != 0 ||
        sim_scene_validate(&sc, err, errlen) != 0)
        return -1;
    snprintf(sc.scan_id, sizeof sc.scan_id, "bench-%dx%d-%+.0fmm", c->positions, c->samples,
             displacement_m * 1e3);
    struct uwb_scan scan;
    if (sim_make_scan(&sc, 1, &scan, err, errlen) != 0)
        return -1;
    if (conditioned) {
        struct uwb_geometry g;
        uwb_geometry_from_scan(&g, &scan, 0.0);
        struct uwb_condition_options opt;
        uwb_condition_defaults(&opt);
        double dominant_hz;
        if (uwb_dominant_frequency(&scan, &dominant_hz, err, errlen) != 0 ||
            uwb_condition(&scan, &g, &opt, dominant_hz, NULL, conditioned, err, errlen) != 0) {
            uwb_scan_free(&scan);
            return -1;
        }
    }
    if (raw)
        *raw = scan;
    else
        uwb_scan_free(&scan);
    return 0;
}
