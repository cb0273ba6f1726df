/*
 * mesh_graph.h: a triangle mesh as a planar graph on hpfc's integer lattice.
 *
 * hpfc-pack's Draco input (draco_input.h) decodes a mesh and hands its
 * positions and triangles here; this part is pure C and knows nothing of
 * Draco, so the unit tests (tests/tools/test_mesh.c) drive it directly.
 *
 * The graph is the set of triangle edges, each shared edge once, in x, y: z
 * and any further position component are ignored. hpfc-pack/README.md
 * ("Meshes") explains the choices; in short:
 *
 *   - Lattice. Each coordinate is mapped to round(v / 10^e), rounding half
 *     away from zero, computed exactly from the double's binary value with
 *     integer arithmetic. The unit 10^e is the coarsest one that represents
 *     every used coordinate exactly when such a unit fits the lattice (so a
 *     mesh with integer coordinates keeps e = 0), else the finest unit in
 *     which the bounding box spans at most 2^34 lattice units.
 *   - Merges. Points that land on one lattice point are one vertex; every
 *     later decision (degenerate, collinear, sides) uses lattice integers only.
 *   - Triangles with two corners on one vertex are dropped, and so are repeats
 *     of a triangle (same three vertices, either winding). A triangle whose
 *     three distinct corners are collinear is dropped too, and its long side,
 *     where another triangle has it, is split at the middle corner.
 *   - The mesh is not noded: two triangles on the same side of a shared edge
 *     (a fold) and edges that cross or touch (hpfc_graph_validate) are
 *     rejected with HPFC_E_NONPLANAR and a message naming the mesh points.
 *
 * Points are named in messages by their index in the caller's arrays (for a
 * merged vertex, the lowest index that landed on it).
 */
#ifndef HPFC_PACK_MESH_GRAPH_H
#define HPFC_PACK_MESH_GRAPH_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Range of lattice unit exponents mesh_graph uses (inside the graph's
 * [-30, 30]): 5^27 < 2^63 keeps the exact conversion in 128-bit integers. */
#define MESH_UNIT_EXP10_MIN (-27)
#define MESH_UNIT_EXP10_MAX 27

/* The automatic unit is the finest one in which the bounding box spans at
 * most 2^MESH_EXTENT_BITS lattice units (and every coordinate stays within
 * HPFC_COORD_MAX). Such a unit is below 10 * extent / 2^34 < extent / 2^30:
 * finer than Draco's finest quantization step (30 bits over the largest of
 * the x, y, z ranges), so dequantized positions a step apart never merge. */
#define MESH_EXTENT_BITS 34

typedef struct mesh_graph_options {
    int fixed_unit;       /* nonzero: use unit_exp10 instead of choosing one */
    int32_t unit_exp10;   /* in [MESH_UNIT_EXP10_MIN, MESH_UNIT_EXP10_MAX] */
} mesh_graph_options;

/* What the conversion did, for reports and tests. */
typedef struct mesh_graph_stats {
    int32_t unit_exp10;          /* the lattice unit used */
    int exact;                   /* every used coordinate is on the lattice */
    size_t points_used;          /* points some triangle refers to */
    size_t merged_points;        /* used points on the lattice point of a lower one */
    size_t degenerate_triangles; /* dropped: two corners on one vertex */
    size_t duplicate_triangles;  /* dropped: a repeat of an earlier triangle */
    size_t collinear_triangles;  /* dropped: three distinct collinear corners */
    size_t split_edges;          /* long sides split at a collinear middle corner */
    size_t vertices, edges;      /* of the graph */
} mesh_graph_stats;

/* Builds the planar graph of a triangle mesh.
 *
 * pos holds npoints points of dims (>= 2) doubles each: x, y, then components
 * that are ignored. tri holds ntri triangles of 3 point indices. Only points
 * some triangle refers to matter; the others may hold anything. opts may be
 * NULL (automatic unit); stats may be NULL.
 *
 * On success *out is a new graph (free with hpfc_graph_free) that passed
 * hpfc_graph_validate. Otherwise *out is NULL, diag (when non-NULL) explains
 * in one line, and the status is one of HPFC_E_NOMEM, HPFC_E_ARG (dims < 2,
 * a bad fixed unit), HPFC_E_VERTEX_INDEX (an index >= npoints),
 * HPFC_E_EXTENT (a coordinate not finite or too large for the lattice),
 * HPFC_E_EMPTY (no triangle, or none left), HPFC_E_NONPLANAR, HPFC_E_LIMIT
 * (more than 2^32 - 1 points or edges). Safe on untrusted input. */
int mesh_graph_build(const double *pos, size_t dims, size_t npoints, const uint32_t *tri,
                     size_t ntri, const mesh_graph_options *opts, hpfc_graph **out,
                     mesh_graph_stats *stats, hpfc_diag *diag);

/* The lattice coordinate of v in units of 10^exp10: v / 10^exp10 rounded
 * half away from zero, exactly. HPFC_E_EXTENT when v is not finite or the
 * result exceeds HPFC_COORD_MAX in magnitude; HPFC_E_ARG when exp10 is
 * outside [MESH_UNIT_EXP10_MIN, MESH_UNIT_EXP10_MAX]. */
int mesh_lattice_coord(double v, int32_t exp10, int64_t *out);

/* Digits after the decimal point in the exact decimal expansion of a finite
 * v (0 for an integer; a double with binary exponent -k below the point has
 * exactly k). */
int mesh_decimal_digits(double v);

#ifdef __cplusplus
}
#endif

#endif
