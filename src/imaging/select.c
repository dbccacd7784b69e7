/* Quickselect: libc offers only a full qsort, which costs n log n where a
 * median needs n. */
#include "select.h"

static float select_kth(float *v, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        float pivot = v[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                float t = v[i];
                v[i] = v[j];
                v[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return v[k];
    }
    return v[k];
}

float uwb_median_float(float *v, size_t n)
{
    if (n == 0)
        return 0.0f;
    float upper = select_kth(v, n, n / 2);
    if (n % 2)
        return upper;
    /* Even count: the lower middle is the largest value below index n/2. */
    float lower = v[0];
    for (size_t i = 1; i < n / 2; i++)
        if (v[i] > lower)
            lower = v[i];
    return 0.5f * (lower + upper);
}
