/*
 * pack_write.h: the end of a pack, from a planar graph to the written file:
 * build the tree, serialise it, link the GIS features to the faces (FEAT,
 * with their attributes, ATTR, and the edges' features, EDGF) and write the
 * file atomically. hpfc-pack and the GDAL driver's writer (gdal/) both call
 * it, so that a map packed either way is the same bytes.
 */
#ifndef HPFC_PACK_WRITE_H
#define HPFC_PACK_WRITE_H

#include <stdint.h>

#include "clock.h"
#include "gis_input.h"
#include "hpfc.h"
#include "part_dir.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the pack did, for hpfc-pack's report. */
typedef struct pack_write_stats {
    int build_failed;           /* the failure (if any) was the build's: the input's fault */
    uint64_t file_bytes;        /* the file written, 0 where the hook's count stands */
    uint32_t parts;             /* the parts the tree was built in (1: whole) */
    uint64_t memory_held;       /* with a budget: the process's own memory before the build */
    uint64_t memory_need;       /* with a budget: the model's peak for those parts */
    uint64_t memory_sample_pixels, memory_sample_points; /* the model's sample (pack_cut.h) */
    stage_time build_t, write_t, features_t; /* wall and CPU */
    uint32_t features, all_features, edges_with_features;
    uint64_t faces_with_features, faces_without_witness;
    uint64_t faces_walked, faces_anchored, faces_checked, link_conflicts;
    int link_witness;
    stage_time link_t[4]; /* faces, witnesses, topology, check */
} pack_write_stats;

/* Called once the tree is built and serialised and the bytes reopened,
 * before the tree is freed: a status, HPFC_OK to go on. */
typedef int (*pack_write_hook)(void *user, const hpfc_tree *t, const hpfc_file *f);

/* How the tree is built: whole (count 0 or 1), in `count` parts one after
 * another here, or `jobs` at a time in threads (dir NULL: hpfc-pack
 * --partitions and --jobs), or in parts that other
 * processes build (hpfc-pack --parts-dir, docs/interfaces.md §8): the parts'
 * graphs are cut into `dir`, then `await_parts` is called and returns when
 * every DIR/part-K.part is there (HPFC_OK), or with a status: then the
 * whole graph is validated, to word a flaw a part found as hpfc_build
 * does. Every way gives the same bytes. */
typedef struct pack_parts {
    uint32_t count; /* at most that many parts, of about equal points (pack_cut_even) */
    uint32_t jobs; /* parts built at once here, in threads (0 or 1: one after another) */
    /* hpfc-pack --memory: a budget in bytes (0: none) for which `count` is
     * chosen instead, the fewest parts whose pack the model of pack_cut.h
     * keeps within it (one: the whole build). When none does, the finest
     * cut is taken and `notice` (when set) is told so before the build. */
    uint64_t memory;
    void (*notice)(const char *text);
    const char *dir;
    int (*await_parts)(void *user, const part_plan *plan, hpfc_diag *diag);
    void *user;
} pack_parts;

/* Builds g with `params` as `parts` says (NULL: whole) and writes it to `output` (NULL: standard output)
 * with `base`'s options (CRS, labels, layout, geometry) and, when `gis` holds
 * features, their FEAT, ATTR and EDGF sections, linked to the faces by the
 * topology or, with `link_witness`, by each face's witness point alone
 * (hpfc-pack --link). `progress_on` draws bars on
 * stderr. HPFC_OK, or a status with diag->message saying why (nothing
 * written). */
int pack_write(const hpfc_graph *g, const hpfc_build_params *params, const pack_parts *parts,
               const hpfc_write_options *base, const gis_info *gis, int link_witness,
               const char *output, int progress_on, pack_write_hook hook, void *user, pack_write_stats *stats,
               hpfc_diag *diag);

#ifdef __cplusplus
}
#endif

#endif
