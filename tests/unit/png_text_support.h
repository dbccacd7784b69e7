/* Reading words back out of a rendered image: the images draw their text
 * with one bitmap font (src/output/png_font.c), so a word is on the page
 * exactly when every pixel the font inks for it is in the word's colour.
 * A caption cut at the panel's edge ("ew baselin") does not match. */
#ifndef UWB_PNG_TEXT_SUPPORT_H
#define UWB_PNG_TEXT_SUPPORT_H

#include "output/render_internal.h"

/* Where `text`, drawn by uwb_draw_text at `scale` in `colour`, is found
 * whole in the w x h RGB raster: every inked pixel in colour, every
 * blank pixel of its cap-height box in another colour. Returns how many
 * places match; the first's top-left goes to *x, *y (may be NULL). */
int png_text_find(const unsigned char *rgb, int w, int h, const char *text, int scale, struct uwb_rgb colour,
                  int *x, int *y);
/* Likewise in any of the font's scales 1..3 and in any colour: the first
 * inked pixel's colour is taken as the text's. 1 if found. */
int png_text_present(const unsigned char *rgb, int w, int h, const char *text);

#endif
