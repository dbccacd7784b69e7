/* The accuracy targets of issue 44 as assertions (make accuracy): every
 * noiseless full-wave pair replayed as published, each figure given set
 * against its truth; see targets.c. */
#ifndef UWB_ACCURACY_TARGETS_H
#define UWB_ACCURACY_TARGETS_H

#include <stddef.h>
#include <stdio.h>

#include "uwb/evaluate.h"

struct accuracy_targets {
    int pairs;
    int given, within, wide;             /* displacements given; within 2 sigma; sigma over the bound */
    int heights_given, heights_within;   /* height changes given; within 2 sigma */
    int edges_given, edges_within;       /* pairs whose edges are published; all within 2 sigma */
    int compressions, compressions_read; /* the family's squeezed spacers; read within 0.5 mm */
    int missed;                          /* targets missed (each printed) */
};

/* Replays data_dir's shared pairs (paper, tank, radial, family, 3-D) and
 * fresh_dir's fresh draws under opt; prints each pair's figures, sigma
 * with its terms and error over sigma, the tallies and every target
 * missed, to out. 0 (see t->missed), or -1 with err. */
int accuracy_targets_run(FILE *out, const char *data_dir, const char *fresh_dir,
                         const struct uwb_evaluate_options *opt, struct accuracy_targets *t, char *err,
                         size_t errlen);

#endif
