/* The planar map an .hpfc file encodes, reconstructed with the library's
 * traversal operators only (interfaces §3, --export-graph). */
#ifndef HPFC_EXPORT_H
#define HPFC_EXPORT_H

#include <stdio.h>

#include "hpfc.h"

typedef struct exported_map {
    size_t nv, nd;
    int64_t *box;               /* 4 per vertex: the leaf pixel, lattice units */
    uint32_t *origin;           /* per dart: origin vertex */
    uint32_t *twin, *next;      /* per dart: opposite dart, next dart along its face */
} exported_map;

/* Walks every vertex and dart of the file. Vertices and darts are numbered
 * in the order of hpfc_leaf_first/next, then local vertex, then clockwise. */
int export_map(const hpfc_file *file, exported_map *out);
void exported_map_free(exported_map *map);

/* Writes the map as the hpfc-graph JSON of interfaces §3, boxes in the
 * input's coordinates. */
int export_map_json(const hpfc_file *file, const exported_map *map, FILE *out);

#endif
