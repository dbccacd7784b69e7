/* Order statistics (private to src/imaging). */
#ifndef UWB_SELECT_H
#define UWB_SELECT_H

#include <stddef.h>

/* Median of v[0..n-1]; reorders v. Returns 0 for n == 0. */
float uwb_median_float(float *v, size_t n);

#endif
