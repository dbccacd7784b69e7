/* What the text replies share (src/text/): the marks of the output's
 * charset, columns padded by characters, and reasons wrapped by words
 * (issue 48: a table never cuts a word). */
#ifndef UWB_TEXT_LAYOUT_H
#define UWB_TEXT_LAYOUT_H

#include <stdio.h>

#include "uwb/reply_text.h"

/* The two non-ASCII marks the text uses, or their ASCII spelling. */
struct text_marks {
    const char *plus_minus; /* "±" or "+/-" */
    const char *one_sigma;  /* "1σ" or "1 sigma" */
};

const struct text_marks *uwb_text_layout_marks_of(enum uwbd_charset charset);

/* The width of s on a terminal: its characters, not its bytes. */
int uwb_text_layout_width(const char *s);
/* width, or s's width where s is wider (a column fits its heading). */
int uwb_text_layout_at_least(int width, const char *s);

/* s, then spaces up to `width` columns (none when s is as wide or wider:
 * never cut). */
void uwb_text_layout_column(FILE *out, const char *s, int width);

/* s's words from column `at` (where the caller has got to), lines
 * broken before a word that would pass `line_width`, each new line
 * indented by `indent` spaces; a word wider than a line is kept whole.
 * Ends with a newline. */
void uwb_text_layout_wrapped(FILE *out, const char *s, int at, int indent, int line_width);

#endif
