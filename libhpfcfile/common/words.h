/*
 * words.h: a word, the string of symbols "+=[]()Y" of a word pixel
 * (spec/hpfc-format.md §3.6-§3.8, §5.2.3), in one place: the symbol a
 * crossing gets (the builder), the fixed code of §5.2.3 measured and written
 * (the writer) and decoded into symbols (the reader), the grammar parsed
 * into components (the traversal, faces, hpfc-inspect) and the crossings
 * counted per road.
 *
 * The compact pool's word code (spec §5.3.4) lives with its layout instead
 * (common/pool_code.h, read/pool_read.c, write/pool_write.c): it is a
 * different code (a symbol's bits depend on the symbol before it, and the
 * fourth '+' is not stored), and each pool layout keeps its own code next
 * to the layout that stores it, as this file keeps the paper layout's.
 * Here: the grammar (common/words.c), the code read (read/words_read.c)
 * and written (write/words_write.c).
 *
 * Internal to the library; hpfc-inspect compiles words.c into itself
 * (hpfc-inspect/meson.build), as the shared library does not export it.
 */
#ifndef HPFC_WORDS_H
#define HPFC_WORDS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "format.h"

/* No index: a stabbing's vertex, a component not open. */
#define WORD_NONE UINT32_MAX

/* ---- encoding ---- */

/* The symbol of a crossing of a component (§3.7): a stabbing's first and
 * second crossing '[' and ']'; a junction of degree 1 '='; else its first
 * '(', last ')', any other 'Y'. `seen`: this crossing is the component's
 * seen-th in word order (1 = first); `size`: its crossings. */
static inline char word_crossing_symbol(bool junction, uint32_t seen, uint32_t size)
{
    if (!junction)
        return seen == 1 ? '[' : ']';
    if (size == 1)
        return '=';
    return seen == 1 ? '(' : seen == size ? ')' : 'Y';
}

/* Bits of a word's fixed code (§5.2.3: '+' one bit, any other symbol four);
 * 0 when the word is not symbols ending at their fourth '+' (the builder
 * never makes one). */
uint64_t word_code_bits(const char *word, uint32_t len);

/* Writes a word's fixed code at bit `off` of a zeroed pool (a '+' is a 0
 * bit, so only the other symbols are written). For a word word_code_bits
 * accepted: it writes that many bits. */
void word_encode_code(uint8_t *pool, uint64_t off, const char *word, uint32_t len);

/* ---- decoding ---- */

/* Decodes the fixed-code word (§5.2.3) in the word_bits-bit slot at bit `off`
 * of `pool`, symbol by symbol up to its fourth '+'. Stores the first `cap`
 * symbols when buf is non-NULL; *len gets the full length. HPFC_E_CORRUPT
 * for a slot without a fourth '+' or with a reserved code, HPFC_E_ARG when
 * the word is longer than cap. */
int word_decode_code(const format_bits *pool, uint64_t off, uint32_t word_bits, char *buf,
                     size_t cap, size_t *len);

/* ---- parsing ---- */

/* The parsed structure of one word. Arrays hold `cap` crossings
 * (word_parts_alloc); components never outnumber crossings. */
typedef struct word_parts {
    uint32_t n;              /* crossings */
    uint32_t road_off[5];    /* first crossing of roads W, N, E, S; then n */
    uint32_t ncomp, nvert;   /* components; junctions (vertices) among them */
    uint32_t *comp;          /* per crossing: its component */
    uint32_t *pred, *succ;   /* per crossing, cyclic within its component */
    uint32_t *comp_vertex;   /* per component: local vertex, WORD_NONE for a stabbing */
    uint32_t *comp_first;    /* per component: first crossing (word order) */
    uint32_t *comp_last;     /* per component: last crossing (word order) */
    uint32_t *comp_size;     /* per component: crossings (a junction's degree) */
    uint32_t *vertex_comp;   /* per local vertex: its component */
    uint32_t *stack;         /* the open groups while parsing */
    uint32_t cap;
} word_parts;

/* Arrays for words of up to `cap` crossings: HPFC_OK or HPFC_E_NOMEM (then
 * word_parts_free still applies). */
int word_parts_alloc(word_parts *wp, uint32_t cap);
void word_parts_free(word_parts *wp);

/* The same arrays in the caller's memory, WORD_PARTS_MEM(cap) uint32_t at
 * mem (no word_parts_free then): for a caller that parses one short word
 * per call (the labels, labels.h) and keeps it on its stack, no malloc. */
#define WORD_PARTS_MEM(cap) (9 * ((size_t)(cap) + 1))
void word_parts_place(word_parts *wp, uint32_t *mem, uint32_t cap);

/* Parses `len` symbols with the one-pass stack of §3.8: HPFC_OK, or
 * HPFC_E_CORRUPT for anything but four roads, each ended by '+', of
 * symbols of "=[]()Y" whose groups nest and close ('Y' and ')' only in a
 * junction's group, ']' only in a stabbing's), or for more crossings than
 * the arrays hold. On HPFC_E_CORRUPT only n and road_off hold (as
 * word_count_roads gives them, the part that does not depend on the
 * grammar). */
int word_parse_symbols(word_parts *wp, const char *sym, size_t len);

/* ---- counting ---- */

/* Offsets of the crossings of each road, as word_parse_symbols' road_off, and
 * their number road_off[4], grammar or not; roads after the last '+' are
 * empty. */
void word_count_roads(const char *sym, size_t len, uint32_t road_off[5]);

/* Crossings on road `road` (0..3) of a word. */
uint32_t word_road_count(const char *sym, size_t len, int road);

/* The road (0..3, as enum hpfc_direction) of crossing k, from road_off. */
static inline int word_road_of_crossing(const uint32_t road_off[5], uint32_t k)
{
    int road = 0;
    while (road < 3 && k >= road_off[road + 1])
        road++;
    return road;
}

#endif
