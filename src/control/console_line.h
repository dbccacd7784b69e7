/* The serial console's line editing, as a terminal program (minicom,
 * picocom, screen) sends keys: CR, LF or CRLF end a line; backspace (0x08)
 * and DEL (0x7f) take back the last character, Ctrl-U the whole line,
 * Ctrl-C drops it; cursor-key escape sequences are ignored. What the person
 * should see (the echo) is collected for the caller to send. The control
 * socket does not use this: it stays machine-clean (src/control/line_buffer.c). */
#ifndef UWB_CONTROL_CONSOLE_LINE_H
#define UWB_CONTROL_CONSOLE_LINE_H

#include <stddef.h>

#include "control/command.h"
#include "control/line_buffer.h" /* enum uwbd_line_event */

/* Shown on the console when it is ready for a command line. */
#define UWBD_CONSOLE_PROMPT "uwbd> "
/* Echo for one fed chunk: at most 3 bytes a key ("\b \b"), with room for a
 * line end and the prompt after Ctrl-C. */
#define UWBD_CONSOLE_CHUNK 512
#define UWBD_CONSOLE_ECHO_MAX (3 * UWBD_CONSOLE_CHUNK + 16)

struct uwbd_console_line {
    char text[UWB_COMMAND_MAX_LINE + 1];
    size_t len;
    int overlong; /* more was typed than a command may hold */
    int after_cr; /* the line just ended with CR: an LF now is its CRLF */
    int escape;   /* 0, 1 after ESC, 2 inside a CSI/SS3 sequence */
    char echo[UWBD_CONSOLE_ECHO_MAX];
    size_t echo_len; /* echo bytes waiting; the caller sends and clears them */
};

/* Feed bytes from data[*used ..n) (at most UWBD_CONSOLE_CHUNK between
 * clearing the echo); stops after each event, advancing *used, so call it
 * again until it returns UWBD_LINE_NONE. *line / *len: the line without
 * its end, NUL-terminated. */
int uwbd_console_line_feed(struct uwbd_console_line *cl, const char *data, size_t n, size_t *used,
                           const char **line, size_t *len);

#endif
