/* The site's lines as an output module (output_site_io.c): the GPIO handle
 * the alarm contacts and the event input share. */
#ifndef UWBD_DAEMON_OUTPUT_SITE_IO_H
#define UWBD_DAEMON_OUTPUT_SITE_IO_H

#include "daemon/output_module.h"
#include "integrations/site_io.h"

extern const struct uwbd_output_module uwbd_output_site_io;

/* The open lines, or NULL: none yet, or a reload could not open them. */
struct uwbd_site_io *uwbd_site_lines(void);

#endif
