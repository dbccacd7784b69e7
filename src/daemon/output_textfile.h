/* The Prometheus textfile as an output module (output_textfile.c): it keeps
 * the verdict counts since start, which MQTT's health report carries too. */
#ifndef UWBD_DAEMON_OUTPUT_TEXTFILE_H
#define UWBD_DAEMON_OUTPUT_TEXTFILE_H

#include "daemon/output_module.h"

extern const struct uwbd_output_module uwbd_output_textfile;

/* The latest verdict's status (NULL: none) and the verdicts since start. */
const char *uwbd_latest_status(void);
unsigned long uwbd_verdicts_since_start(void);

#endif
