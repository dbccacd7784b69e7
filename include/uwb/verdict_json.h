/* The verdict as one JSON object (gpsd style: a "class", no nulls: what is
 * not known is left out). */
#ifndef UWB_VERDICT_JSON_H
#define UWB_VERDICT_JSON_H

#include "uwb/verdict.h"

/* malloc'd single-line JSON text, or NULL when out of memory. */
char *uwb_verdict_to_json(const struct uwb_verdict *v);

#endif
