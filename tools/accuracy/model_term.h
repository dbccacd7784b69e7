/* The axial sigma's model term calibrated on the noiseless full-wave pairs
 * (make accuracy-model-term): see model_term.c. */
#ifndef UWB_ACCURACY_MODEL_TERM_H
#define UWB_ACCURACY_MODEL_TERM_H

#include <stddef.h>
#include <stdio.h>

/* Replays the shared family, tank and paper pairs of data_dir and the
 * fresh draws of fresh_dir; prints the share of the move each needs, the
 * largest rounded up to 0.001 (*share_out), and every pair's figure, sigma
 * with its terms and error over sigma under it. 0, or -1 with err. */
int accuracy_model_term(FILE *out, const char *data_dir, const char *fresh_dir, double *share_out, char *err,
                        size_t errlen);

#endif
