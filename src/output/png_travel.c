/* The antenna's travel on the images whose height axis reaches beyond it:
 * migration images a little above and below the travel (oblique paths),
 * where edges are read from fewer, steeper paths. Rows outside the travel
 * are hatched and the travel's ends dashed, so nobody takes a height
 * there at face value. */
#include "output/render_internal.h"

#include <stdio.h>

static const struct uwb_rgb hatch = {215, 215, 215};
static const struct uwb_rgb ink = {25, 25, 25};

#define HATCH_PERIOD 8

void uwb_mark_antenna_travel(struct uwb_canvas *c, const struct uwb_plot *p,
                             const struct uwb_provenance *prov, int label_scale)
{
    if (!prov || !prov->has_travel || !(prov->travel_hi_m > prov->travel_lo_m))
        return;
    int top = uwb_plot_row(p, prov->travel_hi_m), bottom = uwb_plot_row(p, prov->travel_lo_m);
    for (int row = p->y; row < p->y + p->h; row++) {
        if (row >= top && row <= bottom)
            continue;
        for (int x = p->x + ((row + HATCH_PERIOD * 1000) % HATCH_PERIOD); x < p->x + p->w; x += HATCH_PERIOD)
            uwb_canvas_put(c, x, row, hatch);
    }
    for (int k = 0; k < 2; k++) {
        int row = k ? bottom : top;
        if (row > p->y && row < p->y + p->h - 1)
            uwb_canvas_line(c, p->x, row, p->x + p->w - 1, row, hatch, 1, 4, 4);
    }
    if (label_scale < 1)
        return;
    /* Say what the hatching means where there is room for it. */
    const char *label = "beyond antenna travel";
    int w = uwb_text_width(label, label_scale), h = UWB_FONT_CAP_HEIGHT * label_scale;
    if (w + 8 > p->w)
        return;
    int x = p->x + p->w - w - 4;
    if (top - p->y >= h + 8) {
        uwb_canvas_fill_rect(c, x - 2, top - h - 6, w + 4, h + 4, hatch);
        uwb_draw_text(c, x, top - h - 4, label, label_scale, ink);
    } else if (p->y + p->h - 1 - bottom >= h + 8) {
        uwb_canvas_fill_rect(c, x - 2, bottom + 2, w + 4, h + 4, hatch);
        uwb_draw_text(c, x, bottom + 4, label, label_scale, ink);
    }
}
