/*
 * noded_paths.h: the path each input segment took through GEOS's noding,
 * for hpfc-pack's GIS input (gis_input.c) and the faces' features
 * (face_link.h).
 *
 * GEOS's snap-rounding union cuts a segment at every hot pixel (a vertex or
 * a rounded crossing) its unit square around the pixel's centre meets, and
 * routes the pieces through those centres, so the segment a -> b becomes a
 * chain of the output's segments from a to b whose points all lie in squares
 * the segment meets. The union keeps no trace of which input made which
 * piece, and knowing it is what links faces to features exactly: a ring's
 * area is what its path through the map encloses. So the path is found
 * again here, from the output alone: a walk from a over the output's
 * segments, each step to a point whose unit square meets a -> b (an exact
 * integer test) and which lies further along the segment, in GEOS's own
 * order of nodes along a segment (octant by octant, major coordinate
 * first), the nearest such point first, backtracking at dead ends.
 *
 * Any walk found is a chain of the map's segments from a to b within the
 * segment's snap tube (every point within sqrt(2)/2 of a unit of it), so a
 * ring rewritten with it is a closed walk in the map that encloses what the
 * source ring encloses, up to that band: where GEOS's own choice at a
 * square's edge differs, both paths lie in the band.
 */
#ifndef HPFC_PACK_NODED_PATHS_H
#define HPFC_PACK_NODED_PATHS_H

#include <stddef.h>
#include <stdint.h>

#include "segnode.h"

typedef struct noded_index noded_index;

/* An index over segs[0 .. n) (sorted as segnode_sort orders them, distinct,
 * each with a < b): noding's output. segs is not copied and must outlive
 * the index. 0, or -1 when memory runs out. */
int noded_index_create(const segnode_seg *segs, size_t n, noded_index **out);
void noded_index_free(noded_index *ix);

/* Is (ax, ay)-(bx, by), in either direction, one of the segments? */
int noded_index_has(const noded_index *ix, int64_t ax, int64_t ay, int64_t bx, int64_t by);

/* A growable list of lattice points (x, y pairs). */
typedef struct point_list {
    int64_t *xy;
    size_t n, cap;
} point_list;

int point_list_push(point_list *l, int64_t x, int64_t y);

/* Appends to out the points after (ax, ay) of a path from (ax, ay) to
 * (bx, by) through the index's segments, within the segment's snap tube
 * (see above); (bx, by) last. 0; 1 when there is none (out is then as it
 * was); -1 when memory runs out. */
int noded_path(const noded_index *ix, int64_t ax, int64_t ay, int64_t bx, int64_t by,
               point_list *out);

/* Does the closed unit square centred on lattice point (qx, qy) meet the
 * segment (ax, ay)-(bx, by)? Exact. */
int noded_square_meets(int64_t qx, int64_t qy, int64_t ax, int64_t ay, int64_t bx, int64_t by);

#endif
