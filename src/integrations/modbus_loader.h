/* libmodbus, loaded when Modbus is enabled (see library_loader.h). The
 * table's entries have the types modbus.h declares, so the compiler checks
 * every call as if it were linked. */
#ifndef UWBD_INTEGRATIONS_MODBUS_LOADER_H
#define UWBD_INTEGRATIONS_MODBUS_LOADER_H

#include <modbus/modbus.h>
#include <stddef.h>

#define UWBD_MODBUS_LIBRARY "libmodbus.so.5"
/* Names another library file instead (tests: one that does not exist). */
#define UWBD_MODBUS_LIBRARY_ENV "UWB_MODBUS_LIB"

/* X(name): modbus_<name>, every function modbus_server.c calls. */
#define UWBD_MODBUS_FUNCTIONS(X) \
    X(new_rtu) \
    X(new_tcp_pi) \
    X(tcp_pi_listen) \
    X(free) \
    X(set_slave) \
    X(set_socket) \
    X(set_indication_timeout) \
    X(set_byte_timeout) \
    X(get_header_length) \
    X(mapping_new) \
    X(mapping_free) \
    X(receive) \
    X(reply) \
    X(reply_exception) \
    X(flush) \
    X(strerror)

struct uwbd_modbus_api {
// NOLINTNEXTLINE(bugprone-macro-parentheses): name is a member's name, not an expression
#define UWBD_MODBUS_ENTRY(name) __typeof__(modbus_##name) *name;
    UWBD_MODBUS_FUNCTIONS(UWBD_MODBUS_ENTRY)
#undef UWBD_MODBUS_ENTRY
};

/* The table, loaded on the first call and kept (the library stays mapped);
 * NULL with err naming the library and the package when it cannot be. */
const struct uwbd_modbus_api *uwbd_modbus_load(char *err, size_t errlen);

#endif
