/* libmodbus's functions through dlopen (see modbus_loader.h). */
#include "integrations/modbus_loader.h"

#include "integrations/library_loader.h"

const struct uwbd_modbus_api *uwbd_modbus_load(char *err, size_t errlen)
{
    static struct uwbd_modbus_api api;
    static int loaded;
    if (loaded)
        return &api;
    void *library = uwbd_library_open(UWBD_MODBUS_LIBRARY, UWBD_MODBUS_LIBRARY_ENV, "modbus.enabled",
                                      "libmodbus5", err, errlen);
    if (!library)
        return NULL;
    const char *name = uwbd_library_name(UWBD_MODBUS_LIBRARY, UWBD_MODBUS_LIBRARY_ENV);
    struct uwbd_modbus_api found;
    void *address;
    /* POSIX guarantees dlsym's data pointer converts to a function pointer. */
#define UWBD_MODBUS_FIND(fn) \
    if (!(address = uwbd_library_symbol(library, name, "modbus_" #fn, err, errlen))) \
        return NULL; \
    found.fn = (__typeof__(found.fn))address;
    UWBD_MODBUS_FUNCTIONS(UWBD_MODBUS_FIND)
#undef UWBD_MODBUS_FIND
    api = found;
    loaded = 1;
    return &api;
}
