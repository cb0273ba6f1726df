/*
 * export_gis.h: hpfc-inspect --export and --export-faces (interfaces §5):
 * the file's features, or its faces, as exact (multi)polygons and
 * (multi)line strings through a GDAL vector driver, in the source SRS.
 */
#ifndef HPFC_INSPECT_EXPORT_GIS_H
#define HPFC_INSPECT_EXPORT_GIS_H

#include <stdio.h>

typedef struct gis_export_options {
    const char *file;     /* the .hpfc file */
    const char *output;   /* OUT */
    const char *driver;   /* -f: a GDAL driver name, NULL: from OUT's extension */
    int faces;            /* --export-faces: the faces, not the features */
    int json;             /* the summary as one JSON object */
} gis_export_options;

/* Writes OUT atomically (every file the driver makes goes first into a
 * temporary directory beside OUT, then is renamed into place: no partial
 * OUT on failure). Prints the summary to `report`; on failure one line
 * "hpfc-inspect: ...: why" on stderr. Returns the exit status (0 or 1). */
int export_gis(const gis_export_options *o, FILE *report);

#endif
