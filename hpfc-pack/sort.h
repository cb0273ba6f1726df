/*
 * sort.h: an in-place sort for hpfc-pack's largest arrays (the millions of
 * snapped segments and their end points). Header-only.
 *
 * Why not qsort: glibc's qsort merges through a buffer as large as the
 * array whenever it fits in a quarter of the machine's memory, so sorting
 * the continental layer's segments (143 MB) took 143 MB more, at the read's
 * peak. This is an introsort: quicksort on the median of three (Hoare's
 * partition), insertion sort below 16 elements, heapsort past 2 log2(n)
 * levels, so O(n log n) in the worst case, O(log n) stack and no heap. Not
 * stable, which no caller needs: equal elements are identical here, so
 * the result is the same bytes however the work is shared out.
 * sort_in_place_threads sorts the two sides of a partition on two threads,
 * and so on while it has threads to give: the read's two largest sorts
 * would otherwise keep the second core idle.
 */
#ifndef HPFC_PACK_SORT_H
#define HPFC_PACK_SORT_H

#include <pthread.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

typedef int (*sort_cmp)(const void *, const void *);

enum { SORT_MAX_SIZE = 64, SORT_SMALL = 16 };

static inline char *sort_at(char *base, size_t i, size_t size)
{
    return base + i * size;
}

static inline void sort_swap(char *a, char *b, size_t size)
{
    char t[SORT_MAX_SIZE];
    memcpy(t, a, size);
    memcpy(a, b, size);
    memcpy(b, t, size);
}

static inline void sort_insertion(char *base, size_t n, size_t size, sort_cmp cmp)
{
    char t[SORT_MAX_SIZE];
    for (size_t i = 1; i < n; i++) {
        memcpy(t, sort_at(base, i, size), size);
        size_t j = i;
        for (; j > 0 && cmp(sort_at(base, j - 1, size), t) > 0; j--)
            memcpy(sort_at(base, j, size), sort_at(base, j - 1, size), size);
        memcpy(sort_at(base, j, size), t, size);
    }
}

static inline void sort_sift_down(char *base, size_t root, size_t n, size_t size, sort_cmp cmp)
{
    for (size_t child; (child = 2 * root + 1) < n; root = child) {
        if (child + 1 < n && cmp(sort_at(base, child, size), sort_at(base, child + 1, size)) < 0)
            child++;
        if (cmp(sort_at(base, root, size), sort_at(base, child, size)) >= 0)
            return;
        sort_swap(sort_at(base, root, size), sort_at(base, child, size), size);
    }
}

static inline void sort_heap(char *base, size_t n, size_t size, sort_cmp cmp)
{
    for (size_t i = n / 2; i-- > 0;)
        sort_sift_down(base, i, n, size, cmp);
    for (size_t end = n; end-- > 1;) {
        sort_swap(base, sort_at(base, end, size), size);
        sort_sift_down(base, 0, end, size, cmp);
    }
}

/* Hoare's partition around the median of the first, middle and last
 * elements: returns j with [0, j] <= pivot <= [j + 1, n), 0 <= j < n - 1. */
static inline size_t sort_partition(char *base, size_t n, size_t size, sort_cmp cmp)
{
    char *lo = base, *mid = sort_at(base, n / 2, size), *hi = sort_at(base, n - 1, size);
    if (cmp(mid, lo) < 0)
        sort_swap(mid, lo, size);
    if (cmp(hi, mid) < 0) {
        sort_swap(hi, mid, size);
        if (cmp(mid, lo) < 0)
            sort_swap(mid, lo, size);
    }
    char pivot[SORT_MAX_SIZE];
    memcpy(pivot, mid, size);
    size_t i = 0, j = n - 1;
    for (;;) { /* the median's neighbours stop both scans inside the array */
        while (cmp(sort_at(base, i, size), pivot) < 0)
            i++;
        while (cmp(pivot, sort_at(base, j, size)) < 0)
            j--;
        if (i >= j)
            return j;
        sort_swap(sort_at(base, i, size), sort_at(base, j, size), size);
        i++, j--;
    }
}

static inline void sort_intro(char *base, size_t n, size_t size, sort_cmp cmp, unsigned depth)
{
    while (n > SORT_SMALL) {
        if (depth-- == 0) {
            sort_heap(base, n, size, cmp);
            return;
        }
        size_t left = sort_partition(base, n, size, cmp) + 1, right = n - left;
        if (left < right) { /* recurse on the smaller side: O(log n) stack */
            sort_intro(base, left, size, cmp, depth);
            base = sort_at(base, left, size), n = right;
        } else {
            sort_intro(sort_at(base, left, size), right, size, cmp, depth);
            n = left;
        }
    }
    sort_insertion(base, n, size, cmp);
}

/* sort_intro's budget of levels before heapsort: 2 log2(n). */
static inline unsigned sort_depth(size_t n)
{
    unsigned depth = 0;
    for (size_t m = n; m > 1; m >>= 1)
        depth += 2;
    return depth;
}

/* Sorts n elements of `size` bytes in place (larger elements than
 * SORT_MAX_SIZE go to qsort). */
static inline void sort_in_place(void *base, size_t n, size_t size, sort_cmp cmp)
{
    if (size <= SORT_MAX_SIZE)
        sort_intro(base, n, size, cmp, sort_depth(n));
    else
        qsort(base, n, size, cmp);
}

/* Below this many elements a side is not worth a thread. */
enum { SORT_SPLIT_MIN = 1 << 15 };

typedef struct sort_share {
    char *base;
    size_t n, size, min_split;
    sort_cmp cmp;
    unsigned depth, threads;
} sort_share;

static inline void sort_split(const sort_share *s);

static inline void *sort_share_run(void *arg)
{
    sort_split(arg);
    return NULL;
}

/* s's elements on s->threads threads: partitioned once, the left side on a
 * new thread with half of them, the right side here with the rest. */
static inline void sort_split(const sort_share *s)
{
    if (s->threads < 2 || s->n < s->min_split || s->n <= SORT_SMALL || s->depth == 0) {
        sort_intro(s->base, s->n, s->size, s->cmp, s->depth);
        return;
    }
    size_t left = sort_partition(s->base, s->n, s->size, s->cmp) + 1;
    sort_share l = *s, r = *s;
    l.n = left, l.depth = r.depth = s->depth - 1, l.threads = s->threads / 2;
    r.base = sort_at(s->base, left, s->size), r.n = s->n - left, r.threads = s->threads - l.threads;
    pthread_t thread;
    if (pthread_create(&thread, NULL, sort_share_run, &l) != 0) { /* no thread: one after the other */
        l.threads = 1;
        sort_split(&l);
        sort_split(&r);
        return;
    }
    sort_split(&r);
    pthread_join(thread, NULL);
}

/* sort_in_place on up to `threads` threads (0 or 1: this one), each side
 * of a partition of at least `min_split` elements given a thread of its
 * own: the same bytes as sort_in_place. */
static inline void sort_in_place_split(void *base, size_t n, size_t size, sort_cmp cmp, unsigned threads,
                                       size_t min_split)
{
    if (size > SORT_MAX_SIZE) {
        qsort(base, n, size, cmp);
        return;
    }
    sort_share s = {base, n, size, min_split, cmp, sort_depth(n), threads};
    sort_split(&s);
}

static inline void sort_in_place_threads(void *base, size_t n, size_t size, sort_cmp cmp, unsigned threads)
{
    sort_in_place_split(base, n, size, cmp, threads, SORT_SPLIT_MIN);
}

#endif
