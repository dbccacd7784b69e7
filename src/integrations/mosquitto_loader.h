/* libmosquitto, loaded when MQTT is enabled (see library_loader.h). The
 * table's entries have the types mosquitto.h declares, so the compiler
 * checks every call as if it were linked. */
#ifndef UWBD_INTEGRATIONS_MOSQUITTO_LOADER_H
#define UWBD_INTEGRATIONS_MOSQUITTO_LOADER_H

#include <mosquitto.h>
#include <stddef.h>

#define UWBD_MOSQUITTO_LIBRARY "libmosquitto.so.1"
/* Names another library file instead (tests: one that does not exist). */
#define UWBD_MOSQUITTO_LIBRARY_ENV "UWB_MOSQUITTO_LIB"

/* X(name): mosquitto_<name>, every function mqtt_publisher.c calls. */
#define UWBD_MOSQUITTO_FUNCTIONS(X) \
    X(lib_init) \
    X(lib_cleanup) \
    X(new) \
    X(destroy) \
    X(connect_callback_set) \
    X(disconnect_callback_set) \
    X(publish_callback_set) \
    X(message_callback_set) \
    X(will_set) \
    X(username_pw_set) \
    X(tls_set) \
    X(log_callback_set) \
    X(threaded_set) \
    X(connect_async) \
    X(reconnect_async) \
    X(loop) \
    X(socket) \
    X(disconnect) \
    X(publish) \
    X(subscribe) \
    X(strerror) \
    X(connack_string)

struct uwbd_mosquitto_api {
// NOLINTNEXTLINE(bugprone-macro-parentheses): name is a member's name, not an expression
#define UWBD_MOSQUITTO_ENTRY(name) __typeof__(mosquitto_##name) *name;
    UWBD_MOSQUITTO_FUNCTIONS(UWBD_MOSQUITTO_ENTRY)
#undef UWBD_MOSQUITTO_ENTRY
};

/* The table, loaded on the first call and kept (the library stays mapped);
 * NULL with err naming the library and the package when it cannot be. */
const struct uwbd_mosquitto_api *uwbd_mosquitto_load(char *err, size_t errlen);

#endif
