/*
 * locate.h: point queries of hpfc-inspect (contracts §4): the leaf, the
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
/* --locate-batch POINTS: one "x,y" (or "lon,lat" with lonlat) a line, blank
 * lines and '#' comments skipped; one JSON object a line on out, in input
 * order. The faces are numbered once for all points. */
int view_locate_batch(const hpfc_file *f, FILE *in, const char *in_name, int lonlat, FILE *out,
                      char *why);

#endif
