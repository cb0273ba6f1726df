/*
 * gis_input.h: hpfc-pack's GIS input. Reads the line and polygon layers of
 * any vector dataset GDAL/OGR opens, projects geographic coordinates with
 * GeographicLib (projection.h), snaps them to a power-of-ten lattice
 * (lattice.h) and nodes the linework with GEOS (snap rounding), so that the
 * result is always a valid planar graph: every intersection is a vertex,
 * every shared border is stored once, zero-length pieces are gone.
 *
 * Without GDAL, GEOS and GeographicLib at build time, gis_read_graph() only
 * reports that GIS input is not built in.
 */
#ifndef HPFC_PACK_GIS_INPUT_H
#define HPFC_PACK_GIS_INPUT_H

#include <stddef.h>
#include <stdint.h>

#include "gis_attrs.h"
#include "gis_features.h"
#include "gis_range.h"
#include "hpfc.h"
#include "clock.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { GIS_VERTICES_ALL = 0, GIS_VERTICES_JUNCTIONS = 1 };
/* What to do with a polygon GEOS finds invalid (a self-intersecting ring,
 * a hole outside its shell, ...): refuse the input, or node its rings like
 * any other linework (the planar graph is then still exact; only the
 * polygon's own area is ill-defined). */
enum { GIS_INVALID_REJECT = 0, GIS_INVALID_NODE = 1 };
/* Geographic lines and rings with a segment spanning more than 180 degrees
 * of longitude: cut them at the antimeridian (dateline.h), or refuse them. */
enum { GIS_DATELINE_CUT = 0, GIS_DATELINE_REJECT = 1 };

/* A run of a layer's features, read by another process (gis_read_range):
 * positions begin .. end - 1 of layer `layer` (numbered as the reader
 * numbers the layers it reads), to the layer's end when end < 0. */
typedef struct gis_range_plan {
    uint32_t layer;
    int64_t begin, end;
} gis_range_plan;

/* A read in feature ranges (hpfc-pack --read-ranges): once the dataset is
 * open, its layers are cut into about `count` ranges by their feature
 * counts, and read(user, ranges, n, tag) has each range K read into
 * DIR/range-K by gis_read_range with the same options and this tag. It
 * returns 0 when every range was read; otherwise (a reader failed, or a
 * layer cannot be counted) the layers are read here, so that a failure is
 * worded as a whole read words it. */
typedef struct gis_ranges {
    unsigned count;
    const char *dir;
    int (*read)(void *user, const gis_range_plan *ranges, size_t n, uint64_t tag);
    void *user;
} gis_ranges;

typedef struct gis_options {
    const char *const *layers; /* layer names to read; all layers when n_layers == 0 */
    size_t n_layers;
    const char *projection;    /* "auto" (when NULL), "none", "tm", "lcc", "aea", "eqc" */
    int vertex_model;          /* GIS_VERTICES_ALL or GIS_VERTICES_JUNCTIONS */
    int progress;              /* draw a progress bar on stderr */
    int invalid_mode;          /* GIS_INVALID_REJECT or GIS_INVALID_NODE */
    const char *key_field;     /* attribute(s) kept as each feature's key, NULL for none;
                                  "a,b": the fields' values joined by commas */
    const char *fields;        /* attributes stored (ATTR section): NULL for none but
                                  source_fid, "all", or names separated by commas */
    int dateline;              /* GIS_DATELINE_CUT or GIS_DATELINE_REJECT */
    /* as ogr2ogr's -a_srs (for layers without an SRS) and -s_srs (for every
     * layer): any text OSRSetFromUserInput takes; NULL for none */
    const char *assign_srs, *source_srs;
    /* more than 1: GEOS checks the polygons on a second thread while GDAL
     * reads on (the same result) */
    unsigned threads;
    /* read in feature ranges by other processes; NULL: read here */
    const gis_ranges *ranges;
} gis_options;

typedef struct gis_info {
    char driver[64];           /* GDAL driver short name, e.g. "GeoJSON" */
    char projection[8];        /* projection used: "none", "tm", ... */
    char *crs;                 /* text for the CRS section (malloc'ed), NULL if unknown */
    int32_t unit_exp10;        /* lattice unit: 10^e of the coordinate unit */
    uint64_t layers, features;
    uint64_t skipped_empty;    /* features without geometry, or with an empty one */
    uint64_t skipped_points;   /* point geometries (not part of a planar map) */
    uint64_t invalid_noded;    /* invalid polygons noded (GIS_INVALID_NODE) */
    gis_features *polygons;    /* the features and their parts (rings and lines) */
    gis_attrs *attrs;          /* their attributes, one row per feature */
    uint64_t dateline_cut;     /* features cut at the antimeridian */
    uint64_t points_read;      /* shape points read (after any cut) */
    char noding[8];            /* GEOS noded "none" of the segments, "partial", "all" */
    uint64_t noded_segments;   /* segments GEOS noded (its input when partial, output when all) */
    /* the time of each stage of gis_read_graph() */
    stage_time read_t, project_t, node_t, graph_t;
    /* A layer without an SRS whose extent lies in the longitude/latitude
     * range was taken as WGS 84: the first such layer's name, "" if none. */
    char srs_assumed[64];
    /* opt->ranges: why the ranges other processes read were not taken and
     * the features were read here ("" when they were, or none were read) */
    char ranges_declined[200];
    /* the first invalid polygons noded, as "name" or "layer 'L' feature N",
     * comma-separated (for the report) */
    char repaired[200];
} gis_info;

/* Is GIS input built in? */
int gis_available(void);

/* Is `name` a --projection value? */
int gis_projection_valid(const char *name);

/* Reads `path` into a new graph (*out, freed by the caller) and fills
 * *info (release with gis_info_free()). Returns 0; 1 when the input cannot
 * be read or is invalid; 2 when GIS input is not built in. On failure `err`
 * holds one line without the input's name. */
int gis_read_graph(const char *path, const gis_options *opt, hpfc_graph **out,
                   gis_info *info, char *err, size_t err_len);

/* The same on a vector dataset the caller opened (a GDALDatasetH, which it
 * keeps and closes): the GDAL driver's writer (gdal/) packs the features
 * it was given, gathered in GDAL's Memory driver, exactly as hpfc-pack
 * packs a file that holds them. */
int gis_read_graph_dataset(void *dataset, const gis_options *opt, hpfc_graph **out,
                           gis_info *info, char *err, size_t err_len);
void gis_info_free(gis_info *info);

/* hpfc-pack --read-range: reads range `range` of `path` as gis_read_graph
 * reads it (the same options) and gives what it kept as a range file's
 * bytes (gis_range.h; malloc'ed) with `tag`. 0, 1 (the input cannot be
 * read or is invalid) or 2 (no GIS input built in), with err as
 * gis_read_graph's. */
int gis_read_range(const char *path, const gis_options *opt, const gis_range_plan *range,
                   uint64_t tag, uint8_t **bytes, size_t *len, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
