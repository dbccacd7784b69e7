/* The verdict as one JSON object (gpsd style: a "class", no nulls: what is
 * not known is left out). Built once from the evaluation's verdict; the
 * daemon adds its own fields to the object and prints it. */
#ifndef UWB_VERDICT_JSON_H
#define UWB_VERDICT_JSON_H

#include <cjson/cJSON.h>

#include "uwb/verdict.h"

/* The VERDICT object (free with cJSON_Delete), or NULL when out of memory. */
cJSON *uwb_verdict_object(const struct uwb_verdict *v);

/* Picoseconds to 0.1 ps, as every verdict and reply prints them. */
void uwb_json_add_ps(cJSON *obj, const char *key, double seconds);

/* malloc'd single-line JSON text of uwb_verdict_object, or NULL when out of memory. */
char *uwb_verdict_to_json(const struct uwb_verdict *v);

#endif
