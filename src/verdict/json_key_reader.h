/* Reading a verdict's keys out of a cJSON object, keeping the first
 * problem as "verdict: key `KEY`: PROBLEM": the field table's walk and the
 * record's cycle keys and images read through the same three calls. */
#ifndef UWB_VERDICT_JSON_KEY_READER_H
#define UWB_VERDICT_JSON_KEY_READER_H

#include <cjson/cJSON.h>
#include <stddef.h>

struct uwb_json_key_reader {
    char *err;
    size_t errlen;
    int failed; /* a problem was met (the first is in err) */
};

/* Notes a problem with key: the first one goes into err. */
void uwb_json_key_refuse(struct uwb_json_key_reader *rd, const char *key, const char *problem);
/* The string at key into out (size n): 1 when there, 0 when absent or refused. */
int uwb_json_key_text(struct uwb_json_key_reader *rd, const cJSON *o, const char *key, char *out, size_t n);
/* The finite number at key into *out: 1 when there, 0 when absent or refused. */
int uwb_json_key_number(struct uwb_json_key_reader *rd, const cJSON *o, const char *key, double *out);

#endif
