/* The digitiser's front door: picks the backend for the model from its
 * table (as src/gpio/gpio.c does for GPIO) and hands every call to it. */
#include "uwb/digitiser.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "digitiser/digitiser_backend.h"
#include "uwb/link.h"

static const struct uwb_digitiser_backend *const backends[] = {&uwb_digitiser_framed_backend};

const struct uwb_digitiser_backend *uwb_digitiser_backend_find(const char *model, char *err, size_t errlen)
{
    char known[128] = "";
    size_t used = 0;
    for (size_t i = 0; i < sizeof backends / sizeof backends[0]; i++) {
        if (strcmp(model, backends[i]->name) == 0)
            return backends[i];
        int n = snprintf(known + used, sizeof known - used, "%s%s", i ? ", " : "", backends[i]->name);
        if (n > 0 && (size_t)n < sizeof known - used)
            used += (size_t)n;
    }
    snprintf(err, errlen, "digitiser model '%s' unknown (known: %s)", model, known);
    return NULL;
}

int uwb_digitiser_open_model(const char *model, const struct uwb_digitiser_config *cfg,
                             struct uwb_digitiser **dig, int *link_detail, char *err, size_t errlen)
{
    *dig = NULL;
    if (link_detail)
        *link_detail = UWB_LINK_OK;
    const struct uwb_digitiser_backend *backend = uwb_digitiser_backend_find(model, err, errlen);
    if (!backend)
        return UWB_DIGITISER_ERR_CONFIG;
    struct uwb_digitiser *d = calloc(1, sizeof *d);
    if (!d) {
        snprintf(err, errlen, "digitiser: out of memory");
        return UWB_DIGITISER_ERR_LINK;
    }
    d->backend = backend;
    int rc = backend->open(d, cfg, link_detail, err, errlen);
    if (rc != UWB_DIGITISER_OK) {
        free(d);
        return rc;
    }
    *dig = d;
    return UWB_DIGITISER_OK;
}

int uwb_digitiser_open(const struct uwb_digitiser_config *cfg, struct uwb_digitiser **dig, int *link_detail,
                       char *err, size_t errlen)
{
    return uwb_digitiser_open_model(UWB_DIGITISER_DEFAULT_MODEL, cfg, dig, link_detail, err, errlen);
}

const char *uwb_digitiser_identity(const struct uwb_digitiser *dig)
{
    return dig->backend->identity(dig);
}

int uwb_digitiser_acquire(struct uwb_digitiser *dig, uwb_fire_fn fire, void *ctx, float *out, char *err,
                          size_t errlen)
{
    return dig->backend->acquire(dig, fire, ctx, out, err, errlen);
}

void uwb_digitiser_get_stats(const struct uwb_digitiser *dig, struct uwb_digitiser_stats *stats)
{
    dig->backend->get_stats(dig, stats);
}

void uwb_digitiser_close(struct uwb_digitiser *dig)
{
    if (!dig)
        return;
    dig->backend->close(dig);
    free(dig);
}
