/* uwbd's command-line modes; src/main.c picks one.
 *   uwbd --replay FILE ...        evaluate a recorded scan (src/cli/replay_cli.c)
 *   uwbd --config FILE ...        run the appliance daemon (src/cli/daemon_cli.c)
 *   uwbd --check-config FILE ...  validate a config and exit
 *   uwbd ctl COMMAND ...          talk to a running daemon (src/cli/ctl_cli.c) */
#ifndef UWB_CLI_H
#define UWB_CLI_H

#include <stdio.h>

int uwbd_replay_main(int argc, char **argv);
int uwbd_daemon_main(int argc, char **argv);
int uwbd_ctl_main(int argc, char **argv);

/* Whether argv asks for the daemon (--config, --check-config, --config-keys). */
int uwbd_wants_daemon(int argc, char **argv);

void uwbd_replay_usage(FILE *f);
void uwbd_daemon_usage(FILE *f);
void uwbd_ctl_usage(FILE *f);

/* A VERDICT reply (one JSON line) as text for people: "status ALARM:
 * displacement +12.04 ± 0.23 mm (edges ...)", or the edges, or the reason;
 * then "image: PATH" lines. -1, nothing printed, for any other reply. */
int uwbd_verdict_text(const char *reply, FILE *out);

#endif
