/* The face's intensity along y and where it starts and stops. */
#include "imaging_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

int face_profile(const struct uwb_image *img, double z_face_m, double half_width_m,
                 struct uwb_face_profile *p, char *err, size_t errlen)
{
    int lo = (int)floor((z_face_m - half_width_m - img->z0_m) / img->dz_m);
    int hi = (int)ceil((z_face_m + half_width_m - img->z0_m) / img->dz_m);
    if (lo < 0)
        lo = 0;
    if (hi > img->nz - 1)
        hi = img->nz - 1;
    if (lo > hi) {
        snprintf(err, errlen, "face range %.3f m is outside the image", z_face_m);
        return -1;
    }
    p->value = malloc((size_t)img->ny * sizeof *p->value);
    if (!p->value) {
        snprintf(err, errlen, "out of memory for the face profile");
        return -1;
    }
    p->n = img->ny;
    p->y0_m = img->y0_m;
    p->dy_m = img->dy_m;
    for (int iy = 0; iy < img->ny; iy++) {
        float best = 0.0f;
        for (int iz = lo; iz <= hi; iz++) {
            float v = img->pix[(size_t)iy * img->nz + iz];
            if (v > best)
                best = v;
        }
        p->value[iy] = best;
    }
    return 0;
}

void profile_edges(const struct uwb_face_profile *p, double fraction, struct profile_edges *e)
{
    int ip = 0;
    for (int i = 1; i < p->n; i++)
        if (p->value[i] > p->value[ip])
            ip = i;
    double level = fraction * p->value[ip];
    e->peak = p->value[ip];
    e->peak_y_m = p->y0_m + ip * p->dy_m;
    e->ok = 0;

    int a = ip;
    while (a > 0 && p->value[a - 1] >= level)
        a--;
    int b = ip;
    while (b < p->n - 1 && p->value[b + 1] >= level)
        b++;
    if (a == 0 || b == p->n - 1)
        return;
    /* Crossing between samples a-1 (below) and a (at or above). */
    double below = p->value[a - 1], above = p->value[a];
    e->lower_m = p->y0_m + (a - 1 + (level - below) / (above - below)) * p->dy_m;
    e->slope_lower = (above - below) / p->dy_m;
    above = p->value[b];
    below = p->value[b + 1];
    e->upper_m = p->y0_m + (b + (above - level) / (above - below)) * p->dy_m;
    e->slope_upper = (above - below) / p->dy_m;
    e->ok = 1;
}
