/* json_edit: writes a changed copy of a JSON file (a configuration with one
 * key wrong, a slowed scan) for the e2e scripts, with cJSON instead of
 * python3, which a fresh Debian minbase does not have.
 *
 *   json_edit IN OUT EDIT...
 *     PATH=JSON   set PATH (dotted; its parent must exist) to the JSON value
 *     -PATH       remove PATH, which must exist
 * OUT may be IN; it is written whole to a temporary and renamed over.
 * Exit 0 written; 1 an edit does not apply; 2 IN unreadable or not JSON,
 * or OUT not written. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/read_file.h"

#define MAX_FILE_BYTES ((size_t)64 * 1024 * 1024)

/* The object holding the last key of PATH, and that key. */
static cJSON *parent_of(cJSON *root, const char *path, char *key, size_t keylen)
{
    cJSON *o = root;
    for (;;) {
        size_t n = strcspn(path, ".");
        snprintf(key, keylen, "%.*s", (int)n, path);
        if (path[n] == '\0')
            return cJSON_IsObject(o) ? o : NULL;
        o = cJSON_GetObjectItemCaseSensitive(o, key);
        path += n + 1;
    }
}

static int apply(cJSON *root, const char *edit)
{
    char path[256], key[256];
    const char *eq = strchr(edit, '=');
    int removing = edit[0] == '-';
    if (removing)
        snprintf(path, sizeof path, "%s", edit + 1);
    else if (eq)
        snprintf(path, sizeof path, "%.*s", (int)(eq - edit), edit);
    else {
        fprintf(stderr, "json_edit: '%s' is neither PATH=JSON nor -PATH\n", edit);
        return 1;
    }
    cJSON *parent = parent_of(root, path, key, sizeof key);
    if (!parent) {
        fprintf(stderr, "json_edit: '%s': no object holds %s\n", edit, path);
        return 1;
    }
    if (removing) {
        if (!cJSON_GetObjectItemCaseSensitive(parent, key)) {
            fprintf(stderr, "json_edit: '%s': there is no %s to remove\n", edit, path);
            return 1;
        }
        cJSON_DeleteItemFromObjectCaseSensitive(parent, key);
        return 0;
    }
    cJSON *value = cJSON_Parse(eq + 1);
    if (!value) {
        fprintf(stderr, "json_edit: '%s': '%s' is not a JSON value\n", edit, eq + 1);
        return 1;
    }
    if (cJSON_GetObjectItemCaseSensitive(parent, key))
        cJSON_ReplaceItemInObjectCaseSensitive(parent, key, value);
    else
        cJSON_AddItemToObject(parent, key, value);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: json_edit IN OUT [PATH=JSON | -PATH]...\n");
        return 64;
    }
    char *text, err[1024];
    size_t len;
    if (uwb_read_file(argv[1], MAX_FILE_BYTES, &text, &len, err, sizeof err) != UWB_READ_OK) {
        fprintf(stderr, "json_edit: %s\n", err);
        return 2;
    }
    cJSON *root = cJSON_ParseWithLength(text, len);
    free(text);
    if (!root) {
        fprintf(stderr, "json_edit: %s: not JSON\n", argv[1]);
        return 2;
    }
    for (int i = 3; i < argc; i++) {
        if (apply(root, argv[i]) != 0) {
            cJSON_Delete(root);
            return 1;
        }
    }
    char *out = cJSON_Print(root);
    cJSON_Delete(root);
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.json_edit", argv[2]);
    FILE *f = out ? fopen(tmp, "w") : NULL;
    int ok = f && fputs(out, f) >= 0 && fputc('\n', f) != EOF;
    ok = f && fclose(f) == 0 && ok && rename(tmp, argv[2]) == 0;
    if (!ok) {
        fprintf(stderr, "json_edit: %s: cannot write\n", argv[2]);
        remove(tmp);
    }
    free(out);
    return ok ? 0 : 2;
}
