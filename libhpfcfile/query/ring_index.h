/*
 * ring_index.h: the indexes that keep geometry back from a file
 * (shapes.c) near-linear when a region has many rings: a packed R-tree
 * over ring boxes, to find the outer rings whose box holds a hole's, and a
 * packed interval tree over one ring's segments by their y extent, to test
 * a point against a ring of many points in O(log n + the segments the
 * point's row meets) instead of O(n). Both exact on lattice coordinates
 * (|x|, |y| below 2^42): boxes compare integers, the point test counts
 * crossings with 128-bit cross products, as point_in_ring in shapes.c.
 * Internal to the library.
 */
#ifndef HPFC_RING_INDEX_H
#define HPFC_RING_INDEX_H

#include <stddef.h>
#include <stdint.h>

/* ---- boxes ---- */

/* Levels of boxes, FANOUT to a node: level 0 the items' boxes in packed
 * order (item[k] the caller's index of entry k), each entry of level l + 1
 * the union of its children's. */
typedef struct box_tree {
    int64_t (**level)[4];
    size_t *count;
    int levels;
    uint32_t *item;
} box_tree;

/* Packs boxes b[0 .. n) (x0, y0, x1, y1; copied). HPFC_OK or HPFC_E_NOMEM;
 * no levels for n = 0. */
int box_tree_build(box_tree *t, const int64_t (*b)[4], size_t n);
void box_tree_free(box_tree *t);

/* Appends to *out (*n of *cap, grown) the items whose box contains the
 * box q. HPFC_OK or HPFC_E_NOMEM. */
int box_tree_containing(const box_tree *t, const int64_t q[4], uint32_t **out, size_t *n,
                        size_t *cap);

/* ---- one ring ---- */

typedef struct ring_index {
    const int64_t *xy;  /* the ring's points, closed (last == first), not owned */
    size_t n;
    uint32_t *seg;      /* segment k: xy[seg[k]] -> xy[seg[k] + 1], by y midpoint */
    int64_t **lo, **hi; /* per level: y extents, as the box tree's levels */
    size_t *count;
    int levels;
} ring_index;

/* Indexes the closed ring xy[0 .. n) (n >= 2), which must outlive it.
 * HPFC_OK or HPFC_E_NOMEM. */
int ring_index_build(ring_index *ri, const int64_t *xy, size_t n);
void ring_index_free(ring_index *ri);

/* Where the point p (doubled lattice coordinates: 2x, 2y) lies: 1 inside
 * the ring, 0 outside, -1 on it. */
int ring_index_locate(const ring_index *ri, const int64_t p[2]);

/* The same without an index, over the n points of a closed ring. */
int ring_locate(const int64_t *xy, size_t n, const int64_t p[2]);

#endif
