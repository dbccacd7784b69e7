/* The drawings' winding span (analysis.winding_span_mm, `--winding-span`)
 * judged by one rule wherever it is given, so the command line cannot take
 * what the configuration refuses. */
#ifndef UWB_CONFIG_WINDING_SPAN_H
#define UWB_CONFIG_WINDING_SPAN_H

#include <stddef.h>

#define UWBD_WINDING_SPAN_KEY "analysis.winding_span_mm"

/* 0 when both ends (metres) lie in the key's range and the lower is below
 * the upper; else -1 with problem, worded in the key's unit (mm). */
int uwbd_winding_span_check(const double span_m[2], char *problem, size_t n);

#endif
