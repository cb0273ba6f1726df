/* reader.h: navigation's internals (read.c) for the traversal, faces,
 * labels and geometry code: pixel paths from points, slot positions, and
 * layout-neutral views of the pools. What open checked and the file's
 * fields are in file.h. */
#ifndef HPFC_READER_H
#define HPFC_READER_H

#include <stdbool.h>

#include "hpfc.h"

/* Absolute bit position in the file of a word pixel's record or slot: a
 * unique, stable number per pixel. */
int reader_pixel_slot_bit(const hpfc_file *file, const hpfc_pixel *px, uint64_t *bit);
/* The same for a word pixel only: HPFC_E_ARG for a refined one. */
int reader_leaf_slot_bit(const hpfc_file *file, const hpfc_pixel *px, uint64_t *bit);
/* The image at bit `image` of `level`'s pool (the root image, 0, at level
 * 0), checked as a pixel access checks it: the whole image lies in the
 * pool and the last level has no refined pixel (HPFC_E_CORRUPT otherwise).
 * *bits: its size; *refined: its refined pixels. */
int reader_image_bits(const hpfc_file *file, uint32_t level, uint64_t image, uint64_t *bits,
                      uint64_t *refined);
/* Position of a scan over an image's refined pixels (start at {0, 0}). */
typedef struct reader_refined {
    uint64_t p;      /* next scanline index to look at */
    uint64_t before; /* refined pixels before p */
} reader_refined;
/* The next refined pixel of an image reader_image_bits accepted: its
 * scanline index and its child image's address (unchecked);
 * HPFC_E_NO_PIXEL after the last. */
int reader_next_refined(const hpfc_file *file, uint32_t level, uint64_t image, reader_refined *it,
                        uint32_t *pixel, uint64_t *address);
/* The word pixel of an image reader_image_bits accepted whose slot (record,
 * at level 0) starts at pool bit `bit`: its scanline index, or HPFC_E_ARG
 * when no word slot starts there. O(pixels of the image). */
int reader_word_at(const hpfc_file *file, uint32_t level, uint64_t image, uint64_t bit,
                   uint32_t *pixel);
/* A refined pixel's children with the pixel read once (hpfc_pixel_child
 * reads it again for each child): reader_child_image gives its child
 * image (HPFC_E_NO_PIXEL for a word pixel), reader_child then child (i, j)
 * of it, its path in *out and its type (HPFC_PIXEL_*), checked as
 * hpfc_pixel_child checks it. */
int reader_child_image(const hpfc_file *file, const hpfc_pixel *px, uint64_t *image);
int reader_child(const hpfc_file *file, const hpfc_pixel *px, uint64_t image, uint32_t i,
                 uint32_t j, hpfc_pixel *out, int *type);
/* What a walk over an image's children learnt of a word pixel (compact
 * layout): its rank among its level's leaves and its word's index in the
 * stream (UINT64_MAX: private); rank UINT64_MAX: nothing. */
typedef struct reader_leaf_at {
    uint64_t rank, word;
} reader_leaf_at;

/* The children of a refined pixel in the compact layout, counted once:
 * reader_children_begin reads the child image's type bits and the counts
 * before it, then reader_children_get gives child (i, j)'s path, type and
 * (a word pixel) its reader_leaf_at without another read of the counts.
 * Other layouts and images of more than 28 pixels go through reader_child
 * (the reader_leaf_at empty). px must outlive c. */
typedef struct reader_children {
    const hpfc_pixel *parent;
    uint64_t image, g0, refined, stabbed, pairs;
    bool counted;
} reader_children;
int reader_children_begin(const hpfc_file *file, const hpfc_pixel *px, reader_children *c);
int reader_children_get(const hpfc_file *file, const reader_children *c, uint32_t i, uint32_t j,
                        hpfc_pixel *out, int *type, reader_leaf_at *at);

/* Every leaf below a refined pixel, without a path per pixel (compact
 * layout only; HPFC_E_ARG otherwise). The subtree's pixels at each level
 * are one run of images: the child images of the refined pixels of the
 * run above, which are numbered by their refined rank, so consecutive
 * (§5.3). A scan reads each run's type pairs in pool order and gives its
 * leaves in that order, level by level: their ranks among their level's
 * leaves follow each other within a level. O(pixels of the subtree), one
 * block count read per level. reader_scan_next: HPFC_OK with a leaf,
 * HPFC_E_NO_PIXEL after the last, HPFC_E_CORRUPT where the type bits
 * contradict the level table. */
typedef struct reader_scan {
    uint32_t level;         /* the run's level */
    uint64_t g, end;        /* next pixel of the run and its end (level pixel indices) */
    uint64_t refined;       /* refined pixels of the level before g */
    uint64_t first_refined; /* ... before the run: the next run's first image */
} reader_scan;
int reader_scan_begin(const hpfc_file *file, const hpfc_pixel *px, reader_scan *sc);
/* The next leaf: its level, its rank among the level's leaves and whether
 * it is private (else stabbed). */
int reader_scan_next(const hpfc_file *file, reader_scan *sc, uint32_t *level, uint64_t *rank,
                     bool *is_private);

/* A word pixel's word, as hpfc_pixel_word gives it, and in the compact
 * layout its rank among its level's leaves (labels_leaf_rank's): from
 * `known` when a walk over its image counted them (NULL or empty: from one
 * read of its type bits' counts); *rank is UINT64_MAX when not computed
 * (the paper layout). */
int reader_leaf_word(const hpfc_file *file, const hpfc_pixel *leaf, const reader_leaf_at *known,
                     char *buf, size_t cap, size_t *len, uint64_t *rank);
/* hpfc_locate, from `near` (NULL: from the root): the levels where the
 * point lies in one of near's ancestors take near's path instead of reading
 * the pools again, so locating next to a known pixel costs the levels below
 * their common ancestor. The same answer as hpfc_locate when near's path is
 * the descent to its pixel (one the reader gave; a caller's made-up path is
 * trusted as it is by hpfc_pixel_move). out may be near. */
int reader_locate_near(const hpfc_file *file, const hpfc_pixel *near, int64_t x, int64_t y,
                       hpfc_pixel *out);
/* The end of level `level`'s image numbering: images are named 0 .. end
 * - 1 (paper: bit offsets in the pool, end = s^l; compact: indices, end =
 * the level's images), and reader_image_bits gives each one's extent. */
uint64_t reader_image_end(const hpfc_file *file, uint32_t level);
/* Compact only: the image holding the pixel whose type bits start at pool
 * bit `bit`; HPFC_E_ARG when none does (or the file is paper). */
int reader_slot_image(const hpfc_file *file, uint32_t level, uint64_t bit, uint64_t *image);
/* Slot positions of level `level` (pool-relative) divided by *unit are
 * distinct integers below *entries, one per pixel that has a slot. */
void reader_slot_grid(const hpfc_file *file, uint32_t level, uint64_t *unit, uint64_t *entries);
/* Compact layout: the word pixels of a level before unit u (an image, or
 * a root pixel), as the LABL rank samples count them. */
int reader_compact_words_before(const hpfc_file *file, uint32_t level, uint64_t unit,
                                uint64_t *words);

#endif
