/* Reading a verdict's keys, the first problem kept (see the header). */
#include "verdict/json_key_reader.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void uwb_json_key_refuse(struct uwb_json_key_reader *rd, const char *key, const char *problem)
{
    if (!rd->failed)
        snprintf(rd->err, rd->errlen, "verdict: key `%s`: %s", key, problem);
    rd->failed = 1;
}

int uwb_json_key_text(struct uwb_json_key_reader *rd, const cJSON *o, const char *key, char *out, size_t n)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v)
        return 0;
    if (!cJSON_IsString(v)) {
        uwb_json_key_refuse(rd, key, "not a string");
        return 0;
    }
    if (strlen(v->valuestring) >= n) {
        uwb_json_key_refuse(rd, key, "too long");
        return 0;
    }
    memcpy(out, v->valuestring, strlen(v->valuestring) + 1);
    return 1;
}

int uwb_json_key_number(struct uwb_json_key_reader *rd, const cJSON *o, const char *key, double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v)
        return 0;
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) {
        uwb_json_key_refuse(rd, key, "not a number");
        return 0;
    }
    *out = v->valuedouble;
    return 1;
}
