/* The warm-oil pairs (issue 44, item 2): the shared full-wave tank's
 * winding in the simulator, drawn over the family's ranges, the scan made
 * with the oil's eps_r off the header's and nothing moved; see warm_oil.c. */
#ifndef UWB_ACCURACY_WARM_OIL_H
#define UWB_ACCURACY_WARM_OIL_H

#include <stddef.h>
#include <stdio.h>

struct warm_oil_tally {
    int pairs;
    int given;        /* height changes given */
    int within;       /* ...within 2 sigma of none */
    int shift_within; /* displacements within 2 sigma of none */
};

/* Simulates every tank of the draw at each oil, evaluates it against its
 * baseline, prints a row per pair to out and fills *t. 0, or -1 with err. */
int accuracy_warm_oil(FILE *out, struct warm_oil_tally *t, char *err, size_t errlen);

#endif
