/* libmosquitto's functions through dlopen (see mosquitto_loader.h). */
#include "integrations/mosquitto_loader.h"

#include "integrations/library_loader.h"

const struct uwbd_mosquitto_api *uwbd_mosquitto_load(char *err, size_t errlen)
{
    static struct uwbd_mosquitto_api api;
    static int loaded;
    if (loaded)
        return &api;
    void *library = uwbd_library_open(UWBD_MOSQUITTO_LIBRARY, UWBD_MOSQUITTO_LIBRARY_ENV, "mqtt.enabled",
                                      "libmosquitto1", err, errlen);
    if (!library)
        return NULL;
    const char *name = uwbd_library_name(UWBD_MOSQUITTO_LIBRARY, UWBD_MOSQUITTO_LIBRARY_ENV);
    struct uwbd_mosquitto_api found;
    void *address;
    /* POSIX guarantees dlsym's data pointer converts to a function pointer. */
#define UWBD_MOSQUITTO_FIND(fn) \
    if (!(address = uwbd_library_symbol(library, name, "mosquitto_" #fn, err, errlen))) \
        return NULL; \
    found.fn = (__typeof__(found.fn))address;
    UWBD_MOSQUITTO_FUNCTIONS(UWBD_MOSQUITTO_FIND)
#undef UWBD_MOSQUITTO_FIND
    api = found;
    loaded = 1;
    return &api;
}
