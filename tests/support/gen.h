/*
 * gen.h: deterministic generators of valid planar test graphs.
 *
 * Every generator is a pure function of its arguments: the same seed gives
 * the same graph on every machine. Randomness comes from a seeded
 * xoshiro256** stream (never rand()), and no floating-point value decides
 * anything: geometric decisions use exact integer predicates, and the only
 * double argument (a removal fraction) is converted exactly to fixed point.
 *
 * Every graph produced is a valid planar embedding in the sense of
 * hpfc_graph_validate(): no two edges cross or touch except at a shared end
 * vertex, no two points coincide, no zero-length segment, no isolated vertex
 * and loops carry at least 2 interior points. All graphs use unit exponent 0.
 *
 * Functions return HPFC_OK or an HPFC_E_* status (HPFC_E_ARG for arguments
 * out of range, HPFC_E_NOMEM); on failure *out is set to NULL.
 */
#ifndef HPFC_TEST_GEN_H
#define HPFC_TEST_GEN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hpfc.h"

/* Largest coord_max the Delaunay generators accept: with coordinates below
 * 2^21 the incircle determinant stays below 2^89, inside an __int128. */
#define GEN_COORD_MAX_DELAUNAY ((int64_t)1 << 21)

/* ------------------------------------------------------------------------
 * Pseudo-random numbers: xoshiro256** seeded through splitmix64.
 * ------------------------------------------------------------------------ */
typedef struct gen_rng {
    uint64_t s[4];
} gen_rng;

void gen_rng_seed(gen_rng *rng, uint64_t seed);
uint64_t gen_rng_next(gen_rng *rng);
/* Uniform integer in [0, bound), bound >= 1, without modulo bias. */
uint64_t gen_rng_below(gen_rng *rng, uint64_t bound);

/* ------------------------------------------------------------------------
 * Exact Delaunay triangulation of random lattice points.
 * ------------------------------------------------------------------------ */
typedef struct gen_triangulation {
    size_t npoints;
    int64_t *xy;          /* 2 per point, in generation order */
    size_t ntriangles;
    uint32_t *tri;        /* 3 point indices per triangle, counter-clockwise */
    size_t nedges;
    uint32_t *edge;       /* 2 point indices per edge, smaller index first */
    size_t nhull;         /* points on the hull boundary, collinear included */
} gen_triangulation;

/* npoints distinct points drawn uniformly from [1, coord_max-1]^2 (duplicates
 * are redrawn) and their exact Delaunay triangulation (Bowyer-Watson with
 * ghost triangles, points inserted in Hilbert order, walking point location).
 * Cocircular points get an arbitrary but deterministic diagonal. When fewer
 * than 3 points or all points are collinear there are no triangles and the
 * edges join consecutive points along the line. Requires 2 <= coord_max <=
 * GEN_COORD_MAX_DELAUNAY and npoints <= (coord_max-1)^2. */
int gen_delaunay_triangulation(uint64_t seed, size_t npoints, int64_t coord_max,
                               gen_triangulation *out);
void gen_triangulation_free(gen_triangulation *t);

/* The triangulation above (same seed, same points), then round(remove_fraction
 * * edges) edges removed uniformly at random (the hPFC paper removes 20%),
 * then every vertex left without an edge dropped (the others keep their
 * relative order). remove_fraction in [0, 1]; at 1 the graph is empty. */
int gen_delaunay(uint64_t seed, size_t npoints, int64_t coord_max,
                 double remove_fraction, hpfc_graph **out);

/* Curved edges, "junctions only" vertex model: gen_delaunay's graph (with a
 * larger fraction removed, e.g. 0.5), then every chain through vertices of
 * degree 2 contracted into one polyline edge whose interior points are the
 * chain's vertices. A ring made only of degree-2 vertices becomes a loop edge
 * at its lowest-numbered vertex (>= 2 interior points since a ring has >= 3
 * vertices); a chain leaving a junction and coming back to it is a loop too.
 * So no vertex has degree 2 except the vertex of such a ring. */
int gen_polyline(uint64_t seed, size_t npoints, int64_t coord_max,
                 double remove_fraction, hpfc_graph **out);

/* A (cols+1) x (rows+1) grid of vertices spaced `spacing` apart, each moved
 * by a random jitter in [-J, J]^2 with J = (spacing-1)/4 < spacing/4 (no
 * jitter below spacing 5). Every cell is split by one diagonal of random
 * direction. Every triangle keeps a positive orientation (its determinant is
 * at least spacing^2 - 4*J*spacing > 0), so the mesh stays planar. Vertex
 * (i, j) sits near ((i+1)*spacing, (j+1)*spacing). cols, rows >= 1.
 * (cols+1)(rows+1) vertices, 3*cols*rows + cols + rows edges: 600 x 600
 * gives about 1.08 M segments. */
int gen_grid_mesh(uint64_t seed, size_t cols, size_t rows, int64_t spacing,
                  hpfc_graph **out);

/* ------------------------------------------------------------------------
 * Hand-made special graphs.
 * ------------------------------------------------------------------------ */
enum gen_special_kind {
    /* One straight edge between two vertices. */
    GEN_SPECIAL_EDGE = 0,
    /* A triangle: 3 vertices, 3 straight edges; one bounded face. */
    GEN_SPECIAL_TRIANGLE,
    /* A 40 x 40 square (4 vertices, 4 edges) with a crack: a straight edge
     * from the south-west corner into the inside ending at a degree-1 vertex
     * (a dead end, both sides of the crack on the same face). */
    GEN_SPECIAL_CRACK,
    /* A vertex carrying a loop edge with 3 interior points (a convex
     * quadrilateral through the vertex) and one straight edge leaving it
     * outside the loop. */
    GEN_SPECIAL_LOOP,
    /* Three parallel edges between the same two vertices: one straight, two
     * polylines (one interior point each) bowing out north and south. */
    GEN_SPECIAL_MULTI,
    /* Nested components: an outer square, an inner square inside it with no
     * edge between the two, and an island triangle inside the inner square.
     * Gives a face with a hole and a component nested two levels deep. */
    GEN_SPECIAL_HOLE,
    /* A star: a centre vertex of degree 64 with 64 radial straight edges to
     * every other lattice point of the square ring at Chebyshev distance 16. */
    GEN_SPECIAL_STAR,
    /* A long thin comb (a tree): a spine of 100 vertices 2 units apart along
     * y = 0, each carrying a vertical tooth 1000 units tall; the face runs
     * into 99 slots 2 units wide and 1000 tall. */
    GEN_SPECIAL_COMB,
    GEN_SPECIAL_COUNT
};

/* Short lower-case name of a special graph ("edge", "triangle", ...), or
 * NULL when `which` is out of range. */
const char *gen_special_name(int which);

/* Builds special graph `which` (an enum gen_special_kind). */
int gen_special(int which, hpfc_graph **out);

/* Calls fn on every special graph, then on a Delaunay graph of
 * delaunay_step * seed points and a polyline graph of polyline_points
 * points for each seed in 1 .. seeds: the sweep the traversal tests share.
 * HPFC_OK, or the first generator's failure (the sweep goes on past it). */
int gen_sweep(uint64_t seeds, size_t delaunay_step, size_t polyline_points,
              void (*fn)(const hpfc_graph *g, const char *what));

/* ------------------------------------------------------------------------
 * Output.
 * ------------------------------------------------------------------------ */

/* Writes g as plain-text .pfc: a `pfc 1` line, one `v X Y` line per vertex
 * (vertex indices are implicit, 0-based in file order), one `e U V X1 Y1 ...`
 * line per edge (U, V vertex indices, then the interior points). Only graphs
 * of unit exponent 0 (all generated graphs) are accepted: HPFC_E_ARG
 * otherwise. HPFC_E_IO when a write fails. */
int gen_write_pfc(const hpfc_graph *g, FILE *f);

#endif
