#include "simulate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"

static int dup_text(char **dst, const char *text)
{
    *dst = NULL;
    if (!text || !text[0])
        return 0;
    *dst = strdup(text);
    return *dst ? 0 : -1;
}

int sim_make_scan(const struct sim_scene *s, uint64_t seed, struct uwb_scan *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    struct sim_engine *engine;
    if (sim_engine_create(s, &engine, err, errlen) != 0)
        return -1;
    if (uwb_scan_alloc(out, s->positions, s->samples, err, errlen) != 0) {
        sim_engine_free(engine);
        return -1;
    }
    out->sample_interval_s = s->sample_interval_s;
    out->t0_s = s->t0_s;
    out->tx_m[0] = s->tx_dy_m;
    out->tx_m[1] = s->tx_dz_m;
    out->rx_m[0] = s->rx_dy_m;
    out->rx_m[1] = s->rx_dz_m;
    out->eps_r = s->eps_r;
    out->stack = s->stack;
    if (!isnan(s->target_z_near_m)) {
        out->has_target_z = 1;
        out->target_z_m[0] = s->target_z_near_m;
        out->target_z_m[1] = s->target_z_far_m;
    }
    char source[128];
    snprintf(source, sizeof source, "uwbsim %s (%s physical optics)", SIM_VERSION,
             s->mode == SIM_MODE_2D ? "2-D" : "3-D");
    if (dup_text(&out->source, source) || dup_text(&out->created, s->created) ||
        dup_text(&out->scan_id, s->scan_id) || dup_text(&out->comment, s->comment)) {
        snprintf(err, errlen, "scan: out of memory");
        goto fail;
    }
    struct sim_acq acq;
    sim_acq_init(&acq, seed);
    for (int k = 0; k < s->positions; k++) {
        double y = sim_scene_antenna_y_m(s, k);
        out->antenna_y_m[k] = y;
        if (sim_engine_acquire(engine, y, 0, &acq, out->data + (size_t)k * s->samples, err, errlen) != 0)
            goto fail;
    }
    sim_engine_free(engine);
    return 0;
fail:
    sim_engine_free(engine);
    uwb_scan_free(out);
    return -1;
}
