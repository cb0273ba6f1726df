/*
 * ogr_shapes.h: an .hpfc file's features, faces and edges as OGR
 * geometries and fields, in the source SRS: what hpfc-inspect --export
 * writes and what the GDAL driver (gdal/) reads. The geometry is the
 * library's exact rings (hpfc_shapes_*), turned into user coordinates
 * (lattice * 10^unit_exp10) and, for a map that hpfc-pack projected from
 * longitude and latitude, projected back with the inverse of the
 * projection its CRS section records (projection.h), so that it lies on
 * the original. Needs GDAL's C API and GeographicLib.
 */
#ifndef HPFC_OGR_SHAPES_H
#define HPFC_OGR_SHAPES_H

#include <stddef.h>
#include <stdint.h>

#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "hpfc.h"
#include "projection.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ogr_shapes {
    const hpfc_file *f;
    hpfc_shapes *shapes;        /* the caller's; one thread at a time */
    mapproj_plan *plan;         /* back to lon/lat; NULL: user coordinates */
    int32_t unit_exp10;         /* user coordinate = lattice * 10^unit_exp10 */
    OGRSpatialReferenceH srs;   /* the output's, NULL: none */
    char srs_name[160];         /* "EPSG:4326", a name, or "none" */
    uint64_t polygons, rings, points, lines; /* made so far */
    uint64_t skipped_holes;     /* rings of the unbounded face's, left out */
    char why[600];              /* the last failure */
} ogr_shapes;

/* Sets up the output SRS from the file's CRS section: when hpfc-pack
 * projected a geographic source (the description is one of its
 * projections and the source, where named by an authority, geographic),
 * the source's lon/lat and the plan back there; otherwise the user
 * coordinates are the source's own. `shapes` may be NULL for the SRS
 * alone. 0, or 1 with o->why set. Release with ogr_shapes_release. */
int ogr_shapes_init(ogr_shapes *o, const hpfc_file *f, hpfc_shapes *shapes);
void ogr_shapes_release(ogr_shapes *o);

/* A lattice point in output coordinates; 0 or 1 with o->why set. */
int ogr_shapes_point(ogr_shapes *o, int64_t x, int64_t y, double *ox, double *oy);
/* n lattice points (pairs in xy) in output coordinates (pairs in out, an
 * array apart): the same values as ogr_shapes_point, a batch at a time;
 * 0 or 1 with o->why set. */
int ogr_shapes_points(ogr_shapes *o, const int64_t *xy, size_t n, double *out);

/* Polygon k of an answer (its outer ring and holes), all its polygons as a
 * multipolygon, its rings as a multi line string; NULL with o->why set. */
OGRGeometryH ogr_shapes_polygon(ogr_shapes *o, const hpfc_polygons *p, size_t k);
OGRGeometryH ogr_shapes_multipolygon(ogr_shapes *o, const hpfc_polygons *p);
OGRGeometryH ogr_shapes_multiline(ogr_shapes *o, const hpfc_polygons *p);

/* A feature's geometry: its faces' union, else its lines, else none (*g
 * NULL). 0, or 1 with o->why set. */
int ogr_shapes_feature_geometry(ogr_shapes *o, hpfc_id feature, OGRGeometryH *g);
/* A bounded face's polygon (NULL with o->why set: face 0, or a face that
 * does not have exactly one outer ring in a corrupt file). */
OGRGeometryH ogr_shapes_face_geometry(ogr_shapes *o, hpfc_id face);
/* An edge's polyline, its ends included. */
OGRGeometryH ogr_shapes_edge_geometry(ogr_shapes *o, hpfc_id edge);

/* Each source layer's geometry type, types[l] for the `layers` layers of
 * FEAT: multipolygons when all its features cover faces, multi line
 * strings when none does (or it has none), else unknown; and counts[l]
 * its features (counts may be NULL). One pass over the features' row
 * lengths (hpfc_shapes_layer_kinds), not their faces. 0, or 1 with
 * o->why set. */
int ogr_shapes_layer_types(ogr_shapes *o, OGRwkbGeometryType *types, uint64_t *counts,
                           uint32_t layers);

/* The fields of a feature: what each OGR field holds. */
enum { OGR_SHAPES_FID = -2, OGR_SHAPES_KEY = -1 }; /* else an ATTR column */
typedef struct ogr_shapes_field {
    char *name;
    OGRFieldType type;
    int64_t source;             /* OGR_SHAPES_FID, OGR_SHAPES_KEY or an ATTR column */
} ogr_shapes_field;

/* A feature's fields: "fid" when with_fid (unless an attribute has that
 * name), the key (unless an attribute has its name), then every stored
 * attribute with its type. *fields is malloc'ed (free with
 * ogr_shapes_fields_free). 0, or 1 with o->why set. */
int ogr_shapes_fields(ogr_shapes *o, int with_fid, ogr_shapes_field **fields, size_t *count);
void ogr_shapes_fields_free(ogr_shapes_field *fields, size_t count);
/* Feature k's values into fields first .. first + count of ft. */
int ogr_shapes_fill(ogr_shapes *o, OGRFeatureH ft, int first, const ogr_shapes_field *fields,
                    size_t count, hpfc_id k, const hpfc_feature *feat);

/* A face's features: their count, their fids (space-separated) and keys
 * ('|'-separated; keys_field < 0: none) into the fields given. */
int ogr_shapes_face_features(ogr_shapes *o, OGRFeatureH ft, hpfc_id face, int count_field,
                             int fids_field, int keys_field);

#ifdef __cplusplus
}
#endif

#endif
