/*
 * sized.h: copying the public structs that can grow (hpfc.h, "Structs that
 * grow") between the library's own layout and a caller's, whose size is
 * that of the struct in the hpfc.h the caller was compiled with. Fields are
 * only ever appended, each at or past the struct's previous size, so the
 * bytes both sides know are a common prefix.
 */
#ifndef HPFC_SIZED_H
#define HPFC_SIZED_H

#include <stddef.h>
#include <string.h>

#include "hpfc.h"

/* Out: the library's struct (full, full_size bytes) into the caller's
 * `size` bytes. An older caller gets the fields it knows and nothing is
 * written past them; a newer caller's fields this library does not know
 * are zeroed. */
static inline void sized_out(void *dst, size_t size, const void *full, size_t full_size)
{
    memcpy(dst, full, size < full_size ? size : full_size);
    if (size > full_size)
        memset((char *)dst + full_size, 0, size - full_size);
}

/* In: the caller's struct of `size` bytes over *full, which holds the
 * defaults: an older caller's missing fields keep them. A newer caller's
 * fields this library does not know must be zero (their default, by the
 * rule of hpfc.h), else HPFC_E_ARG: a setting the library cannot honour
 * is refused, not ignored. */
static inline int sized_in(void *full, size_t full_size, const void *src, size_t size)
{
    const unsigned char *extra = (const unsigned char *)src + full_size;
    for (size_t k = full_size; k < size; k++)
        if (*extra++)
            return HPFC_E_ARG;
    memcpy(full, src, size < full_size ? size : full_size);
    return HPFC_OK;
}

#endif
