/* How far apart two short names are, for "did you mean" hints (options,
 * console and control commands). */
#ifndef UWB_UTIL_EDIT_DISTANCE_H
#define UWB_UTIL_EDIT_DISTANCE_H

#include <stddef.h>

/* The edit distance (insert, delete, substitute) between a[0..na) and
 * b[0..nb); (size_t)-1 when either is longer than UWB_EDIT_NAME_MAX. */
#define UWB_EDIT_NAME_MAX 40
size_t uwb_edit_distance(const char *a, size_t na, const char *b, size_t nb);

#endif
