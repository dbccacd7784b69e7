/* Defaults for the images: a size that reads on a laptop screen and
 * prints on A4, the dB floors an engineer expects. */
#include "output/render_internal.h"

void uwb_render_options_default(struct uwb_render_options *opt)
{
    opt->width = 960;
    opt->height = 820;
    opt->floor_db = -30.0;
    opt->bscan_floor_db = -40.0;
    opt->font_scale = 2;
}

/* Options as given, with nonsense replaced by the defaults, so a bad
 * configuration value still yields a readable image. */
void uwb_render_options_sane(const struct uwb_render_options *in, struct uwb_render_options *out)
{
    uwb_render_options_default(out);
    if (!in)
        return;
    if (in->width >= 320 && in->width <= 8192)
        out->width = in->width;
    if (in->height >= 320 && in->height <= 8192)
        out->height = in->height;
    if (in->floor_db < -1.0 && in->floor_db >= -200.0)
        out->floor_db = in->floor_db;
    if (in->bscan_floor_db < -1.0 && in->bscan_floor_db >= -200.0)
        out->bscan_floor_db = in->bscan_floor_db;
    if (in->font_scale >= 1 && in->font_scale <= 4)
        out->font_scale = in->font_scale;
}
