/* The migrated image as an engineer reads it: envelope in dB re its peak
 * (perceptual map, colour bar), height y up the page as in the tank, range
 * z across, both in mm; this scan's edges solid, the baseline's dashed. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>

static const struct uwb_rgb page = {255, 255, 255};

/* Edge lines span this fraction of the plot width either side of the face:
 * long enough to catch the eye, short enough not to hide the face region. */
#define FACE_REGION_FRACTION 0.12

void uwb_render_migrated_layout(const struct uwb_image *intensity, const struct uwb_verdict *v,
                                const struct uwb_render_options *opt, struct uwb_plot *plot, int *colorbar_x,
                                int *colorbar_w)
{
    struct uwb_render_options o;
    uwb_render_options_sane(opt, &o);
    uwb_layout_single_plot(o.width, o.height, o.font_scale,
                           uwb_caption_height(v, o.provenance, o.width, o.font_scale), plot, colorbar_x,
                           colorbar_w);
    plot->x_min = intensity->z0_m;
    plot->x_max = intensity->z0_m + (intensity->nz - 1) * intensity->dz_m;
    plot->y_min = intensity->y0_m;
    plot->y_max = intensity->y0_m + (intensity->ny - 1) * intensity->dy_m;
    /* Equal mm per pixel across and up, so the winding's shape and the
     * distances an engineer reads off the picture are true: the plot keeps
     * its top-left corner and gives up width or height, the colour bar
     * follows its right side. */
    double zspan = plot->x_max - plot->x_min, yspan = plot->y_max - plot->y_min;
    if (zspan > 0.0 && yspan > 0.0) {
        double m_per_px = fmax(zspan / (plot->w - 1), yspan / (plot->h - 1));
        int w = (int)lround(zspan / m_per_px) + 1, h = (int)lround(yspan / m_per_px) + 1;
        if (w < plot->w)
            plot->x += (plot->w - w) / 2; /* centred: the spare width either side */
        plot->w = w < plot->w ? w : plot->w;
        plot->h = h < plot->h ? h : plot->h;
        *colorbar_x = plot->x + plot->w + 22;
    }
}

int uwb_render_migrated_png(const char *path, const struct uwb_image *intensity, const struct uwb_verdict *v,
                            char *err, size_t errlen)
{
    return uwb_render_migrated_png_opt(path, intensity, v, NULL, err, errlen);
}

int uwb_render_migrated_png_opt(const char *path, const struct uwb_image *intensity,
                                const struct uwb_verdict *v, const struct uwb_render_options *opt, char *err,
                                size_t errlen)
{
    if (!path || !*path) {
        snprintf(err, errlen, "migrated image: no output path");
        return -1;
    }
    if (uwb_image_check(intensity, path, err, errlen) != 0)
        return -1;
    struct uwb_render_options o;
    uwb_render_options_sane(opt, &o);
    int s = o.font_scale;

    struct uwb_canvas c;
    if (uwb_canvas_init(&c, o.width, o.height, page, err, errlen) != 0)
        return -1;
    struct uwb_plot plot;
    int bar_x, bar_w;
    uwb_render_migrated_layout(intensity, v, &o, &plot, &bar_x, &bar_w);

    char title[160];
    snprintf(title, sizeof title, "uwbd migrated image - envelope, dB re its peak");
    uwb_draw_caption(&c, title, v, o.provenance, s);

    double peak = uwb_image_peak(intensity);
    uwb_paint_image_db(&c, &plot, intensity, peak, o.floor_db);
    if (!(peak > 0))
        uwb_draw_text(&c, plot.x + 10, plot.y + 10, "image is empty (all zero)", s, UWB_RGB_CURRENT_EDGE);
    uwb_mark_antenna_travel(&c, &plot, o.provenance, s > 1 ? s - 1 : 1);

    if (v) {
        uwb_mark_strong_returns(&c, &plot, intensity, &v->current, s > 1 ? s - 1 : 1);
        uwb_mark_reflector_band(&c, &plot, intensity, &v->current, s > 1 ? s - 1 : 1);
    }
    double half = FACE_REGION_FRACTION * (plot.x_max - plot.x_min);
    if (v && v->has_baseline && v->baseline.found)
        uwb_draw_edges(&c, &plot, &v->baseline, UWB_EDGE_BASELINE, v->baseline.face_z_m - half,
                       v->baseline.face_z_m + half, v->baseline.face_z_m, -1, s);
    if (v && v->current.found)
        uwb_draw_edges(&c, &plot, &v->current, UWB_EDGE_CURRENT, v->current.face_z_m - half,
                       v->current.face_z_m + half, v->current.face_z_m, 1, s);

    /* As many range ticks as the (to-scale, maybe narrow) plot has room for. */
    int x_ticks = plot.w / (4 * UWB_FONT_ADVANCE * s);
    struct uwb_axis_style axes = {.x_label_scale = 1000.0,
                                  .y_label_scale = 1000.0,
                                  .font_scale = s,
                                  .x_ticks = x_ticks < 2   ? 2
                                             : x_ticks > 7 ? 7
                                                           : x_ticks,
                                  .y_ticks = 10,
                                  .x_labels = 1,
                                  .y_labels_left = 1,
                                  .x_title = "range z (mm), to scale with height",
                                  .y_title = "height y (mm)"};
    uwb_draw_axes(&c, &plot, &axes);
    uwb_draw_db_colorbar(&c, bar_x, plot.y, bar_w, plot.h, o.floor_db, s);
    uwb_draw_edge_legend(&c, 12, uwb_layout_legend_y(&plot, s), v && v->current.found,
                         v && v->has_baseline && v->baseline.found, s);

    return uwb_canvas_save_with_verdict(&c, path, "uwbd migrated image", v, o.provenance, err, errlen);
}
