/*
 * scratch_array.h: the scratch arrays of the point locators (locate_point.c
 * and the batch, locate_batch.c), in one place: an array grown by doubling
 * and kept across points, and a short list of ids sorted into a set.
 */
#ifndef HPFC_SCRATCH_ARRAY_H
#define HPFC_SCRATCH_ARRAY_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "hpfc.h"

/* Room for n elements of `size` bytes in *p, which holds *cap: doubled from
 * *cap (16 at first) so that a run of points reallocates rarely.
 * HPFC_E_NOMEM leaves *p and *cap as they were. (build.c's reserve and
 * shapes.c's grow are the same but for their first size; not this
 * helper's files to change.) */
static inline int scratch_grow(void **p, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap)
        return HPFC_OK;
    size_t want = *cap ? *cap : 16;
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
