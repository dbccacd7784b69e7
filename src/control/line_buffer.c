/* Cutting a byte stream into bounded command lines. */
#include "control/line_buffer.h"

int uwbd_line_buffer_feed(struct uwbd_line_buffer *lb, const char *data, size_t n, size_t *used,
                          const char **line, size_t *len)
{
    while (*used < n) {
        char c = data[(*used)++];
        if (c == '\n') {
            int was_long = lb->overlong;
            size_t got = lb->len;
            lb->len = 0;
            lb->overlong = 0;
            if (was_long)
                return UWBD_LINE_TOO_LONG;
            lb->text[got] = '\0';
            *line = lb->text;
            *len = got;
            return UWBD_LINE_READY;
        }
        if (lb->overlong)
            continue;
        /* One byte more than the bound still fits: a "\r" before the "\n". */
        if (lb->len >= UWB_COMMAND_MAX_LINE + 1) {
            lb->overlong = 1;
            lb->len = 0;
            continue;
        }
        lb->text[lb->len++] = c;
    }
    return UWBD_LINE_NONE;
}
