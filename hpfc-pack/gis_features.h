/*
 * gis_features.h: the source features of a GIS pack and which faces of the
 * built map they cover, for the file's FEAT section (spec/hpfc-format.md
 * §7.1).
 *
 * gis_input.c records every feature with lines or polygons (its position
 * in its layer, its source FID, layer and key value) and its parts (rings
 * and lines) on the lattice, exactly as they went into noding. After the
 * build, gis_features_link() derives each face's features from the
 * topology (face_link.h): a polygon's rings are edges of the map, so a
 * feature's membership changes only across its own edges and propagates
 * over face adjacency from the unbounded face. Faces it cannot reach that
 * way (behind edges GEOS re-noded, whose source rings are not known) get
 * the old answer: their witness point (face_witness.h) tested against the
 * rings by the even-odd rule. The same pass links each edge of the map to
 * the features whose lines or rings run along it.
 */
#ifndef HPFC_PACK_GIS_FEATURES_H
#define HPFC_PACK_GIS_FEATURES_H

#include <stddef.h>
#include <stdint.h>

#include "face_witness.h"
#include "hpfc.h"

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
/* A part of feature `feature` (lattice x, y pairs): a ring of a polygon
 * (closed or not; it bounds the feature's area) or, with ring 0, a line.
 * Parts come in non-decreasing feature order. */
int gis_features_add_part(gis_features *fs, uint32_t feature, int ring, const int64_t *xy,
                          size_t n);
/* The segments GEOS re-noded (each with (ax, ay) < (bx, by), sorted as
 * segnode_seg; copied), or all = 1 when it noded the whole linework: the
 * source parts are not known along them. */
int gis_features_set_noded(gis_features *fs, const int64_t *segs, size_t n, int all);

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
/* Is lattice segment (ax, ay)-(bx, by), (ax, ay) < (bx, by), one GEOS
 * re-noded? */
int gis_features_segment_noded(const gis_features *fs, int64_t ax, int64_t ay, int64_t bx,
                               int64_t by);

/* What gis_feature_table() made: the table and the arrays it points to,
 * and the edges' features. */
typedef struct gis_feature_table {
    hpfc_feature_table table;
    uint32_t *face_start, *face_feature;
    int64_t *fid;                   /* positions in the layers */
    uint64_t faces_without_witness; /* faces no witness point was found for */
    /* edge e's features: edge_feature[edge_start[e] .. edge_start[e + 1]) */
    uint32_t edge_count;
    uint32_t *edge_start, *edge_feature;
    uint32_t polygon_features; /* features with a ring */
    /* how the faces were linked */
    uint64_t faces_propagated; /* reached over edges from the unbounded face or an anchor */
    uint64_t anchors;          /* faces answered by a witness point */
    uint64_t conflicts;        /* edges whose two faces disagree with the edge's rings */
    int method_witness;        /* every face by its witness (HPFC_PACK_LINK=witness) */
    /* wall time of the stages, seconds: faces numbered, witnesses found, topology
       (segments matched, sides found, walks), anchors */
    double faces_s, witness_s, topology_s, anchor_s;
} gis_feature_table;

void gis_feature_table_free(gis_feature_table *t);

/* The linking step of a pack: numbers the faces of the open map `file`
 * (built from `graph`; lc: its crossings, taken from the tree before it was
 * freed), links them and the edges to the features and makes the table.
 * With the environment variable HPFC_PACK_LINK=witness, every face is
 * answered by its witness point, as before 1.2 (a checking aid: the tests
 * compare both). 0, or 1 with a message in err. */
int gis_features_link(const gis_features *fs, const hpfc_graph *graph, const leaf_crossings *lc,
                      const hpfc_file *file, gis_feature_table *out, char *err, size_t err_len);
/* The same with the method given: witness 1 answers every face by its
 * witness point, 0 links from the topology. */
int gis_features_link_method(const gis_features *fs, const hpfc_graph *graph,
                             const leaf_crossings *lc, const hpfc_file *file, int witness,
                             gis_feature_table *out, char *err, size_t err_len);

#endif
