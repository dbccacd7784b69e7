/* The intensity image painted into a plot: bilinear in linear amplitude,
 * then dB re the image peak through the perceptual colour map. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const struct uwb_rgb outside_grid = {128, 128, 128};

int uwb_image_check(const struct uwb_image *img, const char *name, char *err, size_t errlen)
{
    if (!img || !img->pix) {
        snprintf(err, errlen, "%s: no image data", name);
        return -1;
    }
    if (img->ny < 2 || img->nz < 2) {
        snprintf(err, errlen, "%s: image of %d x %d pixels is too small to draw", name, img->ny, img->nz);
        return -1;
    }
    if (!(img->dy_m > 0) || !(img->dz_m > 0) || !isfinite(img->y0_m) || !isfinite(img->z0_m) ||
        !isfinite(img->dy_m) || !isfinite(img->dz_m)) {
        snprintf(err, errlen, "%s: image grid spacing must be finite and positive (dy %g m, dz %g m)", name,
                 img->dy_m, img->dz_m);
        return -1;
    }
    return 0;
}

/* Amplitude at a pixel; negative or non-finite values (which an envelope
 * should not have) count as nothing rather than spoil the scale. */
static double amplitude(const struct uwb_image *img, int iy, int iz)
{
    double v = img->pix[(size_t)iy * (size_t)img->nz + (size_t)iz];
    return isfinite(v) && v > 0 ? v : 0.0;
}

double uwb_image_peak(const struct uwb_image *img)
{
    double peak = 0.0;
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double v = amplitude(img, iy, iz);
            if (v > peak)
                peak = v;
        }
    return peak;
}

double uwb_db_to_t(double amplitude_value, double peak, double floor_db)
{
    if (!(peak > 0) || !(amplitude_value > 0))
        return 0.0;
    double db = 20.0 * log10(amplitude_value / peak);
    double t = (db - floor_db) / (0.0 - floor_db);
    return t < 0 ? 0 : t > 1 ? 1 : t;
}

/* Colour-map steps of the painted dB scale: 4096 over the scale's 30 to
 * 60 dB is a hundredth of a dB or less per step, finer than the 8-bit
 * colours can show (they change by at most one level against the exact
 * map). The ends are exact: the peak paints the map's top colour, the
 * floor its bottom colour. */
#define PAINT_LEVELS 4096

/* Where a plot pixel falls on the image grid along one axis: the lower
 * grid index and the weight of the next one; index -1 outside the grid
 * (more than half a pixel beyond its ends). */
struct grid_step {
    int index;
    float next_weight;
};

static void grid_steps(struct grid_step *steps, int pixels, double lo, double hi, int descending,
                       double origin, double spacing, int cells)
{
    for (int i = 0; i < pixels; i++) {
        int j = descending ? pixels - 1 - i : i;
        double x = lo + (hi - lo) * j / (pixels > 1 ? pixels - 1 : 1);
        double f = (x - origin) / spacing;
        if (f < -0.5 || f > cells - 0.5) {
            steps[i].index = -1;
            steps[i].next_weight = 0.0f;
            continue;
        }
        f = f < 0 ? 0 : f > cells - 1 ? cells - 1 : f;
        int k = (int)f;
        if (k > cells - 2)
            k = cells - 2;
        steps[i].index = k;
        steps[i].next_weight = (float)(f - k);
    }
}

void uwb_paint_image_db(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                        double peak, double floor_db)
{
    if (p->w <= 0 || p->h <= 0)
        return;
    struct grid_step *rows = malloc(sizeof *rows * (size_t)p->h), *cols = malloc(sizeof *cols * (size_t)p->w);
    struct uwb_rgb *palette = malloc(sizeof *palette * PAINT_LEVELS);
    if (!rows || !cols || !palette) {
        free(rows);
        free(cols);
        free(palette);
        uwb_canvas_fill_rect(c, p->x, p->y, p->w, p->h, outside_grid);
        return;
    }
    /* Row 0 is the plot's top (y_max). */
    grid_steps(rows, p->h, p->y_min, p->y_max, 1, img->y0_m, img->dy_m, img->ny);
    grid_steps(cols, p->w, p->x_min, p->x_max, 0, img->z0_m, img->dz_m, img->nz);
    for (int i = 0; i < PAINT_LEVELS; i++)
        palette[i] = uwb_colormap_perceptual((double)i / (PAINT_LEVELS - 1));
    /* t = (20 log10(a / peak) - floor) / -floor, as log2 of the ratio. */
    double t_per_log2 = 20.0 * log10(2.0) / -floor_db;
    int have_peak = peak > 0 && floor_db < 0;
    for (int row = 0; row < p->h; row++) {
        int iy = rows[row].index;
        float ay = rows[row].next_weight;
        const float *r0 = iy >= 0 ? img->pix + (size_t)iy * img->nz : NULL;
        const float *r1 = r0 ? r0 + img->nz : NULL;
        for (int col = 0; col < p->w; col++) {
            int iz = cols[col].index;
            struct uwb_rgb colour;
            if (iy < 0 || iz < 0) {
                colour = outside_grid;
            } else {
                float az = cols[col].next_weight;
                float v00 = r0[iz], v01 = r0[iz + 1], v10 = r1[iz], v11 = r1[iz + 1];
                /* Negative or non-finite values (which an envelope should
                 * not have) count as nothing rather than spoil the scale. */
                v00 = isfinite(v00) && v00 > 0 ? v00 : 0.0f;
                v01 = isfinite(v01) && v01 > 0 ? v01 : 0.0f;
                v10 = isfinite(v10) && v10 > 0 ? v10 : 0.0f;
                v11 = isfinite(v11) && v11 > 0 ? v11 : 0.0f;
                double a = (1 - ay) * ((1 - az) * v00 + az * v01) + ay * ((1 - az) * v10 + az * v11);
                int level = 0;
                if (have_peak && a > 0) {
                    double t = 1.0 + t_per_log2 * log2(a / peak);
                    level = t <= 0 ? 0 : t >= 1 ? PAINT_LEVELS - 1 : (int)(t * (PAINT_LEVELS - 1) + 0.5);
                }
                colour = palette[level];
            }
            uwb_canvas_put(c, p->x + col, p->y + row, colour);
        }
    }
    free(rows);
    free(cols);
    free(palette);
}

double uwb_image_peak_z(const struct uwb_image *img)
{
    double peak = -1;
    int best = 0;
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double v = amplitude(img, iy, iz);
            if (v > peak) {
                peak = v;
                best = iz;
            }
        }
    return img->z0_m + best * img->dz_m;
}
