/* Edit distance for "did you mean" hints (see the header). */
#include "util/edit_distance.h"

size_t uwb_edit_distance(const char *a, size_t na, const char *b, size_t nb)
{
    if (na > UWB_EDIT_NAME_MAX || nb > UWB_EDIT_NAME_MAX)
        return (size_t)-1;
    size_t row[UWB_EDIT_NAME_MAX + 1];
    for (size_t j = 0; j <= nb; j++)
        row[j] = j;
    for (size_t i = 1; i <= na; i++) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= nb; j++) {
            size_t above = row[j];
            size_t best = diagonal + (a[i - 1] != b[j - 1]);
            if (above + 1 < best)
                best = above + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diagonal = above;
        }
    }
    return row[nb];
}

void uwb_nearest_start(struct uwb_nearest *n, const char *word, size_t word_len)
{
    n->word = word;
    n->word_len = word_len;
    n->best = NULL;
    n->best_len = 0;
    n->best_distance = UWB_NEAREST_MAX_EDITS + 1;
}

void uwb_nearest_offer(struct uwb_nearest *n, const char *candidate, size_t candidate_len)
{
    size_t d = uwb_edit_distance(n->word, n->word_len, candidate, candidate_len);
    if (d > 0 && d < n->best_distance) {
        n->best = candidate;
        n->best_len = candidate_len;
        n->best_distance = d;
    }
}
