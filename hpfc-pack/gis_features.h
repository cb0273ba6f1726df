/*
 * gis_features.h: the source features of a GIS pack and which faces of the
 * built map they cover, for the file's FEAT section (spec/hpfc-format.md
 * §6.2).
 *
 * gis_input.c records every feature with lines or polygons (its position
 * in its layer, its source FID, layer and key value) and its parts (rings
 * and lines) as they lie in the map: snapped to the lattice, and where
 * noding moved a segment, along the path noding gave it (noded_paths.h),
 * so that every segment of a part is a segment of the map. After the
 * build, gis_features_link() derives each face's features twice, and
 * compares: from the topology (face_link.h: a polygon's rings are edges of
 * the map, so a feature's membership changes only across its own edges and
 * propagates over face adjacency from the unbounded face), and, exactly and
 * independently, from each face's witness point tested against the rings
 * by the even-odd rule (face_witness.h, face_check.h). The witness's answer
 * is kept; the faces where the two differ are counted as conflicts (none
 * on a correct build). The same pass links each edge of the map to the
 * features whose lines or rings run along it.
 */
#ifndef HPFC_PACK_GIS_FEATURES_H
#define HPFC_PACK_GIS_FEATURES_H

#include <stddef.h>
#include <stdint.h>

#include "face_witness.h"
#include "hpfc.h"
#include "clock.h"

typedef struct gis_features gis_features;

/* key_field: the attribute recorded with each feature (NULL: none). */
gis_features *gis_features_create(const char *key_field);
void gis_features_free(gis_features *fs);
/* Names layer `index` (layers are numbered in reading order). */
int gis_features_set_layer(gis_features *fs, uint32_t index, const char *name);
/* A new feature: its position in its layer (the file's fid), its FID in
 * the source (kept as an attribute), its layer and key (NULL for a null
 * value). Its index is the count before. */
int gis_features_add(gis_features *fs, int64_t position, int64_t source_fid, uint32_t layer,
                     const char *key);
uint32_t gis_features_count(const gis_features *fs);
/* The source FID of feature k. */
int64_t gis_features_source_fid(const gis_features *fs, uint32_t k);
/* A part of feature `feature` (lattice x, y pairs, each segment a segment
 * of the map): a ring of a polygon (closed or not; it bounds the feature's
 * area) or, with ring 0, a line. Parts come in non-decreasing feature
 * order. */
int gis_features_add_part(gis_features *fs, uint32_t feature, int ring, const int64_t *xy,
                          size_t n);

/* Reads the points of part r in order (gis_features_part_open). */
typedef struct gis_part_cursor {
    const uint8_t *p;
    uint64_t x, y;
    size_t left;
} gis_part_cursor;

size_t gis_features_part_count(const gis_features *fs);
/* Part r: its feature, whether it is a ring, and a cursor on its points. */
gis_part_cursor gis_features_part_open(const gis_features *fs, size_t r, uint32_t *feature,
                                       int *ring);
void gis_part_next(gis_part_cursor *c, int64_t *x, int64_t *y);
/* Part r's number of points, and its feature. */
size_t gis_features_part_points(const gis_features *fs, size_t r);
uint32_t gis_features_part_feature(const gis_features *fs, size_t r);

/* What gis_feature_table() made: the table and the arrays it points to,
 * and the edges' features. */
typedef struct gis_feature_table {
    hpfc_feature_table table;
    uint32_t *face_start, *face_feature;
    int64_t *fid;                   /* positions in the layers */
    uint64_t faces_without_witness; /* faces no witness point was found for (none should be) */
    /* edge e's features: edge_feature[edge_start[e] .. edge_start[e + 1]) */
    uint32_t edge_count;
    uint32_t *edge_start, *edge_feature;
    uint32_t polygon_features; /* features with a ring */
    /* how the faces were linked */
    uint64_t faces_propagated; /* reached by the walk from the unbounded face */
    uint64_t anchors;          /* faces the walk did not reach: the witness's answer alone */
    uint64_t conflicts;        /* faces where the walk and the witness disagree */
    int method_witness;        /* no walk: every face by its witness (--link witness) */
    /* the time of the stages: faces numbered, witnesses found, topology
       (segments matched, sides found, walk), check (every witness) */
    stage_time faces_t, witness_t, topology_t, check_t;
} gis_feature_table;

void gis_feature_table_free(gis_feature_table *t);

/* The linking step of a pack: numbers the faces of the open map `file`
 * (built from `graph`; lc: its crossings, taken from the tree before it was
 * freed), or takes `faces` when the caller has them (the writer's, bound
 * to `file`: hpfc_faces_attach), links them and the edges to the features
 * and makes the table.
 * `witness` 0 links from the topology, every face then confirmed by the
 * exact check (hpfc-pack's default); 1 answers every face by its witness
 * point alone (hpfc-pack --link witness, a cross-check the tests compare
 * with the default). The faces are numbered (when not given) and checked
 * on up to `threads` threads (0 or 1: the calling one, beside the
 * witnesses' own thread); the table is the same whatever the count. 0, or
 * 1 with a message in err. */
int gis_features_link_method(const gis_features *fs, const hpfc_graph *graph,
                             const leaf_crossings *lc, const hpfc_file *file,
                             const hpfc_faces *faces, int witness, unsigned threads,
                             gis_feature_table *out, char *err, size_t err_len);

#endif
