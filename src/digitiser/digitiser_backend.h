/* What a digitiser backend (src/digitiser/digitiser_framed.c) sees of a
 * struct uwb_digitiser, and the table that picks one by model name; nothing
 * above the backends includes this. A second model is one file and a row
 * in src/digitiser/digitiser.c's table. */
#ifndef UWB_DIGITISER_BACKEND_H
#define UWB_DIGITISER_BACKEND_H

#include <stddef.h>

#include "uwb/digitiser.h"

/* Each as its uwb_digitiser_* namesake; open sets dig->state, close frees it. */
struct uwb_digitiser_backend {
    const char *name; /* the model this backend speaks to */
    int (*open)(struct uwb_digitiser *dig, const struct uwb_digitiser_config *cfg, int *link_detail,
                char *err, size_t errlen);
    const char *(*identity)(const struct uwb_digitiser *dig);
    int (*acquire)(struct uwb_digitiser *dig, uwb_fire_fn fire, void *ctx, float *out, char *err,
                   size_t errlen);
    void (*get_stats)(const struct uwb_digitiser *dig, struct uwb_digitiser_stats *stats);
    void (*close)(struct uwb_digitiser *dig);
};

struct uwb_digitiser {
    const struct uwb_digitiser_backend *backend;
    void *state; /* the backend's own */
};

extern const struct uwb_digitiser_backend uwb_digitiser_framed_backend;

/* The model uwb_digitiser_open speaks to. */
#define UWB_DIGITISER_DEFAULT_MODEL "framed"

/* The backend for `model`, or NULL with err naming the model and the known ones. */
const struct uwb_digitiser_backend *uwb_digitiser_backend_find(const char *model, char *err, size_t errlen);

/* uwb_digitiser_open for a named model; an unknown one is
 * UWB_DIGITISER_ERR_CONFIG. */
int uwb_digitiser_open_model(const char *model, const struct uwb_digitiser_config *cfg,
                             struct uwb_digitiser **dig, int *link_detail, char *err, size_t errlen);

#endif
