/*
 * face_link.h: which source features each face and each edge of a freshly
 * built map belong to, derived from the map's topology in time near-linear
 * in the size of the map, whatever the nesting of the rings.
 *
 * The features' parts are recorded as they lie in the map (gis_features.h:
 * where noding moved a segment, its path through the noded segments), so
 * every segment of a ring is a segment of some edge. Crossing an edge from
 * one face to the other changes a point's parity with respect to feature f
 * exactly when f's rings run along the edge an odd number of times
 * (even-odd rule); along an edge that parity is the same on every segment,
 * since a closed walk through a point of degree 2 leaves it by the other
 * segment or turns back along the same one. So, starting from the
 * unbounded face (inside no feature), each face's features follow from a
 * neighbour's by a symmetric difference with the features toggled by the
 * edge between them: a breadth-first walk over face adjacency.
 *
 * The walk's answer is checked face by face against each face's witness
 * point (face_witness.h, face_check.h), which is the exact answer on its
 * own; gis_features.c compares the two.
 *
 * Every segment of a part also links the part's feature to the segment's
 * edge (line layers, and the rings' borders).
 */
#ifndef HPFC_PACK_FACE_LINK_H
#define HPFC_PACK_FACE_LINK_H

#include <stddef.h>
#include <stdint.h>

#include "face_witness.h"
#include "gis_features.h"
#include "hpfc.h"

typedef struct face_link {
    uint64_t faces;
    uint32_t edges;
    /* per face: its feature set pool[set_off[f] .. + set_len[f]), valid when reached[f] */
    uint64_t *set_off;
    uint32_t *set_len;
    uint8_t *reached;
    uint32_t *pool;
    size_t pool_n, pool_cap;
    /* per edge: the features it toggles, toggle[toggle_start[e] .. toggle_start[e + 1]),
       ascending */
    uint32_t *toggle_start, *toggle;
    /* per edge: its two faces (UINT32_MAX when no crossing names it) */
    uint32_t *side_a, *side_b;
    /* face adjacency: adj[adj_start[f] .. adj_start[f + 1]) edge ids */
    uint64_t *adj_start;
    uint32_t *adj;
    /* per edge: every feature with a part along it, ascending */
    uint32_t *edge_start, *edge_feature;
    uint32_t *queue;
    uint64_t propagated; /* faces reached by the walk, the unbounded one included */
} face_link;

/* Matches the parts of fs to the edges of `graph` (the map of `file`,
 * whose crossings lc holds, whose faces are `faces`), finds each edge's
 * two faces and walks from the unbounded face. HPFC_OK, HPFC_E_NOMEM or
 * HPFC_E_CORRUPT (the inputs disagree: a part leaves the map). */
int face_link_run(face_link *fl, const gis_features *fs, const hpfc_graph *graph,
                  const leaf_crossings *lc, const hpfc_file *file, const hpfc_faces *faces);

void face_link_free(face_link *fl);

#endif
