/*
 * word.h: a word pixel's word taken apart (spec/hpfc-format.md §3.6-§3.8,
 * §5.2.3), for hpfc-inspect's views and renderer.
 *
 * The parse is the library's (hpfc_word_parse, hpfc.h's experimental
 * tier): this layer keeps the parts under the names the views use, names
 * each crossing's symbol, and spells the §5.2.3 codes as text.
 */
#ifndef HPFC_INSPECT_WORD_H
#define HPFC_INSPECT_WORD_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc.h"

#define WORD_NONE HPFC_WORD_NONE

/* The parts of one word: the library's parse (arrays owned by `parser`)
 * and each crossing's symbol. A zeroed struct is ready; word_parse grows
 * it to any word's length; word_info_free releases it. */
typedef struct word_info {
    uint32_t n;              /* crossings */
    uint32_t road_off[5];    /* first crossing of roads W, N, E, S; then n */
    uint32_t ncomp, nvert;   /* components; junctions (vertices) among them */
    char *sym;               /* per crossing: its symbol */
    const uint32_t *comp;        /* per crossing: its component */
    const uint32_t *comp_first;  /* per component: first crossing in word order */
    const uint32_t *comp_last;   /* per component: last crossing in word order */
    const uint32_t *comp_size;   /* per component: crossings (a junction's degree) */
    const uint32_t *comp_vertex; /* per component: local vertex id, WORD_NONE for a stabbing */
    hpfc_word_parser *parser;
    size_t sym_cap;
} word_info;

void word_info_free(word_info *wi);

/* Parses `len` symbols of "+=[]()Y". Returns 0, -1 on a word that breaks
 * the grammar (a corrupt file), -2 when out of memory. */
int word_parse(word_info *wi, const char *sym, size_t len);

/* Road (HPFC_WEST .. HPFC_SOUTH) of crossing k of a parsed word. */
int word_road_of(const word_info *wi, uint32_t k);

/* Crossings per road, straight from the symbols (no parse). */
void word_road_counts(const char *sym, size_t len, uint32_t counts[4]);

/* The §5.2.3 code of one symbol as text ("0", "1000", ...); "????" if unknown. */
const char *word_symbol_code(char symbol);

#endif
