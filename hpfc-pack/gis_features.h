/*
 * gis_features.h: the source features of a GIS pack and which faces of the
 * built map they cover, for the file's FEAT section (spec/hpfc-format.md
 * §7.1).
 *
 * gis_input.c records every polygon feature (id, layer, key value) and its
 * rings on the lattice, exactly as they went into noding. After the build,
 * gis_feature_table() tests each face's witness point (face_witness.h)
 * against the rings by the even-odd rule, with a GEOS STRtree of the rings'
 * boxes to find the candidates.
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
/* A new feature; key NULL for a null value. Its index is the count before. */
int gis_features_add(gis_features *fs, int64_t fid, uint32_t layer, const char *key);
uint32_t gis_features_count(const gis_features *fs);
/* A ring of feature `feature` (lattice x, y pairs; closed or not). Rings
 * come in non-decreasing feature order. */
int gis_features_add_ring(gis_features *fs, uint32_t feature, const int64_t *xy, size_t n);

/* What gis_feature_table() made: the table and the arrays it points to. */
typedef struct gis_feature_table {
    hpfc_feature_table table;
    uint32_t *face_start, *face_feature;
    uint64_t faces_without_witness; /* faces no witness point was found for */
} gis_feature_table;

/* Links each of the `faces` faces to the features whose rings hold its
 * witness an odd number of times. 0, or 1 with a message in err. */
int gis_feature_table_make(const gis_features *fs, const face_witness *w, uint64_t faces,
                           gis_feature_table *out, char *err, size_t err_len);
void gis_feature_table_free(gis_feature_table *t);

/* The linking step of a pack: numbers the faces of the open map `file`
 * (built from `graph`; lc: its crossings, taken from the tree before it was
 * freed), finds each face's witness and makes the table. 0, or 1 with a
 * message in err. */
int gis_features_link(const gis_features *fs, const hpfc_graph *graph, const leaf_crossings *lc,
                      const hpfc_file *file, gis_feature_table *out, char *err, size_t err_len);

#endif
