/*
 * word.h: a word pixel's word taken apart (spec/hpfc-format.md §3.6-§3.8,
 * §10), for hpfc-inspect's views and renderer.
 *
 * The library parses words too, but only behind its traversal operators;
 * the tool needs the parts themselves (which road a crossing lies on, which
 * component it belongs to), so it parses the symbols that hpfc_pixel_word()
 * returns with the one-pass stack of §3.8.
 */
#ifndef HPFC_INSPECT_WORD_H
#define HPFC_INSPECT_WORD_H

#include <stddef.h>
#include <stdint.h>

#define WORD_NONE UINT32_MAX

/* The parts of one word. Arrays grow with word_parse and belong to the
 * struct; word_info_free releases them. */
typedef struct word_info {
    uint32_t n;              /* crossings */
    uint32_t road_off[5];    /* first crossing of roads W, N, E, S; then n */
    uint32_t ncomp, nvert;   /* components; junctions (vertices) among them */
    char *sym;               /* per crossing: its symbol */
    uint32_t *comp;          /* per crossing: its component */
    uint32_t *comp_first;    /* per component: first crossing in word order */
    uint32_t *comp_last;     /* per component: last crossing in word order */
    uint32_t *comp_size;     /* per component: crossings (a junction's degree) */
    uint32_t *comp_vertex;   /* per component: local vertex id, WORD_NONE for a stabbing */
    uint32_t *stack;
    uint32_t cap;            /* capacity of the per-crossing arrays */
} word_info;

void word_info_free(word_info *wi);

/* Parses `len` symbols of "+=[]()Y". Returns 0, -1 on a word that breaks
 * the grammar (a corrupt file), -2 when out of memory. */
int word_parse(word_info *wi, const char *sym, size_t len);

/* Road (HPFC_WEST .. HPFC_SOUTH) of crossing k of a parsed word. */
int word_road_of(const word_info *wi, uint32_t k);

/* Crossings per road, straight from the symbols (no parse). */
void word_road_counts(const char *sym, size_t len, uint32_t counts[4]);

/* The §10 code of one symbol as text ("0", "1000", ...); "????" if unknown. */
const char *word_symbol_code(char symbol);

#endif
