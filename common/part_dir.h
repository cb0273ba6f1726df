/*
 * part_dir.h: a split build's shared directory (docs/interfaces.md §8), the
 * files through which one process hands the parts of a build to others and
 * takes their trees back:
 *
 *   DIR/part-K.pfc    part K's graph (hpfc_part_graph), .pfc text of lattice
 *                     integers, unit exponent 0 (the plan carries the map's)
 *   DIR/part-K.ids    each of its edges' id in the whole map, u32 in the
 *                     machine's order
 *   DIR/part-K.part   the part's tree (spec/part-format.md), from whoever
 *                     built it
 *   DIR/graph         (a .pfc read by the workers) the whole graph as a
 *                     graph file (hpfc.h, "A .pfc read in chunks, into a
 *                     graph file"), each chunk's stretch written by the
 *                     process that read it
 *   DIR/route-C       (the same) chunk C's edges routed to the parts: each
 *                     part's ids of the chunk's edges that come near it,
 *                     which the part's builder copies out of DIR/graph
 *
 * Part K of P is the run of root pixels [R*K/P, R*(K+1)/P) in scanline order
 * (R root pixels). hpfc-pack --parts-dir and the Python package's hpfc.pack
 * (python/src/pack.c) cut and join through these calls; a worker builds one
 * part with part_dir_build. What is read back goes through the library's
 * hardened readers (.pfc parser, part file reader, hpfc_build_part's id
 * checks): a damaged or foreign file is a status with a message.
 */
#ifndef HPFC_PART_DIR_H
#define HPFC_PART_DIR_H

#include <stdbool.h>
#include <stdint.h>

#include "hpfc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a worker needs besides the part's two files. */
typedef struct part_plan {
    hpfc_domain domain;        /* hpfc_build_domain of the whole map */
    int32_t unit_exp10;        /* the whole graph's unit exponent */
    uint64_t edges;            /* the whole graph's edge count */
    uint32_t parts;            /* P */
    uint32_t root_cols, root_rows, cols, rows, leaf_points; /* the build's sizes */
} part_plan;

/* The build parameters a plan names (hpfc_build_params_default otherwise). */
hpfc_build_params part_plan_params(const part_plan *plan);

/* Root pixels [*first, *end) of part k. */
void part_dir_range(const part_plan *plan, uint32_t k, uint64_t *first, uint64_t *end);

/* Fills *plan for g built with p in `parts` parts (at most the root
 * pixels: fewer are taken) and writes every part's .pfc and .ids into dir.
 * Checks first what no part can see (hpfc_graph_check_whole, whose status
 * and message are the build's). HPFC_OK or a status, diag saying why. */
int part_dir_cut(const hpfc_graph *g, const hpfc_build_params *p, uint32_t parts, const char *dir,
                 part_plan *plan, hpfc_diag *diag);

/* Fills *plan for g built with p in `parts` parts (as part_dir_cut), the
 * domain from box (the graph's points' {xmin, ymin, xmax, ymax}, or NULL:
 * hpfc_graph_bounds), checking what no part can see. */
int part_dir_plan(const hpfc_graph *g, const hpfc_build_params *p, uint32_t parts, const int64_t *box,
                  part_plan *plan, hpfc_diag *diag);

/* Routes edges [first_edge, end_edge) of g (the graph file's) to the
 * plan's parts, as part_dir_cut would: DIR/route-C (C = chunk). */
int part_dir_route(const char *dir, const hpfc_graph *g, const part_plan *plan, uint32_t chunk,
                   uint64_t first_edge, uint64_t end_edge, hpfc_diag *diag);

/* Builds part k from DIR/graph and its edges in DIR/route-0 ..
 * route-(chunks - 1) into part-K.part; a route file that is not of this
 * plan's chunks, in order, whole, is HPFC_E_CORRUPT. */
int part_dir_build_routed(const char *dir, const part_plan *plan, uint32_t k, uint32_t chunks,
                          hpfc_diag *diag);

/* Builds part k from dir's part-K.pfc and part-K.ids into part-K.part. */
int part_dir_build(const char *dir, const part_plan *plan, uint32_t k, hpfc_diag *diag);

/* Joins the `count` part files (paths[k], or dir's part-K.part when paths
 * is NULL) where they lie (hpfc_tree_merge_files: the joined tree reads
 * them from their mappings until it is freed, so they must stay unchanged
 * until then), with the map's components and faces counted when
 * `count_components` (else hpfc_tree_merge_files_uncounted: 0, and no
 * union-find over the edges). A file's fault is said as "PATH: why" in
 * diag. */
int part_dir_merge(const char *dir, const char *const *paths, uint32_t count,
                   bool count_components, hpfc_tree **out, hpfc_diag *diag);

/* The graph file for `vertices`, `edges` and `points` at unit 10^unit:
 * its header and last edge offset written, the rest zeros for the chunks'
 * fills (part_dir_fill_chunk). */
int part_dir_graph_create(const char *path, uint64_t vertices, uint64_t edges, uint64_t points,
                          int32_t unit_exp10, hpfc_diag *diag);

/* Where one chunk of a .pfc goes: the whole text's counts and digits, the
 * vertices, edges and points of the chunks before it. */
typedef struct part_dir_chunk_place {
    uint64_t vertices, edges, points;
    int32_t digits;
    uint64_t first_vertex, first_edge, first_point;
} part_dir_chunk_place;

/* Fills chunk [begin, end) of the .pfc at pfc_path, which scanned as
 * *scan, into its stretch of the graph file at graph_path (pwrite of its
 * own bytes only, so processes on other machines may fill theirs at
 * once); *box gets its points' box (hpfc_pfc_fill). hpfc_pfc_chunk is in
 * hpfc.h's experimental tier, which part_dir.c sees. */
int part_dir_fill_chunk(const char *pfc_path, size_t begin, size_t end, const struct hpfc_pfc_chunk *scan,
                        const char *graph_path, const part_dir_chunk_place *place, int64_t box[4],
                        hpfc_diag *diag);

/* A .pfc file mapped read-only for its chunks (munmap with its length); a
 * status with diag's message. */
int part_dir_map_text(const char *path, const char **text, size_t *length, hpfc_diag *diag);

#ifdef __cplusplus
}
#endif

#endif
