/* Documentation printed from the parameter table: --help and the README list. */
#include "scene.h"

#include <string.h>

static void cli_spelling(const char *name, char *buf, size_t buflen)
{
    size_t i = 0;
    for (; name[i] && i + 1 < buflen; i++)
        buf[i] = name[i] == '_' ? '-' : name[i];
    buf[i] = '\0';
}

static const char *value_word(const struct sim_param *p)
{
    switch (p->type) {
    case SIM_PARAM_NUMBER: return "X";
    case SIM_PARAM_OPTNUMBER: return "X|none";
    case SIM_PARAM_INT: return "N";
    case SIM_PARAM_BOOL: return "BOOL";
    case SIM_PARAM_ENUM: return "NAME";
    case SIM_PARAM_STRING: return "TEXT";
    }
    return "?";
}

static void choices_text(const struct sim_param *p, char *buf, size_t buflen)
{
    buf[0] = '\0';
    if (p->type != SIM_PARAM_ENUM)
        return;
    for (int i = 0; p->choices[i]; i++) {
        strncat(buf, i ? "|" : "", buflen - strlen(buf) - 1);
        strncat(buf, p->choices[i], buflen - strlen(buf) - 1);
    }
}

/* Wrap help text at about 78 columns under an indent; `tail` (the unit and
 * default) is kept whole on one line so it can be found and read. */
static void print_wrapped(FILE *out, const char *text, const char *tail, int indent)
{
    int col = indent;
    fprintf(out, "%*s", indent, "");
    const char *w = text;
    while (*w) {
        const char *end = strchr(w, ' ');
        int len = end ? (int)(end - w) : (int)strlen(w);
        if (col > indent && col + 1 + len > 78) {
            fprintf(out, "\n%*s", indent, "");
            col = indent;
        } else if (col > indent) {
            fputc(' ', out);
            col++;
        }
        fwrite(w, 1, (size_t)len, out);
        col += len;
        w += len;
        while (*w == ' ')
            w++;
    }
    int tlen = (int)strlen(tail);
    if (col > indent && col + 1 + tlen > 78)
        fprintf(out, "\n%*s%s\n", indent, "", tail);
    else
        fprintf(out, "%s%s\n", col > indent ? " " : "", tail);
}

void sim_scene_print_help(FILE *out)
{
    size_t n;
    const struct sim_param *all = sim_params(&n);
    const char *group = "";
    for (size_t i = 0; i < n; i++) {
        const struct sim_param *p = &all[i];
        if (strcmp(group, p->group) != 0) {
            group = p->group;
            fprintf(out, "\n%s:\n", group);
        }
        char cli[128], choices[256], line[512];
        cli_spelling(p->name, cli, sizeof cli);
        choices_text(p, choices, sizeof choices);
        snprintf(line, sizeof line, "  --%s %s", cli, p->type == SIM_PARAM_ENUM ? choices : value_word(p));
        fprintf(out, "%s\n", line);
        char tail[256];
        snprintf(tail, sizeof tail, "[%s%sdefault %s]", p->unit[0] ? p->unit : "", p->unit[0] ? "; " : "",
                 p->def[0] ? p->def : "empty");
        print_wrapped(out, p->help, tail, 6);
    }
}

void sim_scene_print_markdown(FILE *out)
{
    size_t n;
    const struct sim_param *all = sim_params(&n);
    fprintf(out, "| JSON key / `--option` | unit | default | meaning |\n|---|---|---|---|\n");
    for (size_t i = 0; i < n; i++) {
        const struct sim_param *p = &all[i];
        char cli[128], choices[256];
        cli_spelling(p->name, cli, sizeof cli);
        choices_text(p, choices, sizeof choices);
        fprintf(out, "| `%s` / `--%s` | %s | %s | %s%s%s%s |\n", p->name, cli, p->unit,
                p->def[0] ? p->def : "(empty)", p->help, choices[0] ? " (" : "", choices,
                choices[0] ? ")" : "");
    }
}
