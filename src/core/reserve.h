/* reserve.h - growing arrays: the planner's, the spatial index's and the BVH's. */
#ifndef LIMEN_RESERVE_H
#define LIMEN_RESERVE_H

#include <limits.h>
#include <stdbool.h>
#include <stdlib.h>

/* Makes *p hold at least `need` elements of `size` bytes, doubling *cap (to exactly `need`
 * where doubling would pass INT_MAX); false (and *p untouched) when out of memory. */
static inline bool limen__reserve(void **p, int *cap, int need, size_t size)
{
    if (need <= *cap)
        return true;
    int n = *cap ? *cap : 16;
    while (n < need)
        n = n > INT_MAX / 2 ? need : n * 2;
    void *q = realloc(*p, size * (size_t)n);
    if (!q)
        return false;
    *p = q;
    *cap = n;
    return true;
}

#endif
