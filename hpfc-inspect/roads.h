/*
 * roads.h: what lies across a word pixel's roads, with the public reader API
 * only (spec/hpfc-format.md §3.4, §3.10).
 *
 * The library identifies crossings across roads inside its traversal
 * operators but keeps crossings hidden from applications. hpfc-inspect needs
 * them: to draw a crossing at the same place from both sides of a road, and
 * to count the stabbings an edge passes. Both rest on one fact (§3.5): the
 * two sides of a stretch of grid line list the same crossings in opposite
 * orders, and the shorter of two facing roads is never cut by the other
 * side's pixels.
 */
#ifndef HPFC_INSPECT_ROADS_H
#define HPFC_INSPECT_ROADS_H

#include <stdbool.h>

#include "hpfc.h"
#include "common/road.h" /* header-only: roads walked exactly as the reader walks them */
#include "word.h"

/* A pixel's lattice box [x0, x1) x [y0, y1): the library's (road.h, whose
 * extents, clockwise runs and lattice points along a road the tool uses). */
typedef road_box lbox;

/* Scratch for decoding words; one per thread. */
typedef struct roads {
    const hpfc_file *file;
    char *buf;
    size_t cap;
    uint64_t max_steps;  /* bound on any walk: all crossings of the file */
    word_info a, b;      /* the two words of a walk step */
} roads;

int roads_init(roads *r, const hpfc_file *file);
void roads_free(roads *r);

/* Decodes px's word into r->buf (valid until the next decode). */
int roads_word(roads *r, const hpfc_pixel *px, size_t *len);
/* Decodes and parses px's word (HPFC_E_CORRUPT if it breaks the grammar). */
int roads_parse(roads *r, const hpfc_pixel *px, word_info *wi);
/* Crossings on road `road` of word pixel px. */
int roads_count(roads *r, const hpfc_pixel *px, int road, uint32_t *count);

int roads_box(const hpfc_file *file, const hpfc_pixel *px, lbox *b);

/* The leaf touching b's road at position t along the line, on b's side
 * (across = false) or on the other side. HPFC_E_NO_PIXEL beyond the domain. */
int roads_leaf(const hpfc_file *file, const lbox *b, int road, int64_t t, bool across,
              hpfc_pixel *out, lbox *out_box);

/* Positions along the line (lattice units, fractional) of the c crossings on
 * road `road` of the leaf with box b, in word order. Every stretch of grid
 * line between two crossroads that both sides share is divided evenly among
 * its crossings, taken from the side whose road is that stretch, so both
 * sides of a road compute the same positions. */
int roads_positions(roads *r, const lbox *b, int road, uint32_t c, double *pos);

/* Crossing identification: crossing k (word index) of the leaf px, parsed in
 * wi, seen from across its road: the leaf *q and the crossing's word index
 * *m there. */
int roads_cross(roads *r, const hpfc_pixel *px, const word_info *wi, uint32_t k,
               hpfc_pixel *q, uint32_t *m);

/* Follows dart d (the out-dart of crossing d->crossing of the leaf holding
 * its origin) through the stabbings it passes to the leaf holding its
 * target. *stabbings counts them; *end (when non-NULL) receives the twin
 * dart: the target's leaf and the crossing where d arrives. */
int roads_walk(roads *r, const hpfc_dart *d, uint64_t *stabbings, hpfc_dart *end);

/* "i,j/i,j/..." of a pixel, into buf (cap >= 24 per level is enough). */
void pixel_path_text(const hpfc_pixel *px, char *buf, size_t cap);

#endif
