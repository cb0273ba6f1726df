/*
 * arrays.h: the library's growable arrays, in one place (an array grown by
 * doubling, with its capacity beside it), and the point locators' short
 * sorted id sets (locate_point.c, locate_batch.c).
 */
#ifndef HPFC_ARRAYS_H
#define HPFC_ARRAYS_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "hpfc.h"

/* Room for n elements of `size` bytes in *p, which holds *cap: doubled
 * from *cap (from `first` when empty) so that a run of appends reallocates
 * rarely. HPFC_E_NOMEM (also for a size that would overflow) leaves *p and
 * *cap as they were. */
static inline int array_reserve(void **p, size_t *cap, size_t n, size_t size, size_t first)
{
    if (n <= *cap)
        return HPFC_OK;
    size_t want = *cap ? *cap : first;
    while (want < n) {
        if (want > SIZE_MAX / 2 / size)
            return HPFC_E_NOMEM;
        want *= 2;
    }
    void *q = realloc(*p, want * size);
    if (!q)
        return HPFC_E_NOMEM;
    *p = q;
    *cap = want;
    return HPFC_OK;
}

/* array_reserve from 16 elements: the point locators' scratch arrays,
 * kept across points, and the shapes' arrays. */
static inline int array_grow(void **p, size_t *cap, size_t n, size_t size)
{
    return array_reserve(p, cap, n, size, 16);
}

/* Sorts v[0 .. n) ascending and drops repeats; returns the new length.
 * The lists are a leaf's faces or their features: a handful, so insertion
 * sort. */
static inline size_t scratch_sort_unique(uint64_t *v, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint64_t t = v[i];
        size_t j = i;
        for (; j > 0 && v[j - 1] > t; j--)
            v[j] = v[j - 1];
        v[j] = t;
    }
    size_t u = 0;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || v[u - 1] != v[i])
            v[u++] = v[i];
    return u;
}

#endif
