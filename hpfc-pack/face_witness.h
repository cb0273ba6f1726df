/*
 * face_witness.h: for every face of a freshly built map, a point the file
 * proves to lie inside it (spec/hpfc-format.md §6.2.3, "What a feature
 * covers"), exactly, so that hpfc-pack can ask which source features cover
 * the face and check what the walk over the faces found (face_link.h).
 *
 * Two kinds of places are inside a face by the file's own rules:
 *   - a private leaf lies wholly in one face and no edge enters it: its
 *     centre, a point of half-integer lattice coordinates;
 *   - in a word leaf, the stretch of the leaf's boundary after a crossing
 *     lies in the face the file names for that crossing's dart (§3.11
 *     rule 2), and that face lies on one side of the crossing's segment all
 *     along it: the segment's midpoint, moved an infinitesimal step to that
 *     side (symbolically, so that every test on it stays exact).
 * A face gets the centre of a private leaf where it has one, else a
 * crossing's midpoint.
 */
#ifndef HPFC_PACK_FACE_WITNESS_H
#define HPFC_PACK_FACE_WITNESS_H

#include <stdint.h>

#include "hpfc.h"

typedef struct face_witness {
    int64_t x2, y2; /* the point, in doubled lattice coordinates (2x, 2y) */
    int64_t nx, ny; /* and the direction of its infinitesimal step ((0, 0): none) */
    int kind;       /* FACE_WITNESS_NONE, _SEGMENT or _LEAF */
} face_witness;

enum { FACE_WITNESS_NONE, FACE_WITNESS_SEGMENT, FACE_WITNESS_LEAF };

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

/* Fills w[0 .. hpfc_faces_face_count(faces)) for the map `file`, built from
 * `graph`, whose crossings `lc` holds. HPFC_OK, or the status of a failing
 * call (HPFC_E_CORRUPT if the three disagree). */
int face_witnesses(const hpfc_graph *graph, const leaf_crossings *lc, const hpfc_file *file,
                   const hpfc_faces *faces, face_witness *w);

/* Does the eastward ray from witness w cross lattice segment (ux, uy) -
 * (vx, vy)? 1 or 0, by exact integer tests, with the half-open rule on y
 * (a ring's vertex on the ray counts once); -1 when w lies on the segment,
 * which a witness never does on a segment of the map. */
int face_witness_ray_crosses(const face_witness *w, int64_t ux, int64_t uy, int64_t vx,
                             int64_t vy);

#endif
