/*
 * export_gis.h: hpfc-inspect --export and --export-faces (interfaces §5):
 * the file's features, or its faces, as exact (multi)polygons and
 * (multi)line strings through a GDAL vector driver, in the source SRS.
 */
#ifndef HPFC_INSPECT_EXPORT_GIS_H
#define HPFC_INSPECT_EXPORT_GIS_H

#include <stdio.h>

#include "hpfc.h"

/* A layer of geometries computed from the file (--dissolve, --mesh)
 * instead of its features or faces: `count` items, item k's geometry
 * (valid until the next call, in lattice points as the library answers)
 * and the value of the one string field. `item` returns an hpfc status. */
typedef struct gis_custom_layer {
    const char *name;     /* the layer's */
    int lines;            /* multi line strings, else multipolygons */
    const char *field;    /* the string field's name, NULL: none */
    size_t count;
    int (*item)(void *ctx, hpfc_shapes *shapes, size_t k, hpfc_polygons *geometry,
                const char **value, size_t *value_len);
    void *ctx;
} gis_custom_layer;

typedef struct gis_export_options {
    const char *file;     /* the .hpfc file ("-": standard input), named in messages */
    const hpfc_file *open; /* non-NULL: FILE already open (read once), used as is */
    const char *output;   /* OUT */
    const char *driver;   /* -f: a GDAL driver name, NULL: from OUT's extension */
    int faces;            /* --export-faces: the faces, not the features */
    int json;             /* the summary as one JSON object */
    const gis_custom_layer *custom; /* non-NULL: this layer, not features or faces */
} gis_export_options;

/* Writes OUT atomically (every file the driver makes goes first into a
 * temporary directory beside OUT, then is renamed into place: no partial
 * OUT on failure). Prints the summary to `report`; on failure one line
 * "hpfc-inspect: ...: why" on stderr. Returns the exit status (0 or 1). */
int export_gis(const gis_export_options *o, FILE *report);

#endif
