/* An RGB raster and the few shapes the images need: rectangles and
 * (optionally dashed, thick) lines. Everything clips to the canvas so
 * callers can draw overlays without bounds arithmetic. */
#include "output/render_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int uwb_canvas_init(struct uwb_canvas *c, int width, int height, struct uwb_rgb background, char *err,
                    size_t errlen)
{
    memset(c, 0, sizeof *c);
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        snprintf(err, errlen, "canvas: size %dx%d out of range", width, height);
        return -1;
    }
    c->rgb = malloc((size_t)width * (size_t)height * 3);
    if (!c->rgb) {
        snprintf(err, errlen, "canvas: out of memory for %dx%d", width, height);
        return -1;
    }
    c->width = width;
    c->height = height;
    uwb_canvas_fill_rect(c, 0, 0, width, height, background);
    return 0;
}

void uwb_canvas_free(struct uwb_canvas *c)
{
    free(c->rgb);
    memset(c, 0, sizeof *c);
}

void uwb_canvas_put(struct uwb_canvas *c, int x, int y, struct uwb_rgb colour)
{
    if (x < 0 || y < 0 || x >= c->width || y >= c->height)
        return;
    unsigned char *p = c->rgb + ((size_t)y * (size_t)c->width + (size_t)x) * 3;
    p[0] = colour.r;
    p[1] = colour.g;
    p[2] = colour.b;
}

struct uwb_rgb uwb_canvas_get(const struct uwb_canvas *c, int x, int y)
{
    struct uwb_rgb out = {0, 0, 0};
    if (x < 0 || y < 0 || x >= c->width || y >= c->height)
        return out;
    const unsigned char *p = c->rgb + ((size_t)y * (size_t)c->width + (size_t)x) * 3;
    out.r = p[0];
    out.g = p[1];
    out.b = p[2];
    return out;
}

void uwb_canvas_fill_rect(struct uwb_canvas *c, int x, int y, int w, int h, struct uwb_rgb colour)
{
    int x0 = x < 0 ? 0 : x, y0 = y < 0 ? 0 : y;
    int x1 = x + w > c->width ? c->width : x + w;
    int y1 = y + h > c->height ? c->height : y + h;
    if (x0 >= x1 || y0 >= y1)
        return;
    /* One row pixel by pixel, the others copied from it: whole canvases
     * are filled several times a PNG. */
    size_t stride = (size_t)c->width * 3, row_bytes = (size_t)(x1 - x0) * 3;
    unsigned char *first = c->rgb + (size_t)y0 * stride + (size_t)x0 * 3;
    for (int xx = x0; xx < x1; xx++)
        uwb_canvas_put(c, xx, y0, colour);
    for (int yy = y0 + 1; yy < y1; yy++)
        memcpy(first + (size_t)(yy - y0) * stride, first, row_bytes);
}

void uwb_canvas_frame_rect(struct uwb_canvas *c, int x, int y, int w, int h, struct uwb_rgb colour)
{
    if (w <= 0 || h <= 0)
        return;
    uwb_canvas_fill_rect(c, x, y, w, 1, colour);
    uwb_canvas_fill_rect(c, x, y + h - 1, w, 1, colour);
    uwb_canvas_fill_rect(c, x, y, 1, h, colour);
    uwb_canvas_fill_rect(c, x + w - 1, y, 1, h, colour);
}

static int clamp_coord(int v, int size)
{
    if (v < -size)
        return -size;
    if (v > 2 * size)
        return 2 * size;
    return v;
}

/* Bresenham; the dash phase advances one per step (so dashes keep their
 * length along horizontal and vertical lines) and carries over from one
 * segment to the next of a polyline. */
static void line_phase(struct uwb_canvas *c, int x0, int y0, int x1, int y1, struct uwb_rgb colour,
                       int thickness, int dash_on, int dash_off, long *phase)
{
    if (thickness < 1)
        thickness = 1;
    /* Callers map data to pixels; keep a wild coordinate from costing a
     * billion steps. Exact for the horizontal and vertical lines that can
     * run off the canvas. */
    x0 = clamp_coord(x0, c->width);
    x1 = clamp_coord(x1, c->width);
    y0 = clamp_coord(y0, c->height);
    y1 = clamp_coord(y1, c->height);
    int lo = -(thickness - 1) / 2, hi = thickness / 2;
    int dx = abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    int dy = -abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int e = dx + dy;
    int period = dash_off > 0 && dash_on > 0 ? dash_on + dash_off : 0;
    for (;;) {
        if (!period || *phase % period < dash_on)
            for (int oy = lo; oy <= hi; oy++)
                for (int ox = lo; ox <= hi; ox++)
                    uwb_canvas_put(c, x0 + ox, y0 + oy, colour);
        if (x0 == x1 && y0 == y1)
            break;
        (*phase)++;
        int e2 = 2 * e;
        if (e2 >= dy) {
            e += dy;
            x0 += sx;
        }
        if (e2 <= dx) {
            e += dx;
            y0 += sy;
        }
    }
}

void uwb_canvas_line(struct uwb_canvas *c, int x0, int y0, int x1, int y1, struct uwb_rgb colour,
                     int thickness, int dash_on, int dash_off)
{
    long phase = 0;
    line_phase(c, x0, y0, x1, y1, colour, thickness, dash_on, dash_off, &phase);
}

void uwb_canvas_polyline(struct uwb_canvas *c, const int *xs, const int *ys, int n, struct uwb_rgb colour,
                         int thickness, int dash_on, int dash_off)
{
    long phase = 0;
    if (n == 1)
        line_phase(c, xs[0], ys[0], xs[0], ys[0], colour, thickness, dash_on, dash_off, &phase);
    for (int i = 0; i + 1 < n; i++)
        line_phase(c, xs[i], ys[i], xs[i + 1], ys[i + 1], colour, thickness, dash_on, dash_off, &phase);
}
