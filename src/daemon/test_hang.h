/* A test-only hook: with UWBD_TEST_HANG=<where> in its environment the
 * daemon stops dead at that point (where: "loop", the main loop as a scan
 * starts; "worker", the scan worker as it starts acquiring), so that a test
 * can see the systemd watchdog's pings stop (tests/e2e/test_systemd_notify.sh).
 * Never set it on an appliance: the daemon then hangs until it is killed. */
#ifndef UWB_DAEMON_TEST_HANG_H
#define UWB_DAEMON_TEST_HANG_H

#define UWBD_TEST_HANG_ENV "UWBD_TEST_HANG"

void uwbd_test_hang_point(const char *where);

#endif
