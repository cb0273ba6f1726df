/*
 * locate.h: point queries of hpfc-inspect (interfaces §4): the leaf, the
 * faces and the source features (FEAT section) at a point. Each returns an
 * exit status (VIEW_OK, VIEW_FAIL) with a one-line reason in `why`.
 */
#ifndef HPFC_INSPECT_LOCATE_H
#define HPFC_INSPECT_LOCATE_H

#include <stdio.h>

#include "hpfc.h"
#include "views.h"

/* --locate X,Y: one point in the file's user coordinates; JSON or text. */
int view_locate(const hpfc_file *f, const decimal xy[2], FILE *out, int json, char *why);
/* --locate-lonlat LON,LAT: one point in degrees, projected with the
 * projection the file's CRS section records. */
int view_locate_lonlat(const hpfc_file *f, const decimal lonlat[2], FILE *out, int json,
                       char *why);
/* --locate-batch POINTS: a table of points, one a line, blank lines and
 * '#' comments skipped. Its first line sets the separator (a tab, else a
 * comma, else a semicolon, else blanks; CSV quotes are understood) and
 * whether it is a header: one when the coordinate fields are not numbers.
 * The coordinate columns are lon_col and lat_col (a header name, any case,
 * or a 1-based number), else the columns named lon/lng/long/longitude or
 * x/easting and lat/latitude or y/northing, else the first two; degrees
 * when `lonlat` or when they are named as longitude and latitude. The id
 * column is id_col, else one named "id". Every other column is passed
 * through. One row a data line, in input order, each with its line number
 * and id; a line without a point is an error row ("error": why) and the
 * run goes on. The faces are numbered once for all points. */
enum { BATCH_JSONL = 0, BATCH_CSV = 1, BATCH_GEOJSON = 2 };
typedef struct batch_options {
    int lonlat;
    const char *lon_col, *lat_col, *id_col; /* NULL: guessed */
    int format;                             /* BATCH_JSONL, BATCH_CSV, BATCH_GEOJSON */
} batch_options;
int view_locate_batch(const hpfc_file *f, FILE *in, const char *in_name, const batch_options *o,
                      FILE *out, char *why);

#endif
