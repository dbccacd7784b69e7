/* libsystemd's notification functions through dlopen (see systemd_loader.h). */
#include "integrations/systemd_loader.h"

#include "integrations/library_loader.h"

const struct uwbd_systemd_api *uwbd_systemd_load(char *err, size_t errlen)
{
    static struct uwbd_systemd_api api;
    static int loaded;
    if (loaded)
        return &api;
    void *library =
        uwbd_library_open(UWBD_SYSTEMD_LIBRARY, UWBD_SYSTEMD_LIBRARY_ENV,
                          "the service manager's notifications (NOTIFY_SOCKET)", "libsystemd0", err, errlen);
    if (!library)
        return NULL;
    const char *name = uwbd_library_name(UWBD_SYSTEMD_LIBRARY, UWBD_SYSTEMD_LIBRARY_ENV);
    struct uwbd_systemd_api found;
    void *address;
    /* POSIX guarantees dlsym's data pointer converts to a function pointer. */
#define UWBD_SYSTEMD_FIND(fn) \
    if (!(address = uwbd_library_symbol(library, name, "sd_" #fn, err, errlen))) \
        return NULL; \
    found.fn = (__typeof__(found.fn))address;
    UWBD_SYSTEMD_FUNCTIONS(UWBD_SYSTEMD_FIND)
#undef UWBD_SYSTEMD_FIND
    api = found;
    loaded = 1;
    return &api;
}
