/*
 * pack_cut.h: how a build in parts cuts the map (hpfc-pack --partitions
 * and --memory). A part is a run of root pixels in scanline order; the
 * runs are chosen by the map's points in each root pixel, so that parts
 * hold about the same share of the map, or as few parts as keep the pack
 * within a memory budget. Any cut gives the same file (pack_write.h); the
 * cut only decides how much is built at once.
 */
#ifndef HPFC_PACK_CUT_H
#define HPFC_PACK_CUT_H

#include <stdint.h>

#include "hpfc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The points of the map (vertices and interior points) in each of the
 * domain's root pixels, scanline index (row 0 the northern one): `weight`
 * has root_cols * root_rows entries, overwritten. */
void pack_cut_weigh(const hpfc_graph *g, const hpfc_build_params *p, const hpfc_domain *d,
                    uint64_t *weight);

/* Cuts the `roots` root pixels into at most `parts` runs of about equal
 * weight, no run empty of pixels: run q is [start[q], start[q + 1]),
 * start has parts + 1 entries. A root pixel heavier than a share makes
 * fewer runs, and a map of no weight one. Returns the number of runs. */
uint32_t pack_cut_even(const uint64_t *weight, uint64_t roots, uint32_t parts, uint64_t *start);

/* Cuts them into the fewest runs whose weight is at most `limit` each (a
 * root pixel heavier than that is a run of its own), at most `most`
 * runs: beyond that the runs are cut evenly (pack_cut_even) into `most`.
 * start has most + 1 entries. Returns the number of runs. */
uint32_t pack_cut_limit(const uint64_t *weight, uint64_t roots, uint64_t limit, uint32_t most,
                        uint64_t *start);

/* What a pack holds at its peak, by the model of bench/README.md ("A
 * memory budget"): `held` bytes before the build (the input graph, a GIS
 * layer's features), then the larger of the build (a whole build's, or
 * `jobs` parts' at once, the heaviest part's points each) and the join and
 * write. The build's tree and the join grow with the tree's pixels as
 * well as with the points, and a map's pixels a point vary fivefold
 * (a street network's few, a coastline's many): the model takes them as
 * tree_pixels / sample_points, measured on a sample of the map
 * (pack_write.c builds a few small parts first). */
typedef struct pack_memory {
    uint64_t held;     /* allocated when the build starts */
    uint64_t points;   /* the map's */
    uint64_t heaviest; /* the heaviest run's points */
    uint32_t parts, jobs;
    uint64_t sample_pixels, sample_points; /* pixels a point; 0 points: one a point */
} pack_memory;
uint64_t pack_memory_need(const pack_memory *m);

/* The fewest runs whose pack needs at most `budget` bytes by the model
 * (m->held, jobs and sample; its points, heaviest and parts are set here),
 * in *start (at most `most` runs, as pack_cut_limit), and what that pack
 * needs, which exceeds the budget when no cut keeps within it (then the
 * cut that needs least, in the fewest runs). Returns the number of runs. */
uint32_t pack_cut_budget(const uint64_t *weight, uint64_t roots, pack_memory *m, uint64_t budget,
                         uint32_t most, uint64_t *start, uint64_t *need);

/* The process's own memory now, in bytes: its resident anonymous pages
 * (Linux), else what glibc's heap has handed out (which counts pages
 * never touched), else 0. */
uint64_t pack_own_bytes(void);

#ifdef __cplusplus
}
#endif

#endif
