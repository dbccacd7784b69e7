/* See png_text_support.h. */
#include "png_text_support.h"

#include <stdlib.h>
#include <string.h>

struct text_mask {
    int w, h;
    unsigned char *ink; /* w * h, 1 where the font inks */
};

static int mask_of(const char *text, int scale, struct text_mask *m)
{
    const struct uwb_rgb blank = {0, 0, 0}, mark = {255, 255, 255};
    struct uwb_canvas c;
    char err[128];
    m->w = uwb_text_width(text, scale);
    m->h = (UWB_FONT_CAP_HEIGHT + 2) * scale;
    if (m->w <= 0 || uwb_canvas_init(&c, m->w, m->h, blank, err, sizeof err) != 0)
        return -1;
    uwb_draw_text(&c, 0, 0, text, scale, mark);
    m->ink = malloc((size_t)m->w * (size_t)m->h);
    if (!m->ink) {
        uwb_canvas_free(&c);
        return -1;
    }
    for (int y = 0; y < m->h; y++)
        for (int x = 0; x < m->w; x++)
            m->ink[y * m->w + x] = uwb_canvas_get(&c, x, y).r == 255;
    uwb_canvas_free(&c);
    return 0;
}

static int is_colour(const unsigned char *rgb, int w, int x, int y, struct uwb_rgb c)
{
    const unsigned char *p = rgb + ((size_t)y * (size_t)w + (size_t)x) * 3;
    return p[0] == c.r && p[1] == c.g && p[2] == c.b;
}

static int matches_at(const unsigned char *rgb, int w, const struct text_mask *m, int x0, int y0,
                      struct uwb_rgb colour, int cap_rows)
{
    for (int y = 0; y < m->h; y++)
        for (int x = 0; x < m->w; x++) {
            int ink = m->ink[y * m->w + x];
            if (ink != is_colour(rgb, w, x0 + x, y0 + y, colour) && (ink || y < cap_rows))
                return 0;
        }
    return 1;
}

static int first_ink(const struct text_mask *m, int *fx, int *fy)
{
    for (int y = 0; y < m->h; y++)
        for (int x = 0; x < m->w; x++)
            if (m->ink[y * m->w + x]) {
                *fx = x;
                *fy = y;
                return 1;
            }
    return 0;
}

static int find(const unsigned char *rgb, int w, int h, const struct text_mask *m, int scale, int any_colour,
                struct uwb_rgb colour, int *x, int *y)
{
    int fx, fy, found = 0;
    if (!first_ink(m, &fx, &fy))
        return 0;
    for (int y0 = 0; y0 + m->h <= h; y0++)
        for (int x0 = 0; x0 + m->w <= w; x0++) {
            struct uwb_rgb c = colour;
            if (any_colour) {
                const unsigned char *p = rgb + ((size_t)(y0 + fy) * (size_t)w + (size_t)(x0 + fx)) * 3;
                c = (struct uwb_rgb){p[0], p[1], p[2]};
            } else if (!is_colour(rgb, w, x0 + fx, y0 + fy, c)) {
                continue;
            }
            if (!matches_at(rgb, w, m, x0, y0, c, UWB_FONT_CAP_HEIGHT * scale))
                continue;
            if (!found && x && y) {
                *x = x0;
                *y = y0;
            }
            found++;
            if (any_colour)
                return found;
        }
    return found;
}

int png_text_find(const unsigned char *rgb, int w, int h, const char *text, int scale, struct uwb_rgb colour,
                  int *x, int *y)
{
    struct text_mask m;
    if (mask_of(text, scale, &m) != 0)
        return 0;
    int n = find(rgb, w, h, &m, scale, 0, colour, x, y);
    free(m.ink);
    return n;
}

int png_text_present(const unsigned char *rgb, int w, int h, const char *text)
{
    for (int scale = 1; scale <= 3; scale++) {
        struct text_mask m;
        if (mask_of(text, scale, &m) != 0)
            return 0;
        int n = find(rgb, w, h, &m, scale, 1, (struct uwb_rgb){0, 0, 0}, NULL, NULL);
        free(m.ink);
        if (n)
            return 1;
    }
    return 0;
}
