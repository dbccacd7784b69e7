/* The alarm contacts' latch kept in the state directory (see the header).
 * Small JSON, so a person can read it; any field missing or of the wrong
 * type makes the whole file unreadable, which holds the alarm. */
#include "state/contacts_latch.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "uwb/read_file.h"

#define LATCH_MAX_BYTES 4096

static const struct {
    const char *key;
    size_t offset;
} fields[] = {
    {"watch_called", offsetof(struct uwbd_contacts_memory, watch_called)},
    {"alarm_called", offsetof(struct uwbd_contacts_memory, alarm_called)},
    {"watch_unacked", offsetof(struct uwbd_contacts_memory, watch_unacked)},
    {"alarm_unacked", offsetof(struct uwbd_contacts_memory, alarm_unacked)},
};
#define FIELD_COUNT (sizeof fields / sizeof fields[0])

static int *field_at(struct uwbd_contacts_memory *m, size_t i)
{
    return (int *)(void *)((char *)m + fields[i].offset);
}

int uwbd_contacts_latch_path(const struct uwbd_store *store, char *out, size_t n)
{
    return uwbd_path_join(out, n, store->root, UWBD_CONTACTS_LATCH_FILE);
}

enum uwbd_contacts_kept uwbd_contacts_latch_read(const char *path, struct uwbd_contacts_memory *out,
                                                 char *why, size_t whylen)
{
    struct stat st;
    if (lstat(path, &st) != 0 && errno == ENOENT)
        return UWBD_CONTACTS_KEPT_NONE;
    char *text = NULL;
    size_t len = 0;
    if (uwb_read_file_nofollow(path, LATCH_MAX_BYTES, &text, &len, why, whylen) != UWB_READ_OK)
        return UWBD_CONTACTS_KEPT_UNREADABLE;
    cJSON *root = cJSON_ParseWithLength(text, len);
    free(text);
    struct uwbd_contacts_memory m = {0};
    const char *bad = NULL;
    if (!cJSON_IsObject(root))
        bad = "not a JSON object";
    for (size_t i = 0; !bad && i < FIELD_COUNT; i++) {
        const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, fields[i].key);
        if (!cJSON_IsBool(item))
            bad = fields[i].key;
        else
            *field_at(&m, i) = cJSON_IsTrue(item);
    }
    cJSON_Delete(root);
    if (bad) {
        snprintf(why, whylen, "%s: %s%s", path, bad,
                 strchr(bad, ' ') ? "" : ": missing, or not true or false");
        return UWBD_CONTACTS_KEPT_UNREADABLE;
    }
    *out = m;
    return UWBD_CONTACTS_KEPT;
}

int uwbd_contacts_latch_write(const char *path, const struct uwbd_contacts_memory *memory, char *err,
                              size_t errlen)
{
    struct uwbd_contacts_memory m = *memory;
    cJSON *root = cJSON_CreateObject();
    for (size_t i = 0; root && i < FIELD_COUNT; i++)
        if (!cJSON_AddBoolToObject(root, fields[i].key, *field_at(&m, i) != 0)) {
            cJSON_Delete(root);
            root = NULL;
        }
    char *json = root ? cJSON_PrintUnformatted(root) : NULL;
    cJSON_Delete(root);
    if (!json) {
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    int rc = uwbd_write_json_file(path, json, err, errlen);
    free(json);
    return rc;
}
