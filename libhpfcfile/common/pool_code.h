/*
 * pool_code.h: what the compact pool's reader (read/pool_read.c) and writer
 * (write/pool_write.c) share: the word code's table (spec/hpfc-format.md
 * §5.3.4) and where a type block's counts lie. Internal to the library.
 */
#ifndef HPFC_POOL_CODE_H
#define HPFC_POOL_CODE_H

#include "pool.h"

/* The code of a symbol depends on its context, the last crossing symbol
 * before it in the word (the '+' do not change it): none yet, '[', '(' or
 * 'Y', or one that closes a group (']', ')', '='). In each context the
 * symbols the grammar (§3.8) allows there are listed by frequency on the
 * Delaunay and GIS maps measured for the issue; the k-th costs k + 1 bits,
 * k ones then a zero, the last one only its ones (spec §5.3.4).
 *
 * The table is indexed by context and by the number of leading ones of
 * the next bits (capped at 7: no code has more than 6), so the decoder
 * makes one lookup a symbol; the encoder searches the same table, which
 * is the code's only definition. */
enum { CTX_NONE, CTX_STABBING, CTX_JUNCTION, CTX_CLOSED };
typedef struct code_entry {
    char symbol;
    uint8_t bits;  /* length of its code */
    uint8_t next;  /* the context after it */
} code_entry;
#define CODE_ONES_CAP 7
/* A row a context: the rows share their layout, not their logic (each is
 * that context's own list of symbols by frequency). */
static const code_entry codes[4][CODE_ONES_CAP + 1] = {
    [CTX_NONE] = {{'[', 1, CTX_STABBING}, {'(', 2, CTX_JUNCTION}, {'+', 3, CTX_NONE},
                  {'=', 3, CTX_CLOSED}, {'=', 3, CTX_CLOSED}, {'=', 3, CTX_CLOSED},
                  {'=', 3, CTX_CLOSED}, {'=', 3, CTX_CLOSED}},
    [CTX_STABBING] = {{'+', 1, CTX_STABBING}, {']', 2, CTX_CLOSED}, {'[', 3, CTX_STABBING},
                      {'(', 4, CTX_JUNCTION}, {'=', 4, CTX_CLOSED}, {'=', 4, CTX_CLOSED},
                      {'=', 4, CTX_CLOSED}, {'=', 4, CTX_CLOSED}},
    [CTX_JUNCTION] = {{'+', 1, CTX_JUNCTION}, {'Y', 2, CTX_JUNCTION}, {')', 3, CTX_CLOSED},
                      {'[', 4, CTX_STABBING}, {'(', 5, CTX_JUNCTION}, {'=', 5, CTX_CLOSED},
                      {'=', 5, CTX_CLOSED}, {'=', 5, CTX_CLOSED}},
    [CTX_CLOSED] = {{'+', 1, CTX_CLOSED}, {']', 2, CTX_CLOSED}, {'[', 3, CTX_STABBING},
                    {'Y', 4, CTX_JUNCTION}, {')', 5, CTX_CLOSED}, {'(', 6, CTX_JUNCTION},
                    {'=', 6, CTX_CLOSED}, {'=', 6, CTX_CLOSED}},
};

/* The code of c in ctx (its first entry: k ones, then a zero unless it is
 * the all-ones code); its length, 0 when the context does not allow c. */
static inline unsigned symbol_code(int ctx, char c, uint64_t *value, int *next)
{
    for (unsigned k = 0; k <= CODE_ONES_CAP; k++)
        if (codes[ctx][k].symbol == c) {
            unsigned bits = codes[ctx][k].bits;
            *value = (((uint64_t)1 << k) - 1) << (bits - k);
            *next = codes[ctx][k].next;
            return bits;
        }
    return 0;
}

/* Where block b's counts start: after all the type pairs. */
static inline uint64_t pool_counts_bit(const pool_level *pl, uint64_t block)
{
    return 2 * pl->pixels + block * ((uint64_t)pl->refined_width + pl->stabbed_width);
}

#endif
