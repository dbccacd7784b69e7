/* One line for a command-line option getopt_long refused (opterr = 0): the
 * option, what is wrong with it, a likely meant option, and "see --help";
 * or for words left over, the `uwbd ctl` command they look like. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "uwb/cli.h"
#include "control/command.h"
#include "util/edit_distance.h"

/* The long option closest to `name` (uwb_nearest's rules), or NULL. */
static const char *closest_option(const char *name, size_t n, const struct option *longopts)
{
    struct uwb_nearest near;
    uwb_nearest_start(&near, name, n);
    for (const struct option *o = longopts; o->name; o++)
        uwb_nearest_offer(&near, o->name, strlen(o->name));
    return near.best;
}

static const struct option *option_with_val(const struct option *longopts, int val)
{
    for (const struct option *o = longopts; o->name; o++)
        if (o->val == val && !o->flag)
            return o;
    return NULL;
}

void uwb_cli_option_error(const char *prog, const char *help, char *const argv[], int argc,
                          const struct option *longopts)
{
    const char *arg = optind >= 1 && optind <= argc ? argv[optind - 1] : "";
    if (optopt != 0) {
        const struct option *o = option_with_val(longopts, optopt);
        if (o && strncmp(arg, "--", 2) == 0)
            fprintf(stderr, "%s: option '--%s' %s; see %s\n", prog, o->name,
                    o->has_arg == no_argument ? "takes no value" : "needs a value", help);
        else if (o)
            fprintf(stderr, "%s: option '-%c' needs a value; see %s\n", prog, optopt, help);
        else
            fprintf(stderr, "%s: unknown option '-%c'; see %s\n", prog, optopt, help);
        return;
    }
    if (strncmp(arg, "--", 2) != 0) {
        fprintf(stderr, "%s: unknown option '%s'; see %s\n", prog, arg, help);
        return;
    }
    const char *name = arg + 2;
    size_t n = strcspn(name, "=");
    int prefixed = 0;
    for (const struct option *o = longopts; o->name; o++)
        prefixed += strncmp(o->name, name, n) == 0;
    if (prefixed > 1) {
        fprintf(stderr, "%s: option '--%.*s' is ambiguous (%d options start so); see %s\n", prog, (int)n,
                name, prefixed, help);
        return;
    }
    const char *meant = closest_option(name, n, longopts);
    if (meant)
        fprintf(stderr, "%s: unknown option '--%.*s' (did you mean --%s?); see %s\n", prog, (int)n, name,
                meant, help);
    else
        fprintf(stderr, "%s: unknown option '--%.*s'; see %s\n", prog, (int)n, name, help);
}

void uwb_cli_unexpected_argument(const char *prog, char *const argv[], int first, int argc)
{
    char line[UWB_COMMAND_MAX_LINE + 1], err[256];
    size_t len = 0;
    int fits = 1;
    for (int i = first; i < argc && fits; i++) {
        size_t n = strlen(argv[i]);
        fits = len + n + 1 < sizeof line;
        if (fits) {
            if (len)
                line[len++] = ' ';
            memcpy(line + len, argv[i], n);
            len += n;
        }
    }
    line[len] = '\0';
    struct uwb_command cmd;
    const char *word = argv[first];
    size_t n = strlen(word);
    if (fits && uwb_command_parse(line, len, &cmd, err, sizeof err) == UWB_COMMAND_OK) {
        fprintf(stderr, "%s: unexpected argument '%s' (did you mean `uwbd ctl %s`?)\n", prog, word, line);
        return;
    }
    static const char scan_suffix[] = ".uwbscan";
    if (n > sizeof scan_suffix - 1 && strcmp(word + n - (sizeof scan_suffix - 1), scan_suffix) == 0) {
        fprintf(stderr, "%s: unexpected argument '%s' (did you mean `uwbd --replay %s`?)\n", prog, word,
                word);
        return;
    }
    /* A command mistyped: the nearest command's first word. */
    struct uwb_nearest near;
    uwb_nearest_start(&near, word, n);
    for (size_t i = 0; i < uwb_command_help_count; i++)
        uwb_nearest_offer(&near, uwb_command_help[i].usage, strcspn(uwb_command_help[i].usage, " "));
    if (near.best)
        fprintf(stderr, "%s: unexpected argument '%s' (did you mean `uwbd ctl %.*s`?)\n", prog, word,
                (int)near.best_len, near.best);
    else
        fprintf(stderr, "%s: unexpected argument '%s'\n", prog, word);
}
