/* A reflector across the image's whole height, away from the winding's
 * face, labelled on the migrated image: in a tank the brightest thing
 * that is not the winding is often a flat surface the antenna sees at
 * every height (in the demo's tank-3d scene the core leg's front face,
 * 70 mm behind the winding's face: face 450 mm + outer radius 150 mm -
 * core_front 80 mm = 520 mm). uwbd does not know the tank's geometry, so
 * the label says where it is and that it is not the winding, not what
 * it is (uwbd-images(7) lists what it may be). */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>

#define FACE_MARGIN_M 0.04 /* the face's blur either side of its range */
#define BAND_DB (-20.0)    /* a row counts where the column is within this of the face's peak */
#define BAND_COVERAGE 0.6  /* ... in this share of the rows or more: the whole height */

static const struct uwb_rgb white = {255, 255, 255};
static const struct uwb_rgb ink = {25, 25, 25};

static double pixel(const struct uwb_image *img, int iy, int iz)
{
    double v = img->pix[(size_t)iy * (size_t)img->nz + (size_t)iz];
    return isfinite(v) ? v : 0.0;
}

static double column_mean(const struct uwb_image *img, int iz)
{
    double sum = 0.0;
    for (int iy = 0; iy < img->ny; iy++)
        sum += pixel(img, iy, iz);
    return sum / img->ny;
}

int uwb_find_reflector_band(const struct uwb_image *img, const struct uwb_edges *e, double *z_out)
{
    if (!e || !e->found || !img->pix || img->ny < 2)
        return 0;
    double face_peak = 0.0;
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++)
            if (fabs(img->z0_m + iz * img->dz_m - e->face_z_m) <= FACE_MARGIN_M)
                face_peak = fmax(face_peak, pixel(img, iy, iz));
    if (!(face_peak > 0.0))
        return 0;
    double least = face_peak * pow(10.0, BAND_DB / 20.0), best_mean = 0.0;
    int best = -1;
    for (int iz = 0; iz < img->nz; iz++) {
        if (fabs(img->z0_m + iz * img->dz_m - e->face_z_m) <= FACE_MARGIN_M)
            continue;
        int bright = 0;
        for (int iy = 0; iy < img->ny; iy++)
            bright += pixel(img, iy, iz) >= least;
        double mean = column_mean(img, iz);
        if (bright >= BAND_COVERAGE * img->ny && mean > best_mean) {
            best_mean = mean;
            best = iz;
        }
    }
    if (best < 0)
        return 0;
    /* Its middle: the columns either side as bright as it, nearly. */
    int lo = best, hi = best;
    while (lo > 0 && column_mean(img, lo - 1) >= 0.9 * best_mean)
        lo--;
    while (hi + 1 < img->nz && column_mean(img, hi + 1) >= 0.9 * best_mean)
        hi++;
    *z_out = img->z0_m + 0.5 * (lo + hi) * img->dz_m;
    return 1;
}

void uwb_mark_reflector_band(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                             const struct uwb_edges *e, int scale)
{
    double z;
    if (!uwb_find_reflector_band(img, e, &z))
        return;
    char where[48];
    snprintf(where, sizeof where, "reflector at %.0f mm", z * 1e3);
    const char *lines[3] = {where, "full height:", "not the winding"};
    int line = UWB_FONT_LINE_HEIGHT * scale, w = 0;
    for (int i = 0; i < 3; i++)
        w = fmax(w, uwb_text_width(lines[i], scale));
    int col = uwb_plot_col(p, z), bh = 3 * line + 2;
    /* Low in the plot, beside the band (over it where the plot is narrow),
     * with a tick from the box to the band. */
    int x = col + 8;
    if (x + w + 4 > p->x + p->w)
        x = col - 8 - w;
    if (x - 2 < p->x)
        x = p->x + 2;
    int y = p->y + p->h - bh - 6 * scale - 2;
    uwb_canvas_fill_rect(c, x - 2, y - 2, w + 4, bh + 2, white);
    for (int i = 0; i < 3; i++)
        uwb_draw_text(c, x, y + i * line, lines[i], scale, ink);
    int tick_from = x > col ? col + 1 : x + w + 2, tick_to = x > col ? x - 2 : col - 1;
    int ty = y + line / 2;
    uwb_canvas_line(c, tick_from, ty, tick_to, ty, white, 3, 0, 0);
    uwb_canvas_line(c, tick_from, ty, tick_to, ty, ink, 1, 0, 0);
}
