/* uwbd's command-line modes; src/main.c picks one.
 *   uwbd --replay FILE ...        evaluate a recorded scan (src/cli/replay_cli.c)
 *   uwbd --config FILE ...        run the appliance daemon (src/cli/daemon_cli.c)
 *   uwbd --check-config FILE ...  validate a config and exit
 *   uwbd ctl COMMAND ...          talk to a running daemon (src/cli/ctl_cli.c) */
#ifndef UWB_CLI_H
#define UWB_CLI_H

#include <stddef.h>
#include <stdio.h>

int uwbd_replay_main(int argc, char **argv);
int uwbd_daemon_main(int argc, char **argv);
int uwbd_ctl_main(int argc, char **argv);

/* Whether argv asks for the daemon (--config, --check-config, --config-keys). */
int uwbd_wants_daemon(int argc, char **argv);

/* The uwbd.json(5) manual page (roff) from the configuration key table: 0, or -1. */
int uwbd_config_print_keys_man(FILE *out);

void uwbd_replay_usage(FILE *f);
void uwbd_daemon_usage(FILE *f);
void uwbd_ctl_usage(FILE *f);

/* After getopt_long (with opterr = 0) returned '?': one line on stderr naming the
 * refused option and the problem, a close option name if there is one, and
 * "see HELP" (e.g. "uwbd --help"), instead of the whole usage. */
struct option;
void uwb_cli_option_error(const char *prog, const char *help, char *const argv[], int argc,
                          const struct option *longopts);

/* One line for words left after the options (argv[first..argc)): when they
 * are a command of the daemon, the `uwbd ctl` line that was meant. */
void uwb_cli_unexpected_argument(const char *prog, char *const argv[], int first, int argc);

/* A HISTORY reply as CSV (uwb/verdict_csv.h): the header, then a row per
 * verdict. 0, or -1 with err: not a HISTORY reply (nothing printed), a
 * verdict unreadable or a write failed (the rows before it printed). */
int uwbd_history_csv(const char *reply, FILE *out, char *err, size_t errlen);

#endif
