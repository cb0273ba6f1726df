/*
 * face_witness.h: for every face of a freshly built map, a point the file
 * proves to lie inside it (spec/hpfc-format.md §7.1, "What a feature
 * covers"), so that hpfc-pack can ask which source features cover the face.
 *
 * Two kinds of places are inside a face by the file's own rules:
 *   - a private leaf lies wholly in one face: its centre is a witness, as
 *     far from every edge as half the leaf's smaller side;
 *   - in a word leaf, the stretch of the leaf's boundary between two
 *     consecutive crossings lies in the face on the right of the first
 *     one's out-dart (§3.11 rule 2): its middle is a witness, nudged by a
 *     tiny amount across the road the way the perturbation rule of §3.5
 *     moves the road, so that it never sits on an edge lying along the road.
 * Each face keeps its best witness: the centre of its largest private leaf,
 * else the middle of its longest stretch. Coordinates are long doubles in
 * lattice units, exact to far below one lattice unit.
 */
#ifndef HPFC_PACK_FACE_WITNESS_H
#define HPFC_PACK_FACE_WITNESS_H

#include <stdint.h>

#include "hpfc.h"

typedef struct face_witness {
    long double x, y;   /* lattice units */
    long double reach;  /* how far the witness is known (or guessed) to be
                           from the face's edges; 0 when the face has none */
} face_witness;

/* What the witnesses need of the tree, so that it can be freed before the
 * faces are numbered (their flood fill sets a pack's peak memory): the
 * input segment of every crossing of every word leaf, leaves in
 * hpfc_leaf_first / hpfc_leaf_next order, each leaf's crossings in its
 * word's order. 8 bytes a crossing. */
typedef struct leaf_crossings {
    uint32_t *pairs; /* crossing c: edge pairs[2c], segment pairs[2c + 1] */
    uint64_t count;
    size_t cap; /* pairs allocated */
} leaf_crossings;

/* Fills *out for the map `file`, serialised from `tree`. HPFC_OK,
 * HPFC_E_NOMEM, or HPFC_E_CORRUPT if the two disagree. */
int leaf_crossings_collect(const hpfc_tree *tree, const hpfc_file *file, leaf_crossings *out);
void leaf_crossings_free(leaf_crossings *lc);

/* Fills w[0 .. hpfc_faces_count(faces)) for the map `file`, built from
 * `graph`, whose crossings `lc` holds. HPFC_OK, or the status of a failing
 * call (HPFC_E_CORRUPT if the three disagree). */
int face_witnesses(const hpfc_graph *graph, const leaf_crossings *lc, const hpfc_file *file,
                   const hpfc_faces *faces, face_witness *w);

#endif
