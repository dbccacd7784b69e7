/* Line editing for the serial console (see console_line.h). */
#include "control/console_line.h"

#include <string.h>

enum {
    KEY_CTRL_C = 0x03,
    KEY_BACKSPACE = 0x08,
    KEY_TAB = 0x09,
    KEY_CTRL_U = 0x15,
    KEY_ESC = 0x1b,
    KEY_DEL = 0x7f
};

static void echo(struct uwbd_console_line *cl, const char *bytes, size_t n)
{
    if (cl->echo_len + n <= sizeof cl->echo) {
        memcpy(cl->echo + cl->echo_len, bytes, n);
        cl->echo_len += n;
    }
}

static void rub_out(struct uwbd_console_line *cl, size_t count)
{
    for (size_t i = 0; i < count; i++)
        echo(cl, "\b \b", 3);
}

/* Escape sequences (cursor keys send ESC [ A, ESC O A): skipped whole, so
 * their letters do not land in the command. Returns 1 when c was part of one. */
static int in_escape(struct uwbd_console_line *cl, unsigned char c)
{
    if (c == KEY_ESC) {
        cl->escape = 1;
        return 1;
    }
    if (cl->escape == 1) {
        cl->escape = (c == '[' || c == 'O') ? 2 : 0;
        return 1;
    }
    if (cl->escape == 2) {
        if (c >= 0x40 && c <= 0x7e)
            cl->escape = 0; /* the final byte */
        return 1;
    }
    return 0;
}

int uwbd_console_line_feed(struct uwbd_console_line *cl, const char *data, size_t n, size_t *used,
                           const char **line, size_t *len)
{
    while (*used < n) {
        unsigned char c = (unsigned char)data[(*used)++];
        int after_cr = cl->after_cr;
        cl->after_cr = 0;
        if (c == '\n' && after_cr)
            continue; /* the LF of a CRLF */
        if (c == '\r' || c == '\n') {
            cl->escape = 0;
            cl->after_cr = c == '\r';
            echo(cl, "\r\n", 2);
            int was_long = cl->overlong;
            size_t got = cl->len;
            cl->len = 0;
            cl->overlong = 0;
            if (was_long)
                return UWBD_LINE_TOO_LONG;
            cl->text[got] = '\0';
            *line = cl->text;
            *len = got;
            return UWBD_LINE_READY;
        }
        if (in_escape(cl, c))
            continue;
        if (c == KEY_BACKSPACE || c == KEY_DEL) {
            if (cl->len > 0 && !cl->overlong) {
                cl->len--;
                rub_out(cl, 1);
            }
            continue;
        }
        if (c == KEY_CTRL_U) {
            rub_out(cl, cl->overlong ? 0 : cl->len);
            cl->len = 0;
            cl->overlong = 0;
            continue;
        }
        if (c == KEY_CTRL_C) {
            cl->len = 0;
            cl->overlong = 0;
            echo(cl, "^C\r\n" UWBD_CONSOLE_PROMPT, 4 + strlen(UWBD_CONSOLE_PROMPT));
            continue;
        }
        if (c == KEY_TAB)
            c = ' ';
        else if (c < 0x20)
            continue; /* other control keys do nothing */
        if (cl->overlong)
            continue;
        if (cl->len >= UWB_COMMAND_MAX_LINE) {
            cl->overlong = 1;
            echo(cl, "\a", 1); /* the terminal's bell: no more fits */
            continue;
        }
        cl->text[cl->len++] = (char)c;
        echo(cl, (const char *)&c, 1);
    }
    return UWBD_LINE_NONE;
}
