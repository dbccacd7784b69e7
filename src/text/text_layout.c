/* Columns and wrapping for the text replies (see text_layout.h). */
#include "text/text_layout.h"

#include <string.h>

static const struct text_marks utf8_marks = {"\u00b1", "1\u03c3"};
static const struct text_marks ascii_marks = {"+/-", "1 sigma"};

const struct text_marks *uwb_text_layout_marks_of(enum uwbd_charset charset)
{
    return charset == UWBD_CHARSET_ASCII ? &ascii_marks : &utf8_marks;
}

int uwb_text_layout_width(const char *s)
{
    int shown = 0;
    for (const unsigned char *c = (const unsigned char *)s; *c; c++)
        shown += (*c & 0xC0) != 0x80; /* UTF-8 continuation bytes take no column */
    return shown;
}

void uwb_text_layout_column(FILE *out, const char *s, int width)
{
    fputs(s, out);
    for (int shown = uwb_text_layout_width(s); shown < width; shown++)
        fputc(' ', out);
}

void uwb_text_layout_wrapped(FILE *out, const char *s, int at, int indent, int line_width)
{
    int column = at, words_on_line = 0;
    while (*s == ' ')
        s++;
    while (*s) {
        size_t n = strcspn(s, " ");
        char word[512];
        snprintf(word, sizeof word, "%.*s", (int)(n < sizeof word ? n : sizeof word - 1), s);
        int w = uwb_text_layout_width(word);
        int gap = words_on_line ? 1 : 0;
        if ((words_on_line || column > indent) && column + gap + w > line_width) {
            fprintf(out, "\n%*s", indent, "");
            column = indent;
            words_on_line = 0;
        } else if (words_on_line) {
            fputc(' ', out);
            column++;
        }
        fwrite(s, 1, n, out); /* the word whole, however long */
        column += w;
        words_on_line++;
        s += n;
        while (*s == ' ')
            s++;
    }
    fputc('\n', out);
}

int uwb_text_layout_at_least(int width, const char *s)
{
    int w = uwb_text_layout_width(s);
    return w > width ? w : width;
}
