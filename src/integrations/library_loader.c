/* dlopen/dlsym with errors that name the library (see library_loader.h). */
#include "integrations/library_loader.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

const char *uwbd_library_name(const char *default_name, const char *env_override)
{
    const char *name = env_override ? getenv(env_override) : NULL;
    return name && name[0] ? name : default_name;
}

void *uwbd_library_open(const char *default_name, const char *env_override, const char *needed_for,
                        const char *package, char *err, size_t errlen)
{
    const char *name = uwbd_library_name(default_name, env_override);
    /* RTLD_NOW: a library missing a function fails here, not at its first call. */
    void *library = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        const char *why = dlerror();
        snprintf(err, errlen, "%s needs %s, which cannot be loaded (%s); install the %s package", needed_for,
                 name, why ? why : "no reason given", package);
    }
    return library;
}

void *uwbd_library_symbol(void *library, const char *library_name, const char *symbol, char *err,
                          size_t errlen)
{
    dlerror();
    void *address = dlsym(library, symbol);
    if (!address)
        snprintf(err, errlen, "%s has no %s (too old a version?)", library_name, symbol);
    return address;
}
