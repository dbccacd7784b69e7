/* The site's lines (src/integrations/site_io.c): one GPIO handle for the
 * alarm contacts and the event input, opened once at start on a handle of
 * its own (the rig's belongs to the scan thread while it runs), and a timer
 * that reads the event input and opens a lost handle again. It reaches
 * hardware only through the GPIO driver table. */
#ifndef UWB_INTEGRATIONS_SITE_IO_H
#define UWB_INTEGRATIONS_SITE_IO_H

#include <stddef.h>

#include "config/site_config.h"

struct uwbd_site_io;

/* The energised state of the three contacts, -1 where there are none. */
struct uwbd_contact_states {
    int watch, alarm, fault;
};

/* Opens the site's lines (none when neither contacts nor event input is
 * on: *io is then a valid object that does nothing). Returns 0, or an enum
 * uwb_gpio_error with err saying which line. */
int uwbd_site_io_open(struct uwbd_site_io **io, const struct uwbd_site_config *cfg, char *err, size_t errlen);
/* The contact lines held at energised[watch, alarm, fault] from now on:
 * driven now (the handle opened again first if it was lost) and whenever a
 * lost handle comes back. */
void uwbd_site_io_contacts(struct uwbd_site_io *io, const int energised[3]);
/* The timer the daemon polls (-1: none), and what to do when it fires:
 * returns 1 when the event input asks for a scan. */
int uwbd_site_io_timer_fd(const struct uwbd_site_io *io);
int uwbd_site_io_tick(struct uwbd_site_io *io);
/* Drives every output low (contacts de-energised: the fault contact opens,
 * the monitor is stopping) and releases the lines. NULL is a no-op. */
void uwbd_site_io_close(struct uwbd_site_io *io);

#endif
