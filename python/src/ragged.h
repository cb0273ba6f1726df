/*
 * ragged.h: the Python package's geometry answers as flat int64 arrays
 * (GeoArrow's ragged layout), assembled from the library's hpfc_shapes_*
 * and hpfc_geometry_* answers. Plain C, no Python: shapes.c wraps it, and
 * fuzz/read_shapes.c runs it on hostile files.
 *
 * For a list of ids, item i is polygons [part[i], part[i + 1]) (lines for
 * line kinds), polygon p rings [polygon[p], polygon[p + 1]), ring r points
 * [ring[r], ring[r + 1]) of xy (2 int64 a point, absolute lattice
 * coordinates). A hole that no outer ring of its answer contains (the
 * unbounded face's) is a polygon of its own, flagged 1 in hole_only.
 */
#ifndef HPFC_PY_RAGGED_H
#define HPFC_PY_RAGGED_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc.h"

typedef struct {
    int64_t *v;
    size_t n, cap;
} ragged_i64s;

typedef struct {
    ragged_i64s part, polygon, ring, xy, hole_only;
} ragged;

enum ragged_kind {
    RAGGED_FACE = 0,          /* hpfc_shapes_face_polygons: rings of a face */
    RAGGED_FEATURE = 1,       /* hpfc_shapes_feature_polygons: union of its faces */
    RAGGED_FEATURE_LINES = 2, /* hpfc_shapes_feature_polylines */
    RAGGED_EDGE = 3,          /* an input edge's polyline (hpfc_geometry_edge) */
    RAGGED_DART = 4           /* a dart key's polyline (hpfc_geometry_key_points) */
};

/* The item sources: shapes for faces and features, walker for dart keys
 * (either may be NULL when no id of its kinds is asked). */
typedef struct {
    const hpfc_file *file;
    hpfc_shapes *shapes;
    hpfc_walker *walker;
} ragged_source;

/* Empty arrays with their leading zero offsets; polygons: the kind has a
 * polygon level (faces, features). HPFC_OK or HPFC_E_NOMEM. */
int ragged_start(ragged *r, int polygons);
void ragged_free(ragged *r);
/* Appends item `id` of `kind`: HPFC_OK, the library's status (HPFC_E_ARG
 * for an id out of range), or HPFC_E_NOMEM when an array cannot grow. On
 * an error the arrays hold the items before it, possibly with a partial
 * tail: the caller discards them. */
int ragged_add(ragged *r, const ragged_source *src, int kind, uint64_t id);

#endif
