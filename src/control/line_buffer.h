/* Bytes from a socket or a serial line, cut into command lines of bounded
 * length. A line that grows past the bound is dropped whole (reported once,
 * at its newline) rather than cut into pieces that might parse. */
#ifndef UWB_CONTROL_LINE_BUFFER_H
#define UWB_CONTROL_LINE_BUFFER_H

#include <stddef.h>

#include "control/command.h"

struct uwbd_line_buffer {
    char text[UWB_COMMAND_MAX_LINE + 2]; /* room for "\r" and the NUL */
    size_t len;
    int overlong; /* the current line passed the bound */
};

enum uwbd_line_event {
    UWBD_LINE_NONE,     /* no complete line yet */
    UWBD_LINE_READY,    /* *line / *len hold a line, without its newline */
    UWBD_LINE_TOO_LONG, /* a line longer than the bound ended and was dropped */
};

/* Feed bytes from data[*used ..n); stops after each event, advancing *used,
 * so call it again until it returns UWBD_LINE_NONE. */
int uwbd_line_buffer_feed(struct uwbd_line_buffer *lb, const char *data, size_t n, size_t *used,
                          const char **line, size_t *len);

#endif
