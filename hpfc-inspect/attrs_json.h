/*
 * attrs_json.h: a feature's stored attributes (ATTR section) and an edge's
 * features (EDGF section) in hpfc-inspect's JSON answers (interfaces §4).
 */
#ifndef HPFC_INSPECT_ATTRS_JSON_H
#define HPFC_INSPECT_ATTRS_JSON_H

#include <stdint.h>

#include "hpfc.h"
#include "jsonw.h"

/* Writes "attributes": {name: value, ...} for feature `feature` when the
 * file has an ATTR section (nothing otherwise); integers as integers,
 * reals in their shortest exact form, strings as strings, null as null. A
 * damaged section ends the object early with "error": "corrupt". */
void json_feature_attributes(jsonw *w, const hpfc_file *f, hpfc_id feature);

/* Writes "edge_features": [feature indices] for edge `edge` when the file
 * has an EDGF section (for the crossings of a located leaf, once the file
 * gives their edge ids). */
void json_edge_features(jsonw *w, const hpfc_file *f, hpfc_id edge);

#endif
