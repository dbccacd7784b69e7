/* Timing: the median / best of repeated runs. */
#include "bench.h"

#include <stdlib.h>
#include <string.h>

void bench_series_add(struct bench_series *s, double seconds)
{
    if (s->n < (int)(sizeof s->seconds / sizeof s->seconds[0]))
        s->seconds[s->n++] = seconds;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double bench_series_median(const struct bench_series *s)
{
    if (s->n == 0)
        return 0.0;
    double v[sizeof s->seconds / sizeof s->seconds[0]];
    memcpy(v, s->seconds, (size_t)s->n * sizeof v[0]);
    qsort(v, (size_t)s->n, sizeof v[0], by_value);
    return s->n % 2 ? v[s->n / 2] : 0.5 * (v[s->n / 2 - 1] + v[s->n / 2]);
}

double bench_series_best(const struct bench_series *s)
{
    double best = s->n ? s->seconds[0] : 0.0;
    for (int i = 1; i < s->n; i++)
        if (s->seconds[i] < best)
            best = s->seconds[i];
    return best;
}
