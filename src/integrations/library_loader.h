/* Opening an integration's shared library at run time (dlopen), so that
 * uwbd maps libmosquitto, libmodbus and libsystemd only when the
 * configuration or the service manager asks for them: a replay, `uwbd
 * --version` or a site without MQTT/Modbus starts without them (and
 * without what they pull in: OpenSSL, libgcrypt, compressors).
 * The per-library tables are mosquitto_loader.h, modbus_loader.h and
 * systemd_loader.h. */
#ifndef UWBD_INTEGRATIONS_LIBRARY_LOADER_H
#define UWBD_INTEGRATIONS_LIBRARY_LOADER_H

#include <stddef.h>

/* The library the environment variable env_override names (a test, or a
 * library outside the loader's path), else default_name ("libmodbus.so.5").
 * NULL with err saying what needs it (needed_for, e.g. "mqtt.enabled"),
 * which library and why it could not be opened, and the package to install. */
void *uwbd_library_open(const char *default_name, const char *env_override, const char *needed_for,
                        const char *package, char *err, size_t errlen);

/* A function of the opened library (dlsym); NULL with err naming both. */
void *uwbd_library_symbol(void *library, const char *library_name, const char *symbol, char *err,
                          size_t errlen);

/* The name uwbd_library_open uses for default_name and env_override. */
const char *uwbd_library_name(const char *default_name, const char *env_override);

#endif
