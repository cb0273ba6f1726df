/*
 * grow.h: amortised growth of a malloc'ed array, for the tools (hpfc-pack's
 * readers, hpfc-inspect's queries and renderer). Header-only.
 */
#ifndef HPFC_TOOLS_GROW_H
#define HPFC_TOOLS_GROW_H

#include <stdint.h>
#include <stdlib.h>

/* Makes *p (of *cap elements of `size` bytes) hold at least `need`,
 * doubling; 1 on success, 0 when memory or size_t runs out (*p is then
 * unchanged). */
static inline int array_grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 1;
    size_t c = *cap ? *cap : 16;
    while (c < need) {
        if (c > SIZE_MAX / 2)
            return 0;
        c *= 2;
    }
    if (c > SIZE_MAX / size)
        return 0;
    void *np = realloc(*p, c * size);
    if (!np)
        return 0;
    *p = np;
    *cap = c;
    return 1;
}

/* Gives back the tail of an array that shrank to n elements (p itself when
 * realloc will not). */
static inline void *array_shrink(void *p, size_t n, size_t size)
{
    void *q = realloc(p, (n ? n : 1) * size);
    return q ? q : p;
}

#endif
