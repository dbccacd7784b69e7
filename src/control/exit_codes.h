/* uwbd's exit statuses (sysexits.h values), one per thing an installer
 * has to fix, so a unit file or a script can tell them apart. */
#ifndef UWB_CONTROL_EXIT_CODES_H
#define UWB_CONTROL_EXIT_CODES_H

enum uwbd_exit {
    UWBD_EXIT_OK = 0,           /* stopped by SIGTERM/SIGINT, or --check-config passed */
    UWBD_EXIT_USAGE = 64,       /* bad command line */
    UWBD_EXIT_GPIO_CHIP = 69,   /* GPIO chip (or the emulated board's GPIO socket) missing or unreachable */
    UWBD_EXIT_SOFTWARE = 70,    /* internal error */
    UWBD_EXIT_OS = 71,          /* a system call the daemon needs failed (signalfd, timerfd, threads) */
    UWBD_EXIT_GPIO_LINE = 72,   /* a GPIO line is not on the chip, or another program holds it */
    UWBD_EXIT_CANT_CREATE = 73, /* state directory or control socket cannot be created */
    UWBD_EXIT_DIGITISER = 74,   /* digitiser port missing or unreachable */
    UWBD_EXIT_NO_PERM = 77,     /* started as root without allow_root */
    UWBD_EXIT_CONFIG = 78,      /* configuration malformed or incomplete */
};

/* uwbd ctl */
enum uwbd_ctl_exit {
    UWBD_CTL_OK = 0,      /* a reply other than ERROR */
    UWBD_CTL_REFUSED = 1, /* the daemon replied ERROR */
    UWBD_CTL_USAGE = 64,
    UWBD_CTL_NO_DAEMON = 69, /* nothing listening on the control socket */
    UWBD_CTL_TIMEOUT = 75,   /* no reply in time */
    UWBD_CTL_NO_PERM = 77,   /* this user may not open the control socket */
};

/* The exit status for a failed uwb_rig_open (its result and *detail). */
int uwbd_exit_for_rig_open(int rig_error, int detail);

#endif
