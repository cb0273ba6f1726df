/* The FEAT section (spec/hpfc-format.md §6.2), shared by the writer
 * (write.c) and the reader (file.c, features.c). */
#ifndef HPFC_FEAT_H
#define HPFC_FEAT_H

#include <stdbool.h>

#include "diag.h"
#include "feature_links.h"

/* Checks a feature table for the writer and computes the section's length
 * (HPFC_E_ARG on an inconsistent table, HPFC_E_LIMIT beyond 32-bit counts). */
int feat_section_length(const hpfc_feature_table *t, uint64_t *length, hpfc_diag *diag);
/* Writes the section (feat_section_length() bytes) at out. */
void feat_section_emit(const hpfc_feature_table *t, uint8_t *out);
/* The open-time check: the header's reserved field is zero, the lengths of
 * the parts add up to the section's length, the key field's name lies in
 * the strings. HPFC_E_SECTION otherwise. O(1): the tables are checked at
 * each access. */
int feat_section_check(const uint8_t *section, uint64_t length);
/* The layers of features [first, first + count) into layer[], one pass
 * over their records with no per-feature call (the GDAL driver types each
 * layer at open): HPFC_E_ARG past the features, HPFC_E_CORRUPT for a layer
 * past the layer table (S8), HPFC_E_NO_SECTION without FEAT. */
int features_layers(const hpfc_file *file, uint32_t first, uint32_t count, uint32_t *layer);
/* FEAT's face links (feature_links.h), for hpfc_face_feature* and the
 * shapes' index: HPFC_E_ARG when !out_ok, HPFC_E_NO_SECTION without FEAT. */
int features_face_links(const hpfc_file *file, bool out_ok, feature_links *links);

#endif
