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

/* Builds part k from dir's part-K.pfc and part-K.ids into part-K.part. */
int part_dir_build(const char *dir, const part_plan *plan, uint32_t k, hpfc_diag *diag);

/* Joins the `count` part files (paths[k], or dir's part-K.part when paths
 * is NULL) where they lie (hpfc_tree_merge_files: the joined tree reads
 * them from their mappings until it is freed, so they must stay unchanged
 * until then). A file's fault is said as "PATH: why" in diag. */
int part_dir_merge(const char *dir, const char *const *paths, uint32_t count, hpfc_tree **out,
                   hpfc_diag *diag);

#ifdef __cplusplus
}
#endif

#endif
