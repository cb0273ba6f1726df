/*
 * segnode.h: which lattice segments need noding, decided exactly on
 * integers, for hpfc-pack's GIS input (gis_input.c).
 *
 * A layer built topologically (shared borders stored bit-identically, as in
 * census or Natural Earth boundaries) is already a planar graph once its
 * segments are snapped to the lattice and the duplicates removed: no two
 * segments meet but at a shared end. Handing millions of such segments to
 * GEOS's snap-rounding union costs minutes and gigabytes for nothing, so
 * gis_input.c first asks which segments meet another otherwise (a crossing,
 * an end on another's interior, an overlap) and nodes only those.
 */
#ifndef HPFC_PACK_SEGNODE_H
#define HPFC_PACK_SEGNODE_H

#include <stddef.h>
#include <stdint.h>

/* A segment between lattice points, with (ax, ay) < (bx, by)
 * lexicographically; coordinates within +-2^40. */
typedef struct segnode_seg {
    int64_t ax, ay, bx, by;
} segnode_seg;

/* A lattice point, and the order segnode_seg's ends follow: x, then y. */
typedef struct segnode_pt {
    int64_t x, y;
} segnode_pt;

static inline int segnode_pt_cmp(const void *a, const void *b)
{
    const segnode_pt *p = a, *q = b;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    return (p->y > q->y) - (p->y < q->y);
}

/* Sets dirty[i] to 1 for every segment s[i] that meets another segment
 * other than at an end point of both, leaving the others as they are (so a
 * caller can pre-mark segments). The segments must be distinct and
 * non-degenerate. Buckets the segments in a uniform grid and tests the pairs
 * that share a cell with exact orientation tests (128-bit products); a
 * segment whose box covers too many cells is marked dirty without tests.
 * The cells are tested on up to `threads` threads (the same marks on any
 * number). Returns the number of dirty segments, or -1 when memory runs
 * out. */
long long segnode_find_dirty(const segnode_seg *s, size_t n, unsigned char *dirty,
                             unsigned threads);

/* 1 when a segment of all[0 .. n) meets one of fresh[0 .. m) other than at
 * an end point of both (a segment of all equal to a fresh one is that one,
 * not tested against itself), or when a fresh segment, or a segment of all
 * near them, covers too many cells of the fresh segments' grid to be tested
 * (as segnode_find_dirty marks it); 0 when none does; -1 when memory runs
 * out. The pairs within all are not tested: after segnode_find_dirty, the
 * segments it left clean meet none but at shared ends, so a graph made of
 * them and of freshly noded segments is planar iff this gives 0, at a cost
 * that follows n plus the pairs near the fresh segments, not a second pass
 * over every cell. */
int segnode_any_near(const segnode_seg *fresh, size_t m, const segnode_seg *all, size_t n);

/* Does segment a meet segment b other than at an end point of both? Exact. */
int segnode_interact(const segnode_seg *a, const segnode_seg *b);

#endif
