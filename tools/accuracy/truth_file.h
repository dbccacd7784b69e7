/* A full-wave scan's truth file (SCAN.truth.json beside SCAN.uwbscan,
 * ../shared/data/README.md): what the accuracy reports judge against. */
#ifndef UWB_ACCURACY_TRUTH_FILE_H
#define UWB_ACCURACY_TRUTH_FILE_H

#include <stddef.h>

struct accuracy_truth {
    double shift_mm;         /* displacement_mm: the winding's move */
    double height_change_mm; /* a squeezed spacer's, 0 when the file has none */
    int has_span;            /* y1_m and y2_m given: the winding's drawn extent */
    double y1_mm, y2_mm;
};

/* The truth of scan_path (a path ending in .uwbscan): 0, or -1 with err
 * naming the file and what it lacks. */
int accuracy_truth_read(const char *scan_path, struct accuracy_truth *t, char *err, size_t errlen);

#endif
