/*
 * Independent checks of a built hPFC tree against its input graph, shared by
 * the builder tests. Each check recomputes what a pixel must hold from the
 * graph alone (all segments, no filtering) and compares it with the tree.
 */
#ifndef HPFC_TREE_ORACLE_H
#define HPFC_TREE_ORACLE_H

#include <stdbool.h>
#include <stddef.h>

#include "hpfc.h"

/* Calls fn for every pixel of every image of every level. */
typedef void (*pixel_fn)(const hpfc_tree *t, uint32_t level, size_t image, uint32_t i,
                         uint32_t j, const hpfc_tree_pixel *px, void *ctx);
void oracle_for_each_pixel(const hpfc_tree *t, pixel_fn fn, void *ctx);

/* Is the word well nested (rpfc-operators §2), with exactly four '+' and
 * the fourth last? */
bool oracle_word_is_valid(const char *word, size_t len);

/* Runs every check of the tree against the graph, built with the bound
 * max_leaf_points on shape points per leaf (0: none; spec §3.9 rule 3);
 * returns the number of failures (each printed to stderr with the pixel
 * concerned). */
int oracle_check_tree(const hpfc_graph *g, const hpfc_tree *t, uint32_t max_leaf_points);

/* Checks that the flat rPFC `flat` and the hPFC `tree` of the same graph
 * describe the same crossings, in the same order, on every road of every
 * leaf of the hPFC. Returns the number of failures. */
int oracle_compare_flat(const hpfc_tree *flat, const hpfc_tree *tree);

/* The leaf word pixel containing lattice point (x, y) (half-open cells);
 * returns false when outside the domain. */
bool oracle_locate(const hpfc_tree *t, int64_t x, int64_t y, hpfc_tree_pixel *out,
                   uint32_t *level);

/* Number of crossings of each road of a word (W, N, E, S). */
void oracle_road_counts(const char *word, size_t len, size_t counts[4]);

#endif
