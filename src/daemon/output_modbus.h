/* The Modbus server as an output module (output_modbus.c). */
#ifndef UWBD_DAEMON_OUTPUT_MODBUS_H
#define UWBD_DAEMON_OUTPUT_MODBUS_H

#include "daemon/output_module.h"

extern const struct uwbd_output_module uwbd_output_modbus;

/* Whether the server is open (for `status`). */
int uwbd_modbus_listening(void);

#endif
