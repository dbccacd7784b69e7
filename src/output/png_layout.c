/* Page layout shared by the single-plot images (migrated image, B-scan):
 * caption on top, y axis labels and title left, colour bar right, x axis
 * labels, title and legend below. Margins follow the font scale. */
#include "output/render_internal.h"

void uwb_layout_single_plot(int width, int height, int s, int caption_height, struct uwb_plot *plot,
                            int *colorbar_x, int *colorbar_w)
{
    int cap_gap = 16 + UWB_FONT_LINE_HEIGHT * s;                      /* room for the colour bar's title */
    int left = 12 + 9 * s + 10 + (5 * UWB_FONT_ADVANCE - 1) * s + 12; /* title, "-1000", tick */
    int bar_w = 10 + 6 * s;
    int right = 22 + bar_w + 12 + (5 * UWB_FONT_ADVANCE - 1) * s + 10; /* gap, bar, tick, "-100" */
    int bottom = 12 + UWB_FONT_CAP_HEIGHT * s + 10 + 9 * s + 14 + UWB_FONT_LINE_HEIGHT * s + 10;
    plot->x = left;
    plot->y = caption_height + cap_gap;
    plot->w = width - left - right;
    plot->h = height - plot->y - bottom;
    if (plot->w < 16)
        plot->w = 16;
    if (plot->h < 16)
        plot->h = 16;
    *colorbar_x = plot->x + plot->w + 22;
    *colorbar_w = bar_w;
}

/* y of the legend line under a single plot. */
int uwb_layout_legend_y(const struct uwb_plot *plot, int s)
{
    return plot->y + plot->h + 12 + UWB_FONT_CAP_HEIGHT * s + 10 + 9 * s + 14;
}
