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

#endif
