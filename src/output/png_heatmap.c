/* The intensity image painted into a plot: bilinear in linear amplitude,
 * then dB re the image peak through the perceptual colour map. */
#include "uwb/render.h"

#include <math.h>
#include <stdio.h>

static const struct uwb_rgb outside_grid = { 128, 128, 128 };

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
    if (!(img->dy_m > 0) || !(img->dz_m > 0) || !isfinite(img->y0_m) || !isfinite(img->z0_m)
        || !isfinite(img->dy_m) || !isfinite(img->dz_m)) {
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

/* Bilinear sample at fractional grid position; -1 outside the grid. */
static double sample(const struct uwb_image *img, double fy, double fz)
{
    if (fy < -0.5 || fz < -0.5 || fy > img->ny - 0.5 || fz > img->nz - 0.5)
        return -1.0;
    fy = fy < 0 ? 0 : fy > img->ny - 1 ? img->ny - 1 : fy;
    fz = fz < 0 ? 0 : fz > img->nz - 1 ? img->nz - 1 : fz;
    int iy = (int)fy, iz = (int)fz;
    if (iy > img->ny - 2)
        iy = img->ny - 2;
    if (iz > img->nz - 2)
        iz = img->nz - 2;
    double ay = fy - iy, az = fz - iz;
    return (1 - ay) * ((1 - az) * amplitude(img, iy, iz) + az * amplitude(img, iy, iz + 1))
         + ay * ((1 - az) * amplitude(img, iy + 1, iz) + az * amplitude(img, iy + 1, iz + 1));
}

double uwb_db_to_t(double amplitude_value, double peak, double floor_db)
{
    if (!(peak > 0) || !(amplitude_value > 0))
        return 0.0;
    double db = 20.0 * log10(amplitude_value / peak);
    double t = (db - floor_db) / (0.0 - floor_db);
    return t < 0 ? 0 : t > 1 ? 1 : t;
}

void uwb_paint_image_db(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                        double peak, double floor_db)
{
    for (int row = 0; row < p->h; row++) {
        double y = p->y_max - (p->y_max - p->y_min) * row / (p->h > 1 ? p->h - 1 : 1);
        double fy = (y - img->y0_m) / img->dy_m;
        for (int col = 0; col < p->w; col++) {
            double z = p->x_min + (p->x_max - p->x_min) * col / (p->w > 1 ? p->w - 1 : 1);
            double a = sample(img, fy, (z - img->z0_m) / img->dz_m);
            struct uwb_rgb colour = a < 0 ? outside_grid : uwb_colormap_perceptual(uwb_db_to_t(a, peak, floor_db));
            uwb_canvas_put(c, p->x + col, p->y + row, colour);
        }
    }
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
