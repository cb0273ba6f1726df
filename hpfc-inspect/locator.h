/*
 * locator.h: hpfc-inspect's point locator, shared by the one-point queries
 * (locate.c) and the batch (locate_batch.c): the file's sections looked up
 * once, the answer for one point, and its JSON pieces.
 */
#ifndef HPFC_INSPECT_LOCATOR_H
#define HPFC_INSPECT_LOCATOR_H

#include <stdio.h>

#include "hpfc.h"
#include "jsonw.h"
#include "projection.h"
#include "views.h"

#define PATH_TEXT 1200


typedef struct locator {
    const hpfc_file *f;
    hpfc_file_info info;
    hpfc_faces *faces;       /* NULL when the file stores its labels */
    int labels;              /* the file has a LABL section */
    int exact;               /* and a GEOM section: hpfc_locate_point answers */
    int features;            /* the file has a FEAT section */
    hpfc_features_info fi;
    uint64_t *cand;          /* candidate faces of one leaf */
    size_t cap;
    hpfc_id *feat;           /* features of the candidates */
    size_t feat_cap;
    int edge_features;       /* LABL and EDGF: the leaf's edges name their features */
    hpfc_id *along;          /* features of the located leaf's edges */
    size_t along_cap;
    mapproj_plan *plan;      /* --lonlat: the file's projection */
} locator;

/* The answer for one point. */
typedef struct answer {
    int inside;
    hpfc_pixel px;
    char path[PATH_TEXT];
    int is_private;
    char *word;
    size_t nfaces, nfeat;
    size_t nalong;           /* features whose lines or rings cross the leaf */
    int exact;               /* faces is the exact answer (else candidates) */
    hpfc_point_location loc; /* exact: on_boundary, vertex or edge */
} answer;

/* Looks up the file's sections (numbering its faces when it stores no
 * labels); `lonlat`: open the CRS's projection too. VIEW_OK or VIEW_FAIL. */
int locator_open(const hpfc_file *f, int lonlat, locator *L, char *why);
void locator_close(locator *L);
/* The answer at a point in user coordinates: an hpfc status. */
int locate_decimal(locator *L, const decimal xy[2], answer *a);
/* (lon, lat) in degrees projected into the file's user coordinates. */
int project_lonlat(const locator *L, const decimal ll[2], decimal xy[2], char *why);

void json_decimal(jsonw *w, const char *key, const decimal *d);
void json_feature(jsonw *w, const locator *L, hpfc_id index);
void json_along(jsonw *w, const locator *L, const answer *a);
void json_exact(jsonw *w, const locator *L, const answer *a);

#endif
