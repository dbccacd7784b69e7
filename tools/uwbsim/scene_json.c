/* JSON scene files: a flat object of parameter names, read with cJSON. */
#include "scene.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/read_file.h"

/* A scene is a few hundred bytes; this bounds what a wrong path can cost. */
#define SCENE_FILE_MAX_BYTES ((size_t)16 * 1024 * 1024)

static const char *type_word(enum sim_param_type t)
{
    switch (t) {
    case SIM_PARAM_NUMBER: return "a number";
    case SIM_PARAM_OPTNUMBER: return "a number or null";
    case SIM_PARAM_INT: return "an integer";
    case SIM_PARAM_BOOL: return "true or false";
    case SIM_PARAM_ENUM:
    case SIM_PARAM_STRING: return "a string";
    }
    return "?";
}

/* Turn one JSON value into the text the setter takes, or refuse its type. */
static int value_text(const struct sim_param *p, const cJSON *v, char *buf, size_t buflen)
{
    switch (p->type) {
    case SIM_PARAM_OPTNUMBER:
        if (cJSON_IsNull(v)) {
            snprintf(buf, buflen, "none");
            return 0;
        }
        /* fall through */
    case SIM_PARAM_NUMBER:
    case SIM_PARAM_INT:
        if (!cJSON_IsNumber(v))
            return -1;
        snprintf(buf, buflen, "%.17g", v->valuedouble);
        return 0;
    case SIM_PARAM_BOOL:
        if (!cJSON_IsBool(v))
            return -1;
        snprintf(buf, buflen, "%s", cJSON_IsTrue(v) ? "true" : "false");
        return 0;
    case SIM_PARAM_ENUM:
    case SIM_PARAM_STRING:
        if (!cJSON_IsString(v) || !v->valuestring)
            return -1;
        if (strlen(v->valuestring) >= buflen)
            return -1;
        snprintf(buf, buflen, "%s", v->valuestring);
        return 0;
    }
    return -1;
}

int sim_scene_apply_json_text(const char *text, const char *name, struct sim_scene *scene, char *err,
                              size_t errlen)
{
    cJSON *root = cJSON_Parse(text);
    if (!root) {
        const char *where = cJSON_GetErrorPtr();
        long off = where ? (long)(where - text) : -1;
        snprintf(err, errlen, "%s: not valid JSON (near byte %ld)", name, off);
        return -1;
    }
    if (!cJSON_IsObject(root)) {
        snprintf(err, errlen, "%s: a scene file must be one JSON object", name);
        cJSON_Delete(root);
        return -1;
    }
    /* Work on a copy so a refused file leaves the caller's scene untouched. */
    struct sim_scene work = *scene;
    char value[SIM_TEXT_MAX + 32], inner[300];
    for (const cJSON *item = root->child; item; item = item->next) {
        const struct sim_param *p = NULL;
        size_t n;
        const struct sim_param *all = sim_params(&n);
        for (size_t i = 0; i < n; i++)
            if (strcmp(all[i].name, item->string) == 0)
                p = &all[i];
        if (!p) {
            snprintf(err, errlen, "%s: unknown key \"%s\" (uwbsim --help lists the parameters)", name,
                     item->string);
            cJSON_Delete(root);
            return -1;
        }
        if (value_text(p, item, value, sizeof value) != 0) {
            snprintf(err, errlen, "%s: key \"%s\" must be %s", name, p->name, type_word(p->type));
            cJSON_Delete(root);
            return -1;
        }
        if (sim_scene_set(&work, p->name, value, inner, sizeof inner) != 0) {
            snprintf(err, errlen, "%s: key %s", name, inner);
            cJSON_Delete(root);
            return -1;
        }
    }
    cJSON_Delete(root);
    *scene = work;
    return 0;
}

int sim_scene_load_json(const char *path, struct sim_scene *scene, char *err, size_t errlen)
{
    char *text;
    size_t len;
    enum uwb_read_result read_result = uwb_read_file(path, SCENE_FILE_MAX_BYTES, &text, &len, err, errlen);
    if (read_result == UWB_READ_TOO_BIG) {
        size_t used = strlen(err);
        snprintf(err + used, errlen - used, ": not a scene file");
    }
    if (read_result != UWB_READ_OK)
        return -1;
    int rc = sim_scene_apply_json_text(text, path, scene, err, errlen);
    free(text);
    return rc;
}

int sim_scene_to_json(const struct sim_scene *scene, char **json)
{
    size_t n;
    const struct sim_param *all = sim_params(&n);
    cJSON *root = cJSON_CreateObject();
    if (!root)
        return -1;
    for (size_t i = 0; i < n; i++) {
        const struct sim_param *p = &all[i];
        const char *base = (const char *)scene + p->offset;
        cJSON *v = NULL;
        switch (p->type) {
        case SIM_PARAM_NUMBER:
        case SIM_PARAM_OPTNUMBER: {
            // cppcheck-suppress invalidPointerCast ; points at a double member (the key table's offsetof)
            double d = *(const double *)base;
            v = isnan(d) ? cJSON_CreateNull() : cJSON_CreateNumber(d);
            break;
        }
        case SIM_PARAM_INT: v = cJSON_CreateNumber(*(const int *)base); break;
        case SIM_PARAM_BOOL: v = cJSON_CreateBool(*(const int *)base); break;
        case SIM_PARAM_ENUM: v = cJSON_CreateString(p->choices[*(const int *)base]); break;
        case SIM_PARAM_STRING: v = cJSON_CreateString(base); break;
        }
        if (!v || !cJSON_AddItemToObject(root, p->name, v)) {
            cJSON_Delete(v);
            cJSON_Delete(root);
            return -1;
        }
    }
    *json = cJSON_Print(root);
    cJSON_Delete(root);
    return *json ? 0 : -1;
}
