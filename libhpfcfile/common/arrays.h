/*
 * arrays.h: the library's growable arrays, in one place (an array grown by
 * doubling, with its capacity beside it), the point locators' short
 * sorted id sets (locate_point.c, locate_batch.c), and a sort of items by
 * 32-bit keys (the batch's points in Morton order, the shapes' darts by
 * vertex), and of ids below a bound (a window's lists).
 */
#ifndef HPFC_ARRAYS_H
#define HPFC_ARRAYS_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

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

/* Insertion sort of v[0 .. n) ascending: for the short lists below. */
static inline void insertion_sort_u64(uint64_t *v, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint64_t t = v[i];
        size_t j = i;
        for (; j > 0 && v[j - 1] > t; j--)
            v[j] = v[j - 1];
        v[j] = t;
    }
}

/* Sorts v[0 .. n) ascending and drops repeats; returns the new length.
 * The lists are a leaf's faces or their features: a handful, so insertion
 * sort. */
static inline size_t scratch_sort_unique(uint64_t *v, size_t n)
{
    insertion_sort_u64(v, n);
    size_t u = 0;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || v[u - 1] != v[i])
            v[u++] = v[i];
    return u;
}

/* An item to sort: its key and its index among the caller's items. */
typedef struct key_item {
    uint32_t key, index;
} key_item;

/* items[0 .. n) sorted by key, stably, tmp (n items) as scratch: insertion
 * sort for a few, else LSD radix a byte a pass. */
static inline void key_sort(key_item *items, key_item *tmp, size_t n)
{
    if (n < 64) {
        for (size_t i = 1; i < n; i++) {
            key_item t = items[i];
            size_t j = i;
            for (; j > 0 && items[j - 1].key > t.key; j--)
                items[j] = items[j - 1];
            items[j] = t;
        }
        return;
    }
    for (unsigned byte = 0; byte < 4; byte++) {
        size_t count[257] = {0};
        for (size_t k = 0; k < n; k++)
            count[(items[k].key >> (8 * byte) & 0xFF) + 1]++;
        for (unsigned b = 0; b < 256; b++)
            count[b + 1] += count[b];
        for (size_t k = 0; k < n; k++)
            tmp[count[items[k].key >> (8 * byte) & 0xFF]++] = items[k];
        key_item *t = items;
        items = tmp, tmp = t; /* four passes: the result ends in `items` */
    }
}

/* ids[0 .. n), each below `bound`, sorted ascending, tmp (n ids) as
 * scratch: insertion sort for a few, else LSD radix a byte a pass, only
 * the bytes that ids below `bound` can have (a window's lists: thousands
 * of ids below a few million, three passes where qsort's comparisons cost
 * ten times more). */
static inline void id_sort(uint64_t *ids, uint64_t *tmp, size_t n, uint64_t bound)
{
    if (n < 64) {
        insertion_sort_u64(ids, n);
        return;
    }
    uint64_t *from = ids, *to = tmp;
    for (unsigned byte = 0; byte < 8 && (bound - 1) >> (8 * byte); byte++) {
        size_t count[257] = {0};
        for (size_t k = 0; k < n; k++)
            count[(from[k] >> (8 * byte) & 0xFF) + 1]++;
        for (unsigned b = 0; b < 256; b++)
            count[b + 1] += count[b];
        for (size_t k = 0; k < n; k++)
            to[count[from[k] >> (8 * byte) & 0xFF]++] = from[k];
        uint64_t *t = from;
        from = to, to = t;
    }
    if (from != ids)
        memcpy(ids, from, n * sizeof *ids);
}

#endif
