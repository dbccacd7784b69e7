/* Returns on the migrated image as strong as the winding's face but away
 * from it (a clamping plate, a tank wall, a press board's end) are ringed
 * and labelled "not the winding": the face is where the edges say, not
 * necessarily the brightest thing in the picture. */
#include "output/render_internal.h"

#include <math.h>

#define FACE_MARGIN_M 0.04 /* the face's blur beyond its edges and either side of its range */
#define STRONG_DB (-6.0)   /* within this of the face's own peak, or brighter */
#define APART_M 0.06       /* two labels at least this far apart */
#define MAX_LABELS 2
#define RING_RADIUS 9

static const struct uwb_rgb white = {255, 255, 255};
static const struct uwb_rgb ink = {25, 25, 25};

static int near_face(const struct uwb_edges *e, double y, double z)
{
    return fabs(z - e->face_z_m) <= FACE_MARGIN_M && y >= e->lower_m - FACE_MARGIN_M &&
           y <= e->upper_m + FACE_MARGIN_M;
}

/* The strongest pixel off the face, at least APART_M from those already
 * found; its value, or 0 when there is none above `least`. */
static double strongest_off_face(const struct uwb_image *img, const struct uwb_edges *e, double least,
                                 const double (*found)[2], int n_found, double *y_out, double *z_out)
{
    double best = 0.0;
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double v = img->pix[(size_t)iy * (size_t)img->nz + (size_t)iz];
            double y = img->y0_m + iy * img->dy_m, z = img->z0_m + iz * img->dz_m;
            if (!(v >= least) || !(v > best) || near_face(e, y, z))
                continue;
            int close = 0;
            for (int k = 0; k < n_found && !close; k++)
                close = hypot(y - found[k][0], z - found[k][1]) < APART_M;
            if (close)
                continue;
            best = v;
            *y_out = y;
            *z_out = z;
        }
    return best;
}

static void ring(struct uwb_canvas *c, int cx, int cy, int r, struct uwb_rgb colour)
{
    for (int dy = -r - 1; dy <= r + 1; dy++)
        for (int dx = -r - 1; dx <= r + 1; dx++) {
            double d = hypot(dx, dy);
            if (d >= r - 1.0 && d <= r + 0.5)
                uwb_canvas_put(c, cx + dx, cy + dy, colour);
        }
}

static void label(struct uwb_canvas *c, const struct uwb_plot *p, int cx, int cy, int scale)
{
    const char *text = "not the winding";
    int w = uwb_text_width(text, scale), h = UWB_FONT_CAP_HEIGHT * scale;
    int x = cx + RING_RADIUS + 4; /* right of the ring, else left of it */
    if (x + w + 2 >= p->x + p->w)
        x = cx - RING_RADIUS - 4 - w;
    if (x - 2 < p->x)
        x = p->x + 2;
    int y = cy - h / 2;
    if (y - 2 < p->y)
        y = p->y + 2;
    if (y + h + 2 >= p->y + p->h)
        y = p->y + p->h - h - 3;
    uwb_canvas_fill_rect(c, x - 2, y - 2, w + 4, h + 4, white);
    uwb_draw_text(c, x, y, text, scale, ink);
}

void uwb_mark_strong_returns(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                             const struct uwb_edges *e, int label_scale)
{
    if (!e || !e->found || !img->pix)
        return;
    double face_peak = 0.0;
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double v = img->pix[(size_t)iy * (size_t)img->nz + (size_t)iz];
            if (v > face_peak && near_face(e, img->y0_m + iy * img->dy_m, img->z0_m + iz * img->dz_m))
                face_peak = v;
        }
    if (!(face_peak > 0.0))
        return;
    double least = face_peak * pow(10.0, STRONG_DB / 20.0), found[MAX_LABELS][2] = {{0.0, 0.0}};
    int n = 0;
    while (n < MAX_LABELS &&
           strongest_off_face(img, e, least, (const double(*)[2])found, n, &found[n][0], &found[n][1]) > 0.0)
        n++;
    for (int k = 0; k < n; k++) {
        int cx = uwb_plot_col(p, found[k][1]), cy = uwb_plot_row(p, found[k][0]);
        ring(c, cx, cy, RING_RADIUS + 1, ink);
        ring(c, cx, cy, RING_RADIUS, white);
        label(c, p, cx, cy, label_scale);
    }
}
