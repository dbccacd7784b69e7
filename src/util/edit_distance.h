/* How far apart two short names are, for "did you mean" hints (options,
 * console and control commands, configuration keys). */
#ifndef UWB_UTIL_EDIT_DISTANCE_H
#define UWB_UTIL_EDIT_DISTANCE_H

#include <stddef.h>

/* The edit distance (insert, delete, substitute) between a[0..na) and
 * b[0..nb); (size_t)-1 when either is longer than UWB_EDIT_NAME_MAX. */
#define UWB_EDIT_NAME_MAX 40
size_t uwb_edit_distance(const char *a, size_t na, const char *b, size_t nb);

/* A hint names a candidate at most this many edits away: past it, the
 * word typed is another word, not a slip. */
#define UWB_NEAREST_MAX_EDITS 2

/* The candidate nearest a word, offered one at a time: every "did you
 * mean" keeps the same rules (the first of equally near ones wins, the
 * word itself is no hint). */
struct uwb_nearest {
    const char *word;
    size_t word_len;
    const char *best; /* NULL until one within UWB_NEAREST_MAX_EDITS */
    size_t best_len;
    size_t best_distance;
};

void uwb_nearest_start(struct uwb_nearest *n, const char *word, size_t word_len);
void uwb_nearest_offer(struct uwb_nearest *n, const char *candidate, size_t candidate_len);

#endif
