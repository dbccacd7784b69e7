/* A signed figure as the pictures print it: the caption, the radial panel
 * and the limits meter share it, so it lives apart from each of them. */
#include "output/render_internal.h"

#include <math.h>
#include <stdio.h>

void uwb_format_signed(char *buf, size_t len, double value, int decimals)
{
    double unit = pow(10.0, -decimals);
    if (fabs(value) < 0.5 * unit)
        snprintf(buf, len, "%.*f", decimals, 0.0); /* never "-0.0" */
    else
        snprintf(buf, len, "%+.*f", decimals, value);
}
