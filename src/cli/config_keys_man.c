/* uwbd --config-keys=man: the uwbd.json(5) manual page, made from the same
 * key table as the Markdown one (uwbd_config_print_keys_markdown), so the
 * page cannot drift from what the loader accepts. */
#define _GNU_SOURCE /* open_memstream */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/cli.h"
#include "daemon/daemon.h"

/* Text for roff: backslashes escaped, `code` in bold, a leading '.' or '\''
 * kept from being read as a request. */
static void put_roff_text(FILE *out, const char *text, size_t n)
{
    int bold = 0;
    if (n > 0 && (text[0] == '.' || text[0] == '\''))
        fputs("\\&", out);
    for (size_t i = 0; i < n; i++) {
        char c = text[i];
        if (c == '`') {
            fputs(bold ? "\\fR" : "\\fB", out);
            bold = !bold;
        } else if (c == '\\') {
            fputs("\\e", out);
        } else if (c == '-') {
            fputs("\\-", out);
        } else {
            fputc(c, out);
        }
    }
    if (bold)
        fputs("\\fR", out);
}

static void put_cell(FILE *out, const char *cell)
{
    put_roff_text(out, cell, strlen(cell));
}

/* One Markdown table row "| a | b | ... | meaning |" cut into its 6 cells (in place). */
static int split_row(char *row, char *cells[6])
{
    if (strncmp(row, "| ", 2) != 0)
        return -1;
    char *p = row + 2;
    for (int i = 0; i < 5; i++) {
        char *bar = strstr(p, " | ");
        if (!bar)
            return -1;
        *bar = '\0';
        cells[i] = p;
        p = bar + 3;
    }
    size_t n = strlen(p);
    if (n >= 2 && strcmp(p + n - 2, " |") == 0)
        p[n - 2] = '\0';
    cells[5] = p;
    return 0;
}

static const char header[] =
    ".TH UWBD.JSON 5 \"\" \"uwbd " UWBD_VERSION "\" \"File Formats\"\n"
    ".SH NAME\n"
    "uwbd.json \\- configuration of uwbd, the winding\\-displacement appliance\n"
    ".SH SYNOPSIS\n"
    ".B /etc/uwbd/uwbd.json\n"
    ".SH DESCRIPTION\n"
    "One JSON object; nested objects group the keys, which are written below\n"
    "with dots (\\fBgpio.backend\\fR is the key \\fBbackend\\fR of the object\n"
    "\\fBgpio\\fR). An unknown key, a value of the wrong type or out of its range,\n"
    "and a missing required key are refused by name:\n"
    ".B uwbd \\-\\-check\\-config\n"
    "FILE validates a file and exits 0, or 78 with \"FILE: key \\(gax.y\\(ga: problem\".\n"
    "A key given with \\fB\\-\\-set\\fR KEY=VALUE on the command line overrides the file.\n"
    "The daemon re\\-reads the file on SIGHUP, between scans.\n"
    ".SH KEYS\n"
    "Each key with its type, unit, range and default; \\fBrequired\\fR keys have no default.\n";

static const char footer[] = ".SH FILES\n"
                             ".TP\n"
                             ".I /etc/uwbd/uwbd.json\n"
                             "the configuration the systemd unit starts uwbd with\n"
                             ".SH SEE ALSO\n"
                             ".BR uwbd (8),\n"
                             ".BR uwbd\\-ctl (1);\n"
                             "the installed config.md and install\\-guide.md under /usr/share/doc/uwbd\n";

int uwbd_config_print_keys_man(FILE *out)
{
    char *markdown = NULL;
    size_t size = 0;
    FILE *mem = open_memstream(&markdown, &size);
    if (!mem)
        return -1;
    uwbd_config_print_keys_markdown(mem);
    if (fclose(mem) != 0) {
        free(markdown);
        return -1;
    }
    fputs(header, out);
    int rows = 0, rc = 0;
    for (char *line = strtok(markdown, "\n"); line; line = strtok(NULL, "\n")) {
        char *cells[6];
        if (strncmp(line, "|---", 4) == 0)
            continue; /* the table's rule */
        if (split_row(line, cells) != 0) {
            rc = -1;
            break;
        }
        if (strcmp(cells[0], "key") == 0)
            continue; /* the table's head */
        /* key, then "type, unit, range, default: ..." on the tag line, then the meaning */
        fputs(".TP\n", out);
        put_cell(out, cells[0]);
        fputs("\n", out);
        put_cell(out, cells[1]);
        if (cells[2][0]) {
            fputs(" in ", out);
            put_cell(out, cells[2]);
        }
        if (cells[3][0]) {
            fputs(", ", out);
            put_cell(out, cells[3]);
        }
        if (strcmp(cells[4], "required") == 0)
            fputs("; required", out);
        else if (cells[4][0]) {
            fputs("; default ", out);
            put_cell(out, cells[4]);
        }
        fputs(".\n.br\n", out);
        put_cell(out, cells[5]);
        fputs("\n", out);
        rows++;
    }
    free(markdown);
    fputs(footer, out);
    return rc == 0 && rows > 0 ? 0 : -1;
}
